// Side by side: the fields of one mesh (each in a pane with its colour map
// and legend), the skeletons drawn over it, or the scene's objects; all
// through the one camera (viewer/comparison.ts), framed together or, with
// "Fit each pane", each pane on its own object. "Leave comparison" goes back
// to one view, and offers the comparison back for a few seconds.
import type * as THREE from 'three';
import { jobMeshId } from '../api/types.ts';
import { byId } from '../panels/dom.ts';
import type { ArtifactRef } from '../state/app_state.ts';
import { ComparisonView } from '../viewer/comparison.ts';
import type { PlyMesh } from '../viewer/ply.ts';
import { describe, jobOf, type AppContext } from './context.ts';
import { fieldLegendTitle, shownField, type FieldSource } from '../kinds/scalar_field.ts';
import type { Kinds } from '../kinds/registry.ts';
import type { MeshLoader } from './mesh_loader.ts';
import type { SceneController } from './scene.ts';

/** What a comparison uses: the scalar fields' kind, the mesh in its stored order, the scene side by side again. */
export interface CompareDeps {
  kinds: Pick<Kinds, 'field'>;
  loader: Pick<MeshLoader, 'ply'>;
  scene: Pick<SceneController, 'sideBySide'>;
}

/** A pane's prepared object (a skeleton over its mesh, a scene object). */
export interface PaneObject {
  key: string;
  title: string;
  object: THREE.Object3D;
  color?: string;
}

/** At most this many panes. */
export const MAX_PANES = 4;

export class CompareController {
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: CompareDeps;
  private readonly view: ComparisonView;
  private readonly leaveButton: HTMLButtonElement;
  /** The comparison being prepared: a later one, or leaving, makes it stale. */
  private token = 0;
  /** Shows the comparison now shown (or last shown) again: what "Undo" after leaving it does. */
  private again: (() => void) | null = null;

  constructor(ctx: AppContext, deps: CompareDeps) {
    this.ctx = ctx;
    this.deps = deps;
    this.view = new ComparisonView(ctx.viewer, byId('viewport'), (panes) => {
      const { selectedId: meshId, compared } = ctx.store.get();
      ctx.hooks.lastCompare = meshId && compared.length ? { meshId, panes: panes.map((p, i) => ({ ...compared[i]!, map: p.map, range: p.range })) } : null;
    });
    this.leaveButton = byId<HTMLButtonElement>('leave-compare');
    this.leaveButton.addEventListener('click', () => this.leaveWithUndo());
  }

  /** "Compare": every scalar field of the job side by side (at most MAX_PANES). */
  compareJob(jobId: string): void {
    const fields = jobOf(this.ctx, jobId)?.artifacts?.filter((a) => a.kind === 'scalar_field') ?? [];
    if (fields.length > MAX_PANES) this.ctx.notice(`Comparing the first ${MAX_PANES} of ${fields.length} fields.`);
    void this.compareFields(fields.slice(0, MAX_PANES).map((a) => ({ jobId, artifact: a.name })));
  }

  /** "Add to comparison": the field joins the fields compared now (or the one shown), on the same mesh. */
  addToComparison(jobId: string, artifact: string): void {
    const { compared } = this.ctx.store.get();
    const field = shownField(this.ctx.store.get());
    const now = compared.length ? compared : field ? [field] : [];
    if (now.some((c) => c.jobId === jobId && c.artifact === artifact)) return;
    const meshId = jobMeshId(jobOf(this.ctx, jobId));
    const other = now.find((c) => jobMeshId(jobOf(this.ctx, c.jobId)) !== meshId);
    if (other) return this.ctx.error(`Cannot compare ${artifact}: it is on another mesh than ${other.artifact}; compare fields of one mesh.`);
    if (now.length >= MAX_PANES) return this.ctx.error(`At most ${MAX_PANES} fields side by side: leave the comparison first.`);
    void this.compareFields([...now, { jobId, artifact }]);
  }

