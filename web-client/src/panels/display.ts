// The Display panel: the inputs of the shown surface's mode and material and
// of the overlays over it, written from the state (AppState.display) and
// writing it (controllers/display.ts applies the settings to what is shown);
// the shown mesh's up axis, the range of the scalar field drawn, what the
// overlays measured, and the view link's text.
import { CREASED_MODES, DEFAULT_DISPLAY, DISPLAY_MODES, MATERIAL_PRESETS, type DisplaySettings } from '../viewer/display_modes.ts';
import { formatSize, type OverlayInfo, type OverlaySettings } from '../viewer/overlays.ts';
import { UP_AXIS_RULE, type UpAxis } from '../viewer/up_axis.ts';
import type { AppStore } from '../state/app_state.ts';
import { checkbox, edgeLegend, row, slider, sliderRow } from './display_controls.ts';
import { el } from './dom.ts';
import { formatMetric, formatNumber } from './format.ts';

/** What the panel's inputs do. */
export interface DisplayActions {
  setDisplay(settings: DisplaySettings): void;
  setOverlays(overlays: OverlaySettings): void;
  setUpAxis(axis: UpAxis): void;
  /** A new range for the field drawn (null: its full range). */
  setFieldRange(range: [number, number] | null): void;
  /** The field's range from its 1st to its 99th percentile. */
  clipField(): void;
}

const MODE_LABELS: Record<string, string> = {
  smooth: 'Smooth',
  flat: 'Flat',
  wireframe: 'Wireframe',
  points: 'Points',
  'hidden-line': 'Hidden line',
  toon: 'Toon',
};

const degreesText = (degrees: number) => `${degrees}°`;
const CREASE_HELP = 'Faces meeting at more than this angle are shaded apart, as a part has edges; 180° is smooth across every edge';

/** The normal length, a fraction of the box's diagonal, as the units of panels/format.ts write it. */
function normalLengthText(fraction: number): string {
  return formatMetric('normal_length_relative', fraction).text;
}

export class DisplayPanel {
  private readonly mode = el('select', { id: 'display-mode', 'aria-label': 'Display mode' });
  private readonly up = el(
    'select',
    { id: 'display-up', 'aria-label': 'Up axis', title: `Which of the mesh's axes points up; remembered for this mesh. Until chosen: ${UP_AXIS_RULE}` },
    el('option', { value: 'y' }, 'Y up'),
    el('option', { value: 'z' }, 'Z up'),
  );
  private readonly preset = el('select', { id: 'display-preset', 'aria-label': 'Material' });
  private readonly color = el('input', { type: 'color', id: 'display-color' });
  private readonly roughness = slider('display-roughness', 0, 1, 0.05);
  private readonly metalness = slider('display-metalness', 0, 1, 0.05);
  private readonly pointSize = slider('display-point-size', 1, 12, 1);
  private readonly crease = slider('display-crease', 0, 180, 5);
  private readonly creaseValue = el('output', { class: 'slider-value' });
  private readonly toonBands = el('input', { type: 'number', id: 'display-toon-bands', min: '2', max: '8', step: '1' });
  private readonly vertexColors = checkbox('display-vertex-colors', 'Vertex colours');
  private readonly checks = {
    bbox: checkbox('overlay-bbox', 'Bounding box'),
    axes: checkbox('overlay-axes', 'Axes'),
    vertexNormals: checkbox('overlay-vertex-normals', 'Vertex normals'),
    faceNormals: checkbox('overlay-face-normals', 'Face normals'),
    edges: checkbox('overlay-edges', 'Boundary / non-manifold edges'),
  };
  private readonly normalLength = slider('overlay-normal-length', 0.005, 0.2, 0.005);
  private readonly roughnessValue = el('output', { class: 'slider-value' });
  private readonly metalnessValue = el('output', { class: 'slider-value' });
  private readonly normalLengthValue = el('output', { class: 'slider-value' });
  /** The field range as written in its inputs (4 significant digits) and as it is: an input left as written means the exact value. */
  private fieldShown: { text: [string, string]; exact: [number, number] } | null = null;
  private readonly readout = el('div', { class: 'display-readout', id: 'overlay-readout' });
  private readonly fieldBox = el('div', { class: 'field-range', id: 'field-range' });
  private readonly fieldMin = el('input', { type: 'number', id: 'field-min', step: 'any', 'aria-label': 'Field minimum' });
  private readonly fieldMax = el('input', { type: 'number', id: 'field-max', step: 'any', 'aria-label': 'Field maximum' });
  private readonly link = el('input', { type: 'text', id: 'view-link', readonly: '', 'aria-label': 'View link' });
  /** Rows that only one mode uses, shown with it. */
  private readonly pointSizeRow = row('Point size', this.pointSize);
  /** Whether points are drawn whatever the mode (a point cloud, a job's points): the point size applies to them. */
  private points = false;
  private readonly toonBandsRow = row('Toon bands', this.toonBands);
  private readonly creaseRow = sliderRow('Crease angle', this.crease, this.creaseValue);

