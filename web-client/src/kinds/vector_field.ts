// `vector_field` artifacts: a 3D vector per vertex or per face (principal
// directions, gradients), fetched as f32 with its location and hint from the
// Job, drawn over its mesh as line segments (viewer/vector_field_renderer.ts)
// from the mesh in the server's vertex and face order (the streamed mesh
// mapped through its stored order: controllers/mesh_loader.ts), each field in
// its own colour so that two drawn together (a vertex's two principal
// directions) tell apart. Its row: Show / Hide, while drawn a slider for the
// segments' length and a swatch, and once fetched how many vectors have no
// value. The fields drawn are kept in view links (`show=`).
import { fetchArtifactF32 } from '../api/rest.ts';
import { jobMeshId, type ArtifactInfo, type Job } from '../api/types.ts';
import { type AppContext, meshOf } from '../controllers/context.ts';
import { artifactRow } from '../panels/artifact_row.ts';
import { el } from '../panels/dom.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import { artifactKey } from '../state/app_state.ts';
import { longest, VECTOR_COLORS, VectorGlyphs, type VectorField } from '../viewer/vector_field_renderer.ts';
import { OverlayKind, type DrawnOverlay } from './overlay.ts';
import './vector_field.css';
import { type KindDeps } from './kind.ts';

interface DrawnVectors extends DrawnOverlay {
  glyphs: VectorGlyphs;
  field: VectorField;
}

/** The length slider's range: log2 of the scale, 1/4 to 4 times the default. */
const SCALE_LOG2 = { min: -2, max: 2, step: 0.25 };

export class VectorFieldKind extends OverlayKind<DrawnVectors> {
  readonly kind = 'vector_field';
  readonly storedFormat = 'f32';
  /** A job run here that made no scalar field shows its vector field when it ends. */
  readonly autoShow = 1;
  /** Vectors without a value, by `${jobId}/${name}`, once a field has been fetched (what its row says, drawn or not). */
  private readonly missing = new Map<string, { missing: number; count: number; location: string }>();
  /** The length chosen for a field (a multiple of the default), by `${jobId}/${name}`. */
  private readonly scales = new Map<string, number>();

  constructor(ctx: AppContext, deps: KindDeps) {
    super(ctx, deps, 'vector_field', VECTOR_COLORS);
  }

  /** "Show" (over its mesh, in a colour of its own), "Hide" while drawn, with the length slider and its colour; then how many vectors have no value. */
  row(job: Job, a: ArtifactInfo, view: JobsView, actions: JobsActions): HTMLElement {
    const key = artifactKey(job.id, a.name);
    const [toggle, swatch] = this.toggle(job, a, view.state, actions, {
      class: 'show-vectors',
      shown: 'Hide',
      hidden: 'Show',
      titles: { shown: 'Stop drawing the vectors', hidden: 'Draw the vectors over the mesh' },
    });
    return artifactRow(job, a, this.storedFormat, [toggle, swatch, swatch ? this.lengthControl(key, a.name) : null], this.note(key));
  }

  rowState(job: Job, a: ArtifactInfo, view: JobsView): [string, number | null] {
    const key = artifactKey(job.id, a.name);
    return [this.colorIn(view.state, key) ?? '', this.missing.get(key)?.missing ?? null];
  }

  /** A field on a mesh gone cannot be drawn: says so. */
  protected override canShow(job: Job, artifact: ArtifactInfo): boolean {
    const meshId = jobMeshId(job);
    if (!meshId) return false;
    if (meshOf(this.ctx, meshId)) return true;
    this.ctx.error(`Cannot show ${artifact.name} of ${job.algorithm}: its mesh no longer exists`);
    return false;
  }

  /** The field and its mesh in the stored order: made from the streamed one (no second download of it). */
  protected async fetch(job: Job, artifact: ArtifactInfo): Promise<(color: string) => DrawnVectors> {
    const key = artifactKey(job.id, artifact.name);
    const [values, ply] = await Promise.all([fetchArtifactF32(job.id, artifact.name), this.deps.loader.ply(jobMeshId(job)!)]);
    return (color) => {
      if (values.length % 3 !== 0) throw new Error(`${values.length} numbers are not whole x, y, z triples`);
      const location = artifact.location ?? (values.length / 3 === ply.faces && values.length / 3 !== ply.vertices ? 'face' : 'vertex');
      const hint = artifact.hint === 'direction' ? 'direction' : 'arrow';
      const maxLength = Number.isFinite(artifact.max_length) && artifact.max_length! > 0 ? artifact.max_length! : longest(values);
      const field: VectorField = { name: artifact.name, location, hint, values, maxLength };
      const glyphs = new VectorGlyphs(ply, field, color, this.scales.get(key) ?? 1);
      this.followShown(glyphs.object);
      this.missing.set(key, { missing: glyphs.stats.missing, count: values.length / 3, location });
      return { object: glyphs.object, glyphs, color, field };
    };
  }

  /** The segments' length as a multiple of the default, from 1/4 to 4 (a log scale): it changes them in place. */
  private lengthControl(key: string, name: string): HTMLElement {
    const scale = this.scales.get(key) ?? 1;
    const input = el('input', {
      type: 'range',
      class: 'vector-length',
      min: String(SCALE_LOG2.min),
      max: String(SCALE_LOG2.max),
      step: String(SCALE_LOG2.step),
      value: String(Math.log2(scale)),
      'aria-label': `Length of ${name}`,
      title: 'Length of the lines drawn',
    });
    const value = el('output', { class: 'vector-length-value' }, times(scale));
    input.addEventListener('input', () => {
      const s = 2 ** Number(input.value);
      value.textContent = times(s);
      this.setScale(key, s);
    });
    return el('label', { class: 'vector-length-row' }, 'Length', input, value);
  }

  private setScale(key: string, scale: number): void {
    this.scales.set(key, scale);
    const drawn = this.drawn.get(key);
    if (!drawn) return;
    drawn.glyphs.setScale(scale);
    this.ctx.viewer.redraw(() => this.report());
  }

  /** How many vectors have no value, once the field has been fetched. */
  private note(key: string): HTMLElement | null {
    const m = this.missing.get(key);
    if (!m) return null;
    const where = m.location === 'face' ? 'faces' : 'vertices';
    const text = m.missing ? `${m.missing} of ${m.count} ${where} without a value (not drawn)` : `all ${m.count} ${where} have a value`;
    return el('p', { class: m.missing ? 'vector-missing warn' : 'vector-missing' }, text);
  }

  protected report(): void {
    this.ctx.hooks.vectors = [...this.drawn].map(([key, d]) => ({
      key,
      color: d.color,
      location: d.field.location,
      hint: d.field.hint,
      type: d.glyphs.object.type,
      points: d.glyphs.object.geometry.getAttribute('position').count,
      drawn: d.glyphs.stats.drawn,
      missing: d.glyphs.stats.missing,
      length: d.glyphs.stats.length * (this.scales.get(key) ?? 1),
      scale: this.scales.get(key) ?? 1,
    }));
  }
}

/** A scale as the slider writes it beside itself ("1×", "0.5×", "2.38×"). */
function times(scale: number): string {
  return `${Number(scale.toPrecision(3))}×`;
}
