// `voxel_grid` artifacts: 2D slices in the slice panel (fetched over the
// WebSocket), the slice's plane in the view (optionally cutting the mesh),
// and the voxels above a threshold drawn in 3D.
import { fetchArtifactBytes } from '../api/rest.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import type { AppContext } from '../controllers/context.ts';
import { artifactRow, runOnButton } from '../panels/artifact_row.ts';
import { byId, el } from '../panels/dom.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import { artifactKey } from '../state/app_state.ts';
import { VoxelSlicePanel, type SliceView } from '../panels/voxel_slices.ts';
import { buildSlicePlane, sliceClipPlane } from '../viewer/slice_plane.ts';
import type { ArtifactKind } from './kind.ts';

export class VoxelGridKind implements ArtifactKind {
  readonly kind = 'voxel_grid';
  readonly storedFormat = 'nrrd';
  private readonly panel: VoxelSlicePanel;

  constructor(ctx: AppContext) {
    const { viewer } = ctx;
    this.panel = new VoxelSlicePanel(
      byId('voxel-slices'),
      ctx.socket,
      (shown) => {
        viewer.setOverlay('voxel-slice', shown ? buildSlicePlane(shown.canvas, shown.slice) : null);
        viewer.setClipPlane(shown?.cut ? sliceClipPlane(shown.slice) : null);
      },
      (jobId, artifact) => fetchArtifactBytes(jobId, artifact, 'nrrd'),
      (shown) => {
        viewer.setOverlay('voxels', shown?.object ?? null);
        ctx.hooks.lastVoxels = shown ? { count: shown.count, kept: shown.kept, threshold: shown.threshold } : null;
      },
    );
  }

  load(): void {
    // Sliced on demand.
  }

  /** "Slices" (the slice panel) and "Run on this". */
  row(job: Job, a: ArtifactInfo, view: JobsView, actions: JobsActions): HTMLElement {
    const slices = el('button', { type: 'button', class: 'button small slices' }, 'Slices');
    slices.addEventListener('click', () => actions.show(job.id, a.name, a.kind));
    return artifactRow(job, a, this.storedFormat, [slices, runOnButton(job, a, view, actions)]);
  }

  rowState(job: Job, a: ArtifactInfo, view: JobsView): boolean {
    return view.target === artifactKey(job.id, a.name);
  }

  async show(jobId: string, artifact: string): Promise<void> {
    this.panel.open(jobId, artifact);
  }

  hide(): void {
    this.panel.close();
  }

  /** The slice shown and how (a lecture's part `slice`), or null. */
  sliceView(): SliceView | null {
    return this.panel.view();
  }

  setSliceView(view: SliceView | null): void {
    this.panel.setView(view);
  }

  shownKeys(): string[] {
    const t = this.panel.opened();
    return t ? [artifactKey(t.jobId, t.artifact)] : [];
  }

  dispose(): void {
    // The slices are of a job's grid, not of the mesh shown: they stay open.
  }
}