  constructor(
    root: HTMLElement,
    private readonly store: AppStore,
    private readonly actions: DisplayActions,
  ) {
    for (const m of DISPLAY_MODES) this.mode.append(el('option', { value: m }, MODE_LABELS[m] ?? m));
    for (const p of MATERIAL_PRESETS) this.preset.append(el('option', { value: p.name }, p.name));
    const clip = el('button', { type: 'button', class: 'button small', id: 'field-clip' }, '1–99%');
    const full = el('button', { type: 'button', class: 'button small', id: 'field-full' }, 'Full range');
    this.fieldBox.append(
      el('div', { class: 'display-subhead' }, 'Field range'),
      el('div', { class: 'field-range-inputs' }, this.fieldMin, '–', this.fieldMax),
      el('div', { class: 'field-range-buttons' }, clip, full),
    );
    this.fieldBox.hidden = true;
    this.link.hidden = true;
    this.crease.title = CREASE_HELP;
    root.append(
      row('Mode', this.mode),
      row('Up axis', this.up),
      this.creaseRow,
      row('Material', this.preset),
      row('Colour', this.color),
      sliderRow('Roughness', this.roughness, this.roughnessValue),
      sliderRow('Metalness', this.metalness, this.metalnessValue),
      this.pointSizeRow,
      this.toonBandsRow,
      this.vertexColors.row,
      el('div', { class: 'display-subhead' }, 'Overlays'),
      ...Object.values(this.checks).map((c) => c.row),
      sliderRow('Normal length', this.normalLength, this.normalLengthValue),
      edgeLegend(),
      this.readout,
      this.fieldBox,
      this.link,
    );
    this.syncInputs();

    const change = () => this.readInputs();
    for (const input of [this.mode, this.color, this.roughness, this.metalness, this.pointSize, this.toonBands, this.vertexColors.input]) {
      input.addEventListener('input', change);
      input.addEventListener('change', change);
    }
    this.up.addEventListener('change', () => actions.setUpAxis(this.up.value === 'z' ? 'z' : 'y'));
    this.preset.addEventListener('change', () => {
      const p = MATERIAL_PRESETS.find((m) => m.name === this.preset.value);
      if (!p) return;
      actions.setDisplay({ ...this.settings, preset: p.name, color: p.color, roughness: p.roughness, metalness: p.metalness });
    });
    const overlayChange = () => this.readOverlayInputs();
    for (const c of Object.values(this.checks)) c.input.addEventListener('change', overlayChange);
    this.normalLength.addEventListener('change', overlayChange);
    this.normalLength.addEventListener('input', overlayChange);

    // While the value is being dragged, before readInputs has the settings.
    this.roughness.addEventListener('input', () => (this.roughnessValue.value = formatNumber(Number(this.roughness.value))));
    this.metalness.addEventListener('input', () => (this.metalnessValue.value = formatNumber(Number(this.metalness.value))));
    // Split normals are made again at each angle: on letting go (a big mesh takes a while), its value shown while dragged.
    this.crease.addEventListener('input', () => (this.creaseValue.value = degreesText(Number(this.crease.value))));
    this.crease.addEventListener('change', change);
    this.normalLength.addEventListener('input', () => (this.normalLengthValue.value = normalLengthText(Number(this.normalLength.value))));

    const rangeChange = () => {
      const shown = this.fieldShown;
      const exactly = (input: HTMLInputElement, i: 0 | 1) => (shown && input.value === shown.text[i] ? shown.exact[i] : Number(input.value));
      const lo = exactly(this.fieldMin, 0);
      const hi = exactly(this.fieldMax, 1);
      if (this.fieldMin.value !== '' && this.fieldMax.value !== '' && Number.isFinite(lo) && Number.isFinite(hi) && lo < hi) {
        actions.setFieldRange([lo, hi]);
      }
    };
    this.fieldMin.addEventListener('change', rangeChange);
    this.fieldMax.addEventListener('change', rangeChange);
    clip.addEventListener('click', () => actions.clipField());
    full.addEventListener('click', () => actions.setFieldRange(null));
    store.subscribe(
      (s) => s.display,
      () => this.syncInputs(),
    );
  }

