// `points` artifacts: point clouds a job made (sampled from its mesh, or
// from a cloud, with normals estimated), fetched as a Draco point cloud
// (`drc`), decoded in the viewer's Draco worker and drawn over their mesh as
// uploaded clouds are (viewer/points_renderer.ts), each in a colour of its
// own where the cloud has none, in the Display panel's point size. Its row:
// Show / Hide, while drawn its colour, a download link per format the server
// lists (drc, ply, xyz), and "Run on this" (a cloud is an algorithm's input).
// The clouds drawn are kept in view links (`show=`).
import type * as THREE from 'three';
import { fetchArtifactBytes } from '../api/rest.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import type { AppContext } from '../controllers/context.ts';
import { artifactRow, runOnButton } from '../panels/artifact_row.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import { artifactKey } from '../state/app_state.ts';
import { buildPoints, pointsReport, POINTS_PALETTE, setPointsLook } from '../viewer/points_renderer.ts';
import { type KindDeps } from './kind.ts';
import { OverlayKind, type DrawnOverlay } from './overlay.ts';

interface DrawnPoints extends DrawnOverlay {
  object: THREE.Points;
}

export class PointsKind extends OverlayKind<DrawnPoints> {
  readonly kind = 'points';
  readonly storedFormat = 'drc';
  /** A job run here whose result is a cloud (and no field) shows it when it ends. */
  readonly autoShow = 2;

  constructor(ctx: AppContext, deps: KindDeps) {
    super(ctx, deps, 'points', POINTS_PALETTE);
    // The Display panel's point size and vertex colours apply to the clouds drawn too.
    ctx.store.subscribe(
      (s) => [s.display.settings.pointSize, s.display.settings.vertexColors],
      () => {
        for (const d of this.drawn.values()) setPointsLook(d.object, this.look(d.color));
        ctx.viewer.redraw(() => this.report());
      },
    );
  }

  /** "Show" (over its mesh, in a colour of its own), "Hide" while drawn, its colour; "Run on this". */
  row(job: Job, a: ArtifactInfo, view: JobsView, actions: JobsActions): HTMLElement {
    const [toggle, swatch] = this.toggle(job, a, view.state, actions, {
      class: 'show-points',
      shown: 'Hide',
      hidden: 'Show',
      titles: { shown: 'Stop drawing the points', hidden: 'Draw the points over the mesh' },
    });
    return artifactRow(job, a, this.storedFormat, [toggle, swatch, runOnButton(job, a, view, actions)]);
  }

  rowState(job: Job, a: ArtifactInfo, view: JobsView): [string, boolean] {
    const key = artifactKey(job.id, a.name);
    return [this.colorIn(view.state, key) ?? '', view.target === key];
  }

  protected async fetch(job: Job, artifact: ArtifactInfo): Promise<(color: string) => DrawnPoints> {
    const bytes = await fetchArtifactBytes(job.id, artifact.name, 'drc');
    const cloud = await this.deps.loader.decode(new Uint8Array(bytes));
    if (!cloud.points) throw new Error('the server sent a mesh, not a point cloud');
    return (color) => {
      const object = buildPoints(cloud, this.look(color), `points:${artifact.name}`);
      this.followShown(object);
      return { object, color };
    };
  }

  /** How a cloud is drawn: the Display panel's size, in `color` where it has no colours of its own. */
  private look(color: string) {
    const { pointSize, vertexColors } = this.ctx.store.get().display.settings;
    return { pointSize, vertexColors, color };
  }

  protected report(): void {
    this.ctx.display.setPointsOver(this.drawn.size > 0);
    this.ctx.hooks.points = [...this.drawn].map(([key, d]) => ({ key, color: d.color, ...pointsReport(d.object) }));
  }
}
