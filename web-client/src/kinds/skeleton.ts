// `skeleton` artifacts: curve skeletons drawn over their mesh (fetched as
// JSON), each in its own colour so that skeletons from several algorithms
// compare at a glance (the paper's Figure 5); a table of their metrics and of
// each one's distance to the first, side by side on demand; through the
// surface or hidden by it ("X-ray", on at first: a curve skeleton lies inside
// its mesh); and skeleton files made by other tools, attached to the mesh
// shown (the table's panel also has the button that loads a field's values
// for it).
import * as THREE from 'three';
import { fetchArtifactJson, submitJob } from '../api/rest.ts';
import { parseSkeleton, type SkeletonData } from '../api/skeleton.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { MAX_PANES } from '../controllers/compare.ts';
import { describe, jobOf, type AppContext } from '../controllers/context.ts';
import { artifactRow } from '../panels/artifact_row.ts';
import { byId } from '../panels/dom.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import { SkeletonsPanel } from '../panels/skeletons.ts';
import { artifactKey, selectedMesh, splitKey } from '../state/app_state.ts';
import { buildSkeleton, setSkeletonXray, SKELETON_COLORS } from '../viewer/skeleton_renderer.ts';
import { buildPlainSurface, SURFACE_COLOR } from '../viewer/surface_renderer.ts';
import { metricsOf } from './metrics.ts';
import { OverlayKind, type DrawnOverlay } from './overlay.ts';
import { type KindDeps } from './kind.ts';

interface DrawnSkeleton extends DrawnOverlay {
  data: SkeletonData;
  nodes: number;
  edges: number;
}

export class SkeletonKind extends OverlayKind<DrawnSkeleton> {
  readonly kind = 'skeleton';
  readonly storedFormat = 'obj';
  /** skeleton_distance jobs submitted for the comparison table, by `${first key}|${other key}` ('' while submitting). */
  private readonly distanceJobs = new Map<string, string>();
  /** Whether skeletons show through the surface (the panel's "X-ray"). */
  private xray = true;
  /** The skeletons in the panes of the last side by side (the viewer disposes of them with the panes; x-ray on them then changes nothing seen). */
  private paneSkeletons: THREE.Object3D[] = [];

  constructor(ctx: AppContext, deps: KindDeps) {
    super(ctx, deps, 'skeleton', SKELETON_COLORS);
    const panel = new SkeletonsPanel(
      byId('skeletons'),
      () => void this.compare(),
      (file) => void this.loadFile(file),
      // Explicitly a field: a .ply is a mesh to the upload control.
      (file) => void deps.importFile(file, 'scalar_field'),
      (on) => this.setXray(on),
    );
    ctx.store.subscribe(
      (s) => [this.colorsOf(s), s.jobs, metricsOf(s), selectedMesh(s) !== null],
      () => this.renderTable(panel),
      { now: true },
    );
  }

  /** "Show" (over its mesh, in a colour of its own; a second click hides it) and, while drawn, its colour. */
  row(job: Job, a: ArtifactInfo, view: JobsView, actions: JobsActions): HTMLElement {
    return artifactRow(job, a, this.storedFormat, this.toggle(job, a, view.state, actions, { class: 'show-skeleton', shown: 'Shown', hidden: 'Show' }));
  }

  rowState(job: Job, a: ArtifactInfo, view: JobsView): string {
    return this.colorIn(view.state, artifactKey(job.id, a.name)) ?? '';
  }

  protected async fetch(job: Job, artifact: ArtifactInfo): Promise<(color: string) => DrawnSkeleton> {
    const data = parseSkeleton(await fetchArtifactJson(job.id, artifact.name));
    return (color) => ({ object: buildSkeleton(data, color, this.xray), data, color, nodes: data.nodes.length / 3, edges: data.edges.length / 2 });
  }

  /**
   * "Load skeleton file…": the file is uploaded (POST /data) for the shown
   * mesh; the server reads it (a bad file is refused naming its line) and
   * answers a done import job, whose skeleton is drawn, measured and compared
   * as any job's. The kind is named so that a .txt file (the picker offers
   * them for CGAL's .polylines.txt) is read as a skeleton or refused with the
   * skeleton formats, never taken for a scalar field's values.
   */
  loadFile(file: File): Promise<void> {
    return this.deps.importFile(file, this.kind);
  }

  /** Shows every skeleton, over the mesh and in the panes, through the surface or hidden by it. */
  private setXray(on: boolean): void {
    this.xray = on;
    for (const o of [...[...this.drawn.values()].map((s) => s.object), ...this.paneSkeletons]) setSkeletonXray(o, on);
    this.ctx.viewer.redraw();
  }

  /** The skeletons drawn, side by side: one pane each, over the plain surface, through the one camera. */
  private compare(): Promise<void> {
    const list = [...this.drawn].slice(0, MAX_PANES);
    return this.deps.compareObjects(
      list.map(([key]) => splitKey(key)),
      (ply) => {
        this.paneSkeletons = list.map(([, s]) => buildSkeleton(s.data, s.color, this.xray));
        return list.map(([key, s], i) => {
          const group = new THREE.Group();
          group.add(buildPlainSurface(ply.positions, ply.indices, SURFACE_COLOR), this.paneSkeletons[i]!);
          const { jobId } = splitKey(key);
          return { key, title: jobOf(this.ctx, jobId)?.algorithm ?? jobId, object: group, color: s.color };
        });
      },
      'the skeletons',
    );
  }

  /** The comparison table of the skeletons drawn; asks the server for each one's distance to the first. */
  private renderTable(panel: SkeletonsPanel): void {
    const { store } = this.ctx;
    const { deps } = this;
    const keys = [...this.drawn.keys()];
    const input = (key: string) => {
      const { jobId, artifact } = splitKey(key);
      return { job: jobId, artifact };
    };
    const metricsOfJob = (jobId: string) => {
      const m = metricsOf(store.get()).get(`${jobId}/metrics`);
      return m && typeof m === 'object' ? (m as Record<string, unknown>) : undefined;
    };
    panel.render(
      keys.map((key, i) => {
        const { jobId: job } = splitKey(key);
        let distance: { hausdorff: number; mean: number } | undefined | null = null;
        if (i > 0) {
          const pair = `${keys[0]}|${key}`;
          const distanceJob = this.distanceJobs.get(pair);
          if (distanceJob === undefined) {
            this.distanceJobs.set(pair, '');
            submitJob('skeleton_distance', { skeleton: input(keys[0]!), reference: input(key) }, {})
              .then((j) => {
                this.distanceJobs.set(pair, j.id);
                deps.upsertJob(j);
              })
              .catch((e) => this.ctx.error(`Cannot measure the distance between skeletons: ${describe(e)}`));
          }
          const m = distanceJob ? metricsOfJob(distanceJob) : undefined;
          distance = m && typeof m.hausdorff === 'number' && typeof m.mean === 'number' ? { hausdorff: m.hausdorff, mean: m.mean } : undefined;
        }
        return {
          key,
          color: this.drawn.get(key)!.color,
          algorithm: jobOf(this.ctx, job)?.algorithm ?? job,
          metrics: metricsOfJob(job),
          distance,
        };
      }),
      selectedMesh(store.get()) !== null,
    );
  }

  protected report(): void {
    this.ctx.hooks.skeletons = [...this.drawn].map(([key, v]) => ({ key, color: v.color, nodes: v.nodes, edges: v.edges }));
  }
}
