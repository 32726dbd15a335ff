// `scalar_field` artifacts: a value per vertex or per face, fetched as f32
// with its location and range from the Job, drawn on the mesh as stored (the
// server's vertex order: viewer/ply.ts) in a colour map, with a legend (what
// the values are and their unit, the range's min and max) whose map can be
// changed, and a range the Display panel can narrow.
import type * as THREE from 'three';
import { fetchArtifactF32 } from '../api/rest.ts';
import { jobMeshId, type ArtifactInfo, type Job } from '../api/types.ts';
import { describe, jobOf, type AppContext, meshOf } from '../controllers/context.ts';
import { artifactRow } from '../panels/artifact_row.ts';
import { byId, el } from '../panels/dom.ts';
import { fieldUnit, withUnit } from '../panels/format.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import { artifactKey, type AppState, type ArtifactRef } from '../state/app_state.ts';
import type { TestHooks } from '../test_hooks.ts';
import { defaultMapFor } from '../viewer/colormaps.ts';
import { Legend } from '../viewer/legend.ts';
import type { PlyMesh } from '../viewer/ply.ts';
import { buildScalarSurface, colourGeometry, finiteRange, type ScalarField } from '../viewer/scalar_field_renderer.ts';
import { type ArtifactKind, type KindDeps } from './kind.ts';
import { KindSlice } from './slice.ts';

/** A scalar_field artifact to draw: its job, its description in the Job, and the mesh it is on. */
export interface FieldSource {
  job: Job;
  artifact: ArtifactInfo;
  meshId: string;
}

interface DrawnField {
  jobId: string;
  artifact: string;
  meshId: string;
  data: ScalarField;
  object: THREE.Mesh;
  map: string;
  fullRange: [number, number];
}

/** A field's legend heading: the job's algorithm, the artifact and its values' unit ("curvature · mean_curvature (mesh units⁻¹)"). */
export function fieldLegendTitle(algorithm: string, artifact: string): string {
  return withUnit(algorithm ? `${algorithm} · ${artifact}` : artifact, fieldUnit(artifact));
}

/** The field drawn, as the job list marks it (and a comparison starts from). */
const shown = new KindSlice<ArtifactRef | null>('scalar_field', null);

/** The scalar field drawn on the mesh in `state`, or null. */
export function shownField(state: Readonly<AppState>): ArtifactRef | null {
  return shown.get(state);
}

export class ScalarFieldKind implements ArtifactKind {
  readonly kind = 'scalar_field';
  readonly storedFormat = 'f32';
  /** A job run here shows its field when it ends. */
  readonly autoShow = 0;
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: KindDeps;
  private readonly legend: Legend;
  /** The field drawn now. */
  private field: DrawnField | null = null;
  /** The field being prepared: a later one, or dropping, makes it stale. */
  private token = 0;
  /** The colour map chosen in the legend; null: the field's hint chooses. */
  private mapName: string | null = null;

  constructor(ctx: AppContext, deps: KindDeps) {
    this.ctx = ctx;
    this.deps = deps;
    this.legend = new Legend(byId('viewport'), (name) => this.setColorMap(name), 'legend');
  }

  load(): void {
    // Fetched when shown.
  }

  /** "Show" (on the mesh) and "Add to comparison" (beside the fields compared now, or the one shown). */
  row(job: Job, a: ArtifactInfo, view: JobsView, actions: JobsActions): HTMLElement {
    const [shown, compared] = this.rowState(job, a, view);
    const show = el('button', { type: 'button', class: shown ? 'button small show active' : 'button small show' }, shown ? 'Shown' : 'Show');
    show.addEventListener('click', () => actions.show(job.id, a.name, a.kind));
    const add = el(
      'button',
      { type: 'button', class: compared ? 'button small compare-add active' : 'button small compare-add', title: 'Show beside the fields compared now (or the one shown)' },
      compared ? 'Compared' : 'Add to comparison',
    );
    add.disabled = compared;
    add.addEventListener('click', () => this.deps.addToComparison(job.id, a.name));
    return artifactRow(job, a, this.storedFormat, [show, add]);
  }

  rowState(job: Job, a: ArtifactInfo, view: JobsView): [boolean, boolean] {
    // The single field is not marked while fields are compared.
    const field = view.compared.size ? null : shown.get(view.state);
    return [field?.jobId === job.id && field.artifact === a.name, view.compared.has(artifactKey(job.id, a.name))];
  }

  /** "Compare" on a job with two fields or more: all of them side by side. */
  jobControls(job: Job): HTMLElement | null {
    if ((job.artifacts ?? []).filter((a) => a.kind === this.kind).length < 2) return null;
    const compare = el('button', { type: 'button', class: 'button small compare', title: "Show this job's fields side by side" }, 'Compare');
    compare.addEventListener('click', () => this.deps.compareJob(job.id));
    return el('div', { class: 'job-actions' }, compare);
  }

  /**
   * The job's scalar_field artifact and its mesh, with that mesh selected
   * (the selection drops what was drawn on another mesh); null, with an error
   * shown, when the job, the artifact or the mesh is gone.
   */
  source(jobId: string, artifactName: string): FieldSource | null {
    const { store } = this.ctx;
    const { deps } = this;
    const job = jobOf(this.ctx, jobId);
    const artifact = job?.artifacts?.find((a) => a.name === artifactName);
    const meshId = jobMeshId(job);
    if (!job || !artifact || !meshId) return null;
    if (store.get().selectedId !== meshId) {
      if (!meshOf(this.ctx, meshId)) {
        this.ctx.error(`Cannot show ${artifactName} of ${job.algorithm}: its mesh no longer exists`);
        return null;
      }
      deps.meshes.select(meshId);
    }
    return { job, artifact, meshId };
  }

