// `mesh` artifacts: a job's output mesh, drawn as an object of the scene of its
// own beside its source ("Add to view": controllers/scene.ts draws it from its
// PLY), or the input of the next job ("Run on this"). The job list marks the
// results in the scene "Added".
import type { ArtifactInfo, Job } from '../api/types.ts';
import type { AppContext } from '../controllers/context.ts';
import { resultOf } from '../controllers/scene.ts';
import { artifactRow, runOnButton } from '../panels/artifact_row.ts';
import { el } from '../panels/dom.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import { artifactKey } from '../state/app_state.ts';
import { type ArtifactKind, type KindDeps } from './kind.ts';
import { KindSlice } from './slice.ts';

export class MeshSurfaceKind implements ArtifactKind {
  readonly kind = 'mesh';
  readonly storedFormat = 'ply';
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: KindDeps;
  /** The results in the scene, as `${jobId}/${name}`: the rows' "Added". */
  private readonly added = new KindSlice<ReadonlySet<string>>('mesh', new Set());

  constructor(ctx: AppContext, deps: KindDeps) {
    this.ctx = ctx;
    this.deps = deps;
    ctx.store.subscribe(
      (s) => s.scene.map((e) => e.mesh).join(' '),
      () => {
        const added = ctx.store.get().scene.flatMap((e) => {
          const r = resultOf(e.mesh);
          return r ? [artifactKey(r.jobId, r.artifact)] : [];
        });
        this.added.set(ctx.store, new Set(added));
      },
    );
  }

  load(): void {
    // Fetched when added to the view.
  }

  /** "Add to view" (beside its input mesh) and "Run on this". */
  row(job: Job, a: ArtifactInfo, view: JobsView, actions: JobsActions): HTMLElement {
    const added = this.added.get(view.state).has(artifactKey(job.id, a.name));
    const add = el('button', { type: 'button', class: added ? 'button small add active' : 'button small add' }, added ? 'Added' : 'Add to view');
    add.disabled = added;
    add.addEventListener('click', () => actions.show(job.id, a.name, a.kind));
    return artifactRow(job, a, this.storedFormat, [add, runOnButton(job, a, view, actions)]);
  }

  rowState(job: Job, a: ArtifactInfo, view: JobsView): [boolean, boolean] {
    const key = artifactKey(job.id, a.name);
    return [this.added.get(view.state).has(key), view.target === key];
  }

  /** Adds a job's output mesh to the scene, beside its source. */
  show(jobId: string, artifact: string): Promise<void> {
    return this.deps.scene.addResult(jobId, artifact);
  }

  /** Opened from elsewhere (a graded run): its job's mesh shown first. */
  open(job: Job, artifact: string): Promise<void> {
    this.deps.meshes.selectMeshOf(job);
    return this.show(job.id, artifact);
  }

  hide(jobId: string, artifact: string): void {
    this.deps.scene.removeResult(jobId, artifact);
  }

  dispose(): void {
    // The scene takes its objects away itself.
    this.ctx.hooks.lastExtra = null;
  }
}
