// What the kinds drawn over their mesh share (skeletons, vector fields,
// points): each artifact drawn is fetched, built in a colour of its own from
// the kind's palette and added over the mesh it belongs to (that mesh
// selected first; vectors and points follow it where it is turned or
// moved); several at once, by `${jobId}/${name}` in the order drawn; hidden one by one
// (its row's toggle) or all when another mesh is shown; kept in view links
// (`show=`). The colours drawn are the kind's part of the state (its row
// shows them); what each drawn one reports goes to the test hooks.
import type * as THREE from 'three';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { describe, jobOf, type AppContext } from '../controllers/context.ts';
import { el } from '../panels/dom.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import { artifactKey, type AppState } from '../state/app_state.ts';
import { type ArtifactKind, type KindDeps } from './kind.ts';
import { KindSlice } from './slice.ts';

/** An artifact drawn over its mesh: its object in the view and its colour. */
export interface DrawnOverlay {
  object: THREE.Object3D;
  color: string;
}

/** The row's toggle: its class, its text while drawn and while not, and its titles (optional). */
export interface OverlayToggle {
  class: string;
  shown: string;
  hidden: string;
  titles?: { shown: string; hidden: string };
}

export abstract class OverlayKind<D extends DrawnOverlay> implements ArtifactKind {
  abstract readonly kind: string;
  abstract readonly storedFormat: string;
  protected readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  protected readonly deps: KindDeps;
  /** Drawn over the mesh, by `${jobId}/${name}`, in the order shown. */
  protected readonly drawn = new Map<string, D>();
  /** The colours drawn, by `${jobId}/${name}`: what the rows show. */
  private readonly colors: KindSlice<ReadonlyMap<string, string>>;
  /** Counts disposals: what was fetched for a mesh since gone is not drawn. */
  private token = 0;

  constructor(
    ctx: AppContext,
    deps: KindDeps,
    kind: string,
    private readonly palette: readonly string[],
  ) {
    this.ctx = ctx;
    this.deps = deps;
    this.colors = new KindSlice<ReadonlyMap<string, string>>(kind, new Map());
  }

  /**
   * Fetches the artifact (its mesh shown by then) and answers what builds it
   * in a colour; throws (or rejects) with what went wrong, which is shown.
   */
  protected abstract fetch(job: Job, artifact: ArtifactInfo): Promise<(color: string) => D>;
  /** Tells the test hooks what is drawn now (nothing, after a dispose). */
  protected abstract report(): void;
  abstract row(job: Job, artifact: ArtifactInfo, view: JobsView, actions: JobsActions): HTMLElement;
  abstract rowState(job: Job, artifact: ArtifactInfo, view: JobsView): unknown;

  /** Whether the job's artifact can be shown now; false says why itself (an error shown) or stays silent. */
  protected canShow(_job: Job, _artifact: ArtifactInfo): boolean {
    return true;
  }

  load(): void {
    // Fetched when shown.
  }

  /**
   * Draws `object` where the shown mesh is: what it draws is in the mesh's
   * own coordinates (a vector per vertex, points it was sampled into), and
   * the mesh may be turned (its up axis) or moved (the Scene panel). Before
   * each frame (and each measure of its box) it takes the shown object's
   * world matrix (the extras' group is not moved).
   */
  protected followShown(object: THREE.Object3D): void {
    const { viewer } = this.ctx;
    const update = object.updateMatrixWorld.bind(object);
    object.matrixAutoUpdate = false;
    object.updateMatrixWorld = () => {
      const shown = viewer.object;
      if (shown) {
        shown.updateWorldMatrix(true, false);
        object.matrix.copy(shown.matrixWorld);
      }
      update(true); // its matrix was set here, which three does not see
    };
  }

  /** The colours drawn as `state` has them, by `${jobId}/${name}`. */
  protected colorsOf(state: Readonly<AppState>): ReadonlyMap<string, string> {
    return this.colors.get(state);
  }

  /** The colour a drawn artifact has in `state`, or undefined when it is not drawn. */
  protected colorIn(state: Readonly<AppState>, key: string): string | undefined {
    return this.colorsOf(state).get(key);
  }

  /** The row's toggle (Show; while drawn, what hides it) and, while drawn, a swatch of its colour. */
  protected toggle(job: Job, a: ArtifactInfo, state: Readonly<AppState>, actions: JobsActions, t: OverlayToggle): [HTMLElement, HTMLElement | null] {
    const color = this.colorIn(state, artifactKey(job.id, a.name));
    const attrs: Record<string, string> = { type: 'button', class: color ? `button small ${t.class} active` : `button small ${t.class}` };
    if (t.titles) attrs.title = color ? t.titles.shown : t.titles.hidden;
    const button = el('button', attrs, color ? t.shown : t.hidden);
    button.addEventListener('click', () => (color ? actions.hide(job.id, a.name, a.kind) : actions.show(job.id, a.name, a.kind)));
    const swatch = color ? el('span', { class: 'swatch', style: `background:${color}`, title: color }) : null;
    return [button, swatch];
  }

  /** Draws a job's artifact over its mesh (selecting that mesh first when another one is shown), in the first colour of the palette not drawn. */
  async show(jobId: string, artifactName: string): Promise<void> {
    const { store, viewer } = this.ctx;
    const { deps } = this;
    const key = artifactKey(jobId, artifactName);
    if (this.drawn.has(key)) return;
    const job = jobOf(this.ctx, jobId);
    const artifact = job?.artifacts?.find((a) => a.name === artifactName);
    if (!job || !artifact || !this.canShow(job, artifact)) return;
    deps.meshes.selectMeshOf(job);
    const selected = store.get().selectedId;
    const token = this.token;
    try {
      const [build] = await Promise.all([this.fetch(job, artifact), deps.loader.showing]);
      if (token !== this.token || store.get().selectedId !== selected || this.drawn.has(key)) return;
      const used = new Set([...this.drawn.values()].map((d) => d.color));
      const color = this.palette.find((c) => !used.has(c)) ?? this.palette[this.drawn.size % this.palette.length]!;
      const drawn = build(color);
      this.drawn.set(key, drawn);
      viewer.addExtra(drawn.object, () => this.report());
      this.publish();
    } catch (e) {
      if (token !== this.token) return;
      this.ctx.error(`Cannot show ${artifactName} of ${job.algorithm}: ${describe(e)}`);
    }
  }

  shownKeys(): string[] {
    return [...this.drawn.keys()];
  }

  hide(jobId: string, artifact: string): void {
    const key = artifactKey(jobId, artifact);
    const drawn = this.drawn.get(key);
    if (!drawn) return;
    this.ctx.viewer.removeExtra(drawn.object); // disposes of its geometry and material
    this.drawn.delete(key);
    this.publish();
    this.ctx.viewer.redraw(() => this.report());
  }

  dispose(): void {
    ++this.token;
    const had = this.drawn.size > 0;
    for (const d of this.drawn.values()) this.ctx.viewer.removeExtra(d.object);
    this.drawn.clear();
    this.report();
    if (had) this.publish();
  }

  private publish(): void {
    this.colors.set(this.ctx.store, new Map([...this.drawn].map(([k, d]) => [k, d.color])));
  }
}
