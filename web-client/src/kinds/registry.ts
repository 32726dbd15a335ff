// The artifact kinds the viewer knows, by the server's kind string: what a
// job made is loaded, shown, hidden and disposed by its kind's module, which
// also builds its row in the job list. A new kind is a module in this folder
// and a line in `modules` below.
import type { ArtifactInfo, Job } from '../api/types.ts';
import type { AppContext } from '../controllers/context.ts';
import { AnimationKind } from './animation.ts';
import type { ArtifactKind, KindDeps } from './kind.ts';
import { MeshSurfaceKind } from './mesh_surface.ts';
import { MetricsKind } from './metrics.ts';
import { PointsKind } from './points.ts';
import { ScalarFieldKind } from './scalar_field.ts';
import { SkeletonKind } from './skeleton.ts';
import { TextKind } from './text.ts';
import { VectorFieldKind } from './vector_field.ts';
import { VoxelGridKind } from './voxel_grid.ts';

export class Kinds {
  /** Scalar fields: also compared side by side, and kept in view links. */
  readonly field: ScalarFieldKind;
  /** Voxel grids: their slice, in a lecture. */
  readonly voxels: VoxelGridKind;
  private readonly byKind: ReadonlyMap<string, ArtifactKind>;

  constructor(ctx: AppContext, deps: KindDeps) {
    // Made in this order because the legend goes over the view before the animation player.
    const skeleton = new SkeletonKind(ctx, deps);
    const voxels = (this.voxels = new VoxelGridKind(ctx));
    this.field = new ScalarFieldKind(ctx, deps);
    const modules: ArtifactKind[] = [
      new AnimationKind(ctx, deps, this.field),
      this.field,
      new MeshSurfaceKind(ctx, deps),
      skeleton,
      voxels,
      new MetricsKind(ctx),
      new TextKind(ctx),
      new VectorFieldKind(ctx, deps),
      new PointsKind(ctx, deps),
    ];
    this.byKind = new Map(modules.map((m) => [m.kind, m]));
  }

  /** The module of a kind; undefined for a kind this viewer does not know (the job list offers its downloads). */
  of(kind: string): ArtifactKind | undefined {
    return this.byKind.get(kind);
  }

  /** A done job: each artifact's module fetches what the job list shows of it. */
  load(job: Job): void {
    for (const a of job.artifacts ?? []) this.of(a.kind)?.load(job, a);
  }

  show(jobId: string, artifact: string, kind: string): Promise<void> {
    return this.of(kind)?.show(jobId, artifact) ?? Promise.resolve();
  }

  /** The skeletons and vector fields drawn and the grid whose slices are open, as `${jobId}/${artifact}` keys (view links' `show=`). */
  shownKeys(): string[] {
    return [...this.byKind.values()].flatMap((m) => m.shownKeys?.() ?? []);
  }

  /** Opens a job's artifact from elsewhere than its row (a graded run), as its kind does. */
  open(job: Job, artifact: ArtifactInfo): Promise<void> {
    const m = this.of(artifact.kind);
    if (!m) return Promise.resolve();
    return m.open ? m.open(job, artifact.name) : m.show(job.id, artifact.name);
  }

  /** What a job this page ran shows when it ends: its artifact of the kind of the lowest rank (kind.ts's autoShow), the first of them; null: none. */
  autoShown(job: Job): ArtifactInfo | null {
    let best: ArtifactInfo | null = null;
    let rank = Infinity;
    for (const a of job.artifacts ?? []) {
      const r = this.of(a.kind)?.autoShow;
      if (r !== undefined && r < rank) [best, rank] = [a, r];
    }
    return best;
  }

  hide(jobId: string, artifact: string, kind: string): void {
    this.of(kind)?.hide(jobId, artifact);
  }

  /** Another mesh is chosen, or the one shown is gone: every kind forgets what it drew on it (the animation first, as it replaced the mesh). */
  dispose(): void {
    for (const m of this.byKind.values()) m.dispose();
  }
}