  private get settings(): DisplaySettings {
    return this.store.get().display.settings;
  }

  private get overlays(): OverlaySettings {
    return this.store.get().display.overlays;
  }

  /** The shown mesh's up axis. */
  showUp(axis: UpAxis): void {
    this.up.value = axis;
  }

  /** What of the inputs applies to the shown object: the crease angle (or why not), its own vertex colours. */
  showObject(shown: { creaseRefusal: string | null; vertexColors: boolean; points: boolean }): void {
    this.crease.disabled = shown.creaseRefusal !== null;
    this.crease.title = shown.creaseRefusal ?? CREASE_HELP;
    this.vertexColors.row.hidden = !shown.vertexColors;
    this.points = shown.points;
    this.syncInputs();
  }

  /** The range of the field drawn now, or null: none drawn. */
  showField(range: [number, number] | null): void {
    this.fieldBox.hidden = !range;
    if (range) {
      const text: [string, string] = [formatNumber(range[0]), formatNumber(range[1])];
      this.fieldShown = { text, exact: [...range] };
      [this.fieldMin.value, this.fieldMax.value] = text;
      this.fieldMin.title = `${range[0]}`;
      this.fieldMax.title = `${range[1]}`;
    }
  }

  /** Shows the view link's URL in the panel. */
  showLink(url: string): void {
    this.link.value = url;
    this.link.hidden = false;
    this.link.select();
  }

  private readInputs(): void {
    const s: DisplaySettings = {
      ...this.settings,
      mode: this.mode.value as DisplaySettings['mode'],
      color: this.color.value,
      roughness: Number(this.roughness.value),
      metalness: Number(this.metalness.value),
      pointSize: Number(this.pointSize.value),
      toonBands: Math.round(Math.min(8, Math.max(2, Number(this.toonBands.value) || DEFAULT_DISPLAY.toonBands))),
      creaseAngle: Math.min(180, Math.max(0, Number(this.crease.value))),
      vertexColors: this.vertexColors.input.checked,
    };
    this.actions.setDisplay(s);
  }

  private readOverlayInputs(): void {
    this.actions.setOverlays({
      bbox: this.checks.bbox.input.checked,
      axes: this.checks.axes.input.checked,
      vertexNormals: this.checks.vertexNormals.input.checked,
      faceNormals: this.checks.faceNormals.input.checked,
      edges: this.checks.edges.input.checked,
      normalLength: Number(this.normalLength.value),
    });
  }

  private syncInputs(): void {
    const s = this.settings;
    this.mode.value = s.mode;
    this.preset.value = s.preset;
    this.color.value = s.color;
    this.roughness.value = String(s.roughness);
    this.metalness.value = String(s.metalness);
    this.pointSize.value = String(s.pointSize);
    this.toonBands.value = String(s.toonBands);
    this.vertexColors.input.checked = s.vertexColors;
    this.pointSizeRow.hidden = s.mode !== 'points' && !this.points;
    this.toonBandsRow.hidden = s.mode !== 'toon';
    this.crease.value = String(s.creaseAngle);
    this.creaseValue.value = degreesText(s.creaseAngle);
    this.creaseRow.hidden = !CREASED_MODES.includes(s.mode);
    for (const [k, c] of Object.entries(this.checks)) c.input.checked = this.overlays[k as keyof typeof this.checks];
    this.normalLength.value = String(this.overlays.normalLength);
    this.roughnessValue.value = formatNumber(s.roughness);
    this.metalnessValue.value = formatNumber(s.metalness);
    this.normalLengthValue.value = normalLengthText(this.overlays.normalLength);
  }

  /** What the overlays measured: the box's size, the boundary and non-manifold edges. */
  showInfo(info: OverlayInfo): void {
    const parts: string[] = [];
    if (info.size) parts.push(`Box ${formatSize(info.size)}`);
    if (info.boundaryEdges !== null) {
      parts.push(`${info.boundaryEdges} boundary edges, ${info.nonManifoldEdges} non-manifold`);
    }
    this.readout.textContent = parts.join(' · ');
    this.readout.dataset.boundary = info.boundaryEdges === null ? '' : String(info.boundaryEdges);
    this.readout.dataset.nonManifold = info.nonManifoldEdges === null ? '' : String(info.nonManifoldEdges);
  }
}
