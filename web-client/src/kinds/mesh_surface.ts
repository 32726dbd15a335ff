// `mesh` artifacts: fetched as binary PLY and drawn plain light blue beside
// the job's input mesh ("Add to view"); gone when another mesh is chosen.
import type * as THREE from 'three';
import { fetchArtifactBytes } from '../api/rest.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { describe, jobOf, type AppContext } from '../controllers/context.ts';
import { artifactRow, runOnButton } from '../panels/artifact_row.ts';
import { el } from '../panels/dom.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import { artifactKey } from '../state/app_state.ts';
import { parsePly } from '../viewer/ply.ts';
import { buildPlainSurface } from '../viewer/surface_renderer.ts';
import type { ArtifactKind } from './kind.ts';

export class MeshSurfaceKind implements ArtifactKind {
  readonly kind = 'mesh';
  readonly storedFormat = 'ply';
  private readonly ctx: AppContext;
  /** The surfaces in the view, by `${jobId}/${name}`. */
  private readonly drawn = new Map<string, THREE.Object3D>();

  constructor(ctx: AppContext) {
    this.ctx = ctx;
  }

  load(): void {
    // Fetched when added to the view.
  }

  /** "Add to view" (beside its input mesh) and "Run on this". */
  row(job: Job, a: ArtifactInfo, view: JobsView, actions: JobsActions): HTMLElement {
    const added = view.added.has(artifactKey(job.id, a.name));
    const add = el('button', { type: 'button', class: added ? 'button small add active' : 'button small add' }, added ? 'Added' : 'Add to view');
    add.disabled = added;
    add.addEventListener('click', () => actions.show(job.id, a.name, a.kind));
    return artifactRow(job, a, this.storedFormat, [add, runOnButton(job, a, view, actions)]);
  }

  rowState(job: Job, a: ArtifactInfo, view: JobsView): [boolean, boolean] {
    const key = artifactKey(job.id, a.name);
    return [view.added.has(key), view.target === key];
  }

  /** Adds a job's mesh artifact (fetched as binary PLY) to the view, beside its input mesh. */
  async show(jobId: string, artifactName: string): Promise<void> {
    const { app, store, viewer, hooks } = this.ctx;
    const job = jobOf(this.ctx, jobId);
    if (!job) return;
    app.meshes.selectMeshOf(job);
    const selected = store.get().selectedId;
    try {
      const [bytes] = await Promise.all([fetchArtifactBytes(jobId, artifactName, 'ply'), app.loader.showing]);
      if (store.get().selectedId !== selected) return;
      const ply = parsePly(bytes);
      const object = buildPlainSurface(ply.positions, ply.indices);
      const key = artifactKey(jobId, artifactName);
      viewer.addExtra(object, () => {
        hooks.lastExtra = { jobId, artifact: artifactName, vertices: ply.vertices, faces: ply.faces };
      });
      this.drawn.set(key, object);
      this.publish();
    } catch (e) {
      this.ctx.error(`Cannot add ${artifactName} of ${job.algorithm}: ${describe(e)}`);
    }
  }

  hide(jobId: string, artifact: string): void {
    const key = artifactKey(jobId, artifact);
    const object = this.drawn.get(key);
    if (!object) return;
    this.ctx.viewer.removeExtra(object);
    this.drawn.delete(key);
    this.publish();
  }

  dispose(): void {
    this.ctx.hooks.lastExtra = null;
    if (!this.drawn.size) return;
    for (const object of this.drawn.values()) this.ctx.viewer.removeExtra(object);
    this.drawn.clear();
    this.publish();
  }

  private publish(): void {
    this.ctx.store.update({ added: new Set(this.drawn.keys()) });
  }
}