  /**
   * Fetches a scalar_field artifact: the values as f32, the range and location
   * from the Job, the mesh in the server's vertex order (viewer/ply.ts).
   */
  async fetch(jobId: string, artifact: ArtifactInfo, meshId: string): Promise<{ data: ScalarField; ply: PlyMesh }> {
    const { loader } = this.deps;
    const [values, ply] = await Promise.all([fetchArtifactF32(jobId, artifact.name), loader.ply(meshId), loader.showing]);
    const location = artifact.location ?? (values.length === ply.faces && values.length !== ply.vertices ? 'face' : 'vertex');
    let range: [number, number] = artifact.range && artifact.range.length === 2 && artifact.range.every(Number.isFinite) ? artifact.range : finiteRange(values);
    if (artifact.hint === 'symmetric') {
      const m = Math.max(Math.abs(range[0]), Math.abs(range[1]));
      range = [-m, m];
    }
    return { data: { name: artifact.name, location, values, range }, ply };
  }

  /** Draws a job's scalar_field artifact on its mesh, in place of a comparison (selecting that mesh first when another one is shown). */
  async show(jobId: string, artifactName: string): Promise<void> {
    const source = this.source(jobId, artifactName);
    if (!source) return;
    const { job, artifact, meshId } = source;
    const { store, viewer, hooks, display } = this.ctx;
    const { deps } = this;
    deps.leaveComparison();
    const token = ++this.token;
    try {
      const { data, ply } = await this.fetch(jobId, artifact, meshId);
      if (token !== this.token || store.get().selectedId !== meshId) return;
      const mapName = this.mapName ?? defaultMapFor(artifact.hint);
      const object = buildScalarSurface(ply, data, mapName);
      this.field = { jobId, artifact: artifactName, meshId, data, object, map: mapName, fullRange: data.range };
      hooks.lastField = null;
      this.ctx.textures.detach(); // the field's surface replaces the textured one
      viewer.replace(object, () => {
        if (viewer.object === object) hooks.lastField = this.report();
      });
      this.showLegend();
      display.setField({ range: data.range, full: data.range, values: data.values });
      shown.set(store, { jobId, artifact: artifactName });
    } catch (e) {
      if (token !== this.token) return;
      this.ctx.error(`Cannot show ${artifactName} of ${job.algorithm}: ${describe(e)}`);
    }
  }

  hide(jobId: string, artifact: string): void {
    if (this.field?.jobId === jobId && this.field.artifact === artifact) this.drop();
  }

  dispose(): void {
    if (this.field) this.drop();
  }

  /** Stops drawing the field (the next object shown is plain). */
  drop(): void {
    ++this.token;
    this.field = null;
    this.ctx.hooks.lastField = null;
    this.legend.hide();
    this.ctx.display.setField(null);
    shown.set(this.ctx.store, null);
  }

  /** The field drawn, as a view link keeps it. */
  drawn(): { jobId: string; artifact: string; meshId: string; map: string; range: [number, number] } | null {
    const f = this.field;
    return f && { jobId: f.jobId, artifact: f.artifact, meshId: f.meshId, map: f.map, range: f.data.range };
  }

  /** The colour map the next field is drawn in (a view link's), and the one drawn now, if any. */
  chooseMap(name: string): void {
    if (this.field && this.field.map !== name) this.setColorMap(name);
    else this.mapName = name;
  }

  /** The legend of the field drawn, if any (back from a comparison). */
  showLegend(): void {
    const f = this.field;
    if (!f) return;
    this.legend.show(fieldLegendTitle(jobOf(this.ctx, f.jobId)?.algorithm ?? '', f.artifact), f.data.range, f.map, f.data.values);
  }

  /** Hides the one view's legend (the panes have their own). */
  hideLegend(): void {
    this.legend.hide();
  }

  private setColorMap(name: string): void {
    this.mapName = name;
    const f = this.field;
    if (!f) return;
    f.map = name;
    colourGeometry(f.object.geometry, f.data, name);
    this.showLegend();
    this.ctx.viewer.redraw(() => {
      if (this.field === f) this.ctx.hooks.lastField = this.report();
    });
  }

  /** Recolours the field drawn over `range` (null: its full range), without fetching it again. */
  setRange(range: [number, number] | null): void {
    const f = this.field;
    if (!f) return;
    f.data.range = range ?? f.fullRange;
    colourGeometry(f.object.geometry, f.data, f.map);
    this.showLegend();
    this.ctx.display.setField({ range: f.data.range, full: f.fullRange, values: f.data.values });
    this.ctx.viewer.redraw(() => {
      if (this.field === f) this.ctx.hooks.lastField = this.report();
    });
  }

  private report(): TestHooks['lastField'] {
    const f = this.field!;
    return { jobId: f.jobId, artifact: f.artifact, meshId: f.meshId, location: f.data.location, count: f.data.values.length, range: f.data.range, map: f.map };
  }
}