  /** Shows the fields (all on one mesh) side by side in synchronized panes, each with its legend (a view link's). */
  async compareFields(list: ArtifactRef[]): Promise<void> {
    const field = this.deps.kinds.field;
    const sources: FieldSource[] = [];
    for (const c of list) {
      const source = field.source(c.jobId, c.artifact);
      if (!source) return;
      sources.push(source);
    }
    const meshId = sources[0]?.meshId;
    if (!meshId || sources.some((s) => s.meshId !== meshId)) return;
    const token = ++this.token;
    try {
      const loaded = await Promise.all(sources.map((s) => field.fetch(s.job.id, s.artifact, meshId)));
      if (token !== this.token || this.ctx.store.get().selectedId !== meshId) return;
      this.take(list);
      this.again = () => void this.compareFields(list);
      this.view.show(
        loaded[0]!.ply,
        loaded.map(({ data }, i) => ({
          key: `${list[i]!.jobId}/${list[i]!.artifact}`,
          title: fieldLegendTitle(sources[i]!.job.algorithm, data.name),
          data,
          hint: sources[i]!.artifact.hint,
        })),
      );
      this.leaveButton.hidden = false;
    } catch (e) {
      if (token !== this.token) return;
      this.ctx.error(`Cannot compare the fields: ${describe(e)}`);
    }
  }

  /**
   * Artifacts of the selected mesh drawn as objects side by side (skeletons,
   * each over the plain surface): `build` makes the panes' objects from the
   * mesh as stored; `what` words a failure.
   */
  async compareObjects(list: ArtifactRef[], build: (ply: PlyMesh) => PaneObject[], what: string): Promise<void> {
    const { store } = this.ctx;
    const { deps } = this;
    const meshId = store.get().selectedId;
    if (list.length < 2 || !meshId) return;
    const token = ++this.token;
    try {
      const ply = await deps.loader.ply(meshId);
      if (token !== this.token || store.get().selectedId !== meshId) return;
      this.take(list);
      this.again = () => void this.compareObjects(list, build, what);
      this.view.showObjects(build(ply));
      this.leaveButton.hidden = false;
    } catch (e) {
      if (token !== this.token) return;
      this.ctx.error(`Cannot show ${what} side by side: ${describe(e)}`);
    }
  }

  /** The scene's objects in the panes (the scene keeps them: they are not disposed when the panes go). */
  showScene(items: PaneObject[]): void {
    ++this.token;
    this.ctx.store.update({ compared: [] });
    this.ctx.hooks.lastCompare = null;
    this.deps.kinds.field.hideLegend();
    this.view.showObjects(items, false);
    this.leaveButton.hidden = false;
    this.again = () => this.deps.scene.sideBySide();
  }

  /**
   * The user's way back to one view ("Leave comparison", the scene's side
   * by side turned off): leaves, and offers the comparison back for a few
   * seconds, on the same mesh and while no other comparison has begun.
   */
  leaveWithUndo(): void {
    const { store } = this.ctx;
    const { compared, scenePanes, selectedId } = store.get();
    const again = this.again;
    if (!compared.length && !scenePanes) return;
    this.leave();
    if (!again) return;
    this.ctx.undo.offer('Left the comparison.', {
      undo: () => {
        const now = store.get();
        if (now.selectedId === selectedId && !now.compared.length && !now.scenePanes) again();
      },
    });
  }

  /** Back to one view: the field drawn before the comparison (if any) with its legend. */
  leave(): void {
    ++this.token;
    const { compared, scenePanes } = this.ctx.store.get();
    if (!compared.length && !scenePanes) return;
    this.ctx.store.update({ compared: [], scenePanes: false });
    this.ctx.hooks.lastCompare = null;
    this.view.clear();
    this.leaveButton.hidden = true;
    this.deps.kinds.field.showLegend();
  }

  /** The panes go to `list` (the scene's side by side ends). */
  private take(list: ArtifactRef[]): void {
    this.ctx.store.update({ compared: list, scenePanes: false });
    this.ctx.hooks.lastCompare = null;
    this.deps.kinds.field.hideLegend();
  }
}
