// The Display panel: the shown surface's mode and material, the overlays
// over it, the range of the scalar field drawn on it, and the view link's
// text. It owns the display and overlay settings and applies them to
// whatever the viewer shows (viewer.onShownChange), so that a mesh shown
// later keeps the mode chosen. With several meshes in the scene, the mode and
// material apply to every object of it, each in its own colour where the
// scene gives one (panels/scene.ts); the overlays are of the shown (first) one.
// A comparison's panes (fields or skeletons side by side) draw their surfaces
// in the mode too (viewer.onPanesChange). The up axis of the shown mesh is
// chosen here too (viewer/up_axis.ts): the one the user chose for it, else
// the one its file's format implies.
import * as THREE from 'three';
import { saveBlob } from '../api/auth.ts';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import { creaseOf, creaseRefusal } from '../viewer/crease.ts';
import {
  applyCrease,
  applyDisplay,
  CREASED_MODES,
  DEFAULT_DISPLAY,
  DISPLAY_MODES,
  isDefaultDisplay,
  isSurface,
  MATERIAL_PRESETS,
  sanitizeDisplay,
  type DisplaySettings,
} from '../viewer/display_modes.ts';
import { percentileRange } from '../viewer/histogram.ts';
import { DEFAULT_OVERLAYS, formatSize, sanitizeOverlays, updateOverlays, type OverlayInfo, type OverlaySettings } from '../viewer/overlays.ts';
import { defaultUpAxis, setObjectUp, storeUpAxis, storedUpAxis, UP_AXIS_RULE, type UpAxis } from '../viewer/up_axis.ts';
import type { Viewer } from '../viewer/viewer.ts';
import { checkbox, edgeLegend, row, slider, sliderRow } from './display_controls.ts';
import { el } from './dom.ts';
import { formatMetric, formatNumber } from './format.ts';

/** What the panel reports after each change has been drawn (window.__cgview.display). */
export interface DisplayReport extends DisplaySettings, OverlayInfo {
  overlays: OverlaySettings;
  /** The shown object's name ("surface", "scalar:NAME"), or null. */
  object: string | null;
  /** The shown mesh's up axis. */
  up: UpAxis;
  /** The crease angle the shown surface is drawn with; null: as built (180°, its file's normals, not a surface). */
  crease: number | null;
}

export interface DisplayCallbacks {
  /** A new range for the field drawn (null: its full range). */
  setFieldRange: (range: [number, number] | null) => void;
  /** Called after a frame shows the settings. */
  drawn: (report: DisplayReport) => void;
  /** The scene's other objects, drawn in the same mode (none by default). */
  others?: () => THREE.Object3D[];
  /** An object's own colour in the scene, in place of the material's; null: the material's. */
  colorOf?: (object: THREE.Object3D) => string | null;
  /** The mesh an object of the scene draws (its up axis is that mesh's), or null. */
  meshOf?: (object: THREE.Object3D) => string | null;
  /** A mesh's file format ("stl", "glb"...), which gives its up axis until one is chosen; null: not known. */
  formatOf?: (meshId: string) => string | null;
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
  private settings: DisplaySettings = { ...DEFAULT_DISPLAY };
  private overlays: OverlaySettings = { ...DEFAULT_OVERLAYS };
  private info: OverlayInfo = { size: null, boundaryEdges: null, nonManifoldEdges: null };
  private object: THREE.Object3D | null = null;
  /** The surfaces of a comparison's panes (fields, skeletons over the mesh), drawn in the mode as the shown one is. */
  private paneSurfaces: THREE.Mesh[] = [];
  /** The objects of a comparison's panes, all of the shown mesh: they are drawn with its up axis. */
  private paneObjects: readonly THREE.Object3D[] = [];
  /** The scene object whose overlays are drawn, when not the shown one. */
  private overlayObject: THREE.Object3D | null = null;
  private environment: THREE.Texture | null = null;
  private field: { range: [number, number]; full: [number, number]; values: Float32Array } | null = null;

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
  private readonly toonBandsRow = row('Toon bands', this.toonBands);
  private readonly creaseRow = sliderRow('Crease angle', this.crease, this.creaseValue);

  constructor(
    root: HTMLElement,
    private readonly viewer: Viewer,
    private readonly callbacks: DisplayCallbacks,
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
    this.up.addEventListener('change', () => this.setUpAxis(this.up.value === 'z' ? 'z' : 'y'));
    this.preset.addEventListener('change', () => {
      const p = MATERIAL_PRESETS.find((m) => m.name === this.preset.value);
      if (!p) return;
      this.setDisplay({ ...this.settings, preset: p.name, color: p.color, roughness: p.roughness, metalness: p.metalness });
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
        this.callbacks.setFieldRange([lo, hi]);
      }
    };
    this.fieldMin.addEventListener('change', rangeChange);
    this.fieldMax.addEventListener('change', rangeChange);
    clip.addEventListener('click', () => {
      if (this.field) this.callbacks.setFieldRange(percentileRange(this.field.values, 1, 99));
    });
    full.addEventListener('click', () => this.callbacks.setFieldRange(null));

    viewer.onShownChange((object) => this.attach(object));
    viewer.onPanesChange((panes) => this.attachPanes(panes));
  }

  /** The settings, for the view link. */
  state(): { display: DisplaySettings; overlays: OverlaySettings } {
    return { display: { ...this.settings }, overlays: { ...this.overlays } };
  }

  /** Takes settings from a view link (untrusted: checked, invalid values fall back to the defaults). */
  restore(display: Record<string, unknown> | undefined, overlays: Record<string, unknown> | undefined): void {
    this.settings = sanitizeDisplay(display);
    this.overlays = sanitizeOverlays(overlays);
    this.syncInputs();
    this.applyAll();
  }

  /** The shown mesh's up axis. */
  upAxis(): UpAxis {
    const mesh = this.object && this.meshOf(this.object);
    return mesh ? this.upOf(mesh) : 'y';
  }

  /** A mesh's up axis: the one chosen for it, else its format's. */
  private upOf(mesh: string): UpAxis {
    return storedUpAxis(mesh, defaultUpAxis(this.callbacks.formatOf?.(mesh) ?? null));
  }

  /**
   * Makes `axis` the shown mesh's up axis: kept for the mesh, put on its
   * objects (the shown one, its panes, its copies in the scene), and the
   * view framed again, since the objects turned.
   */
  setUpAxis(axis: UpAxis): void {
    const mesh = this.object && this.meshOf(this.object);
    if (!mesh) {
      this.up.value = 'y';
      return;
    }
    storeUpAxis(mesh, axis, defaultUpAxis(this.callbacks.formatOf?.(mesh) ?? null));
    this.up.value = axis;
    let turned = false;
    for (const o of [...(this.object ? [this.object] : []), ...(this.callbacks.others?.() ?? []), ...this.paneObjects]) {
      if (this.meshOfOrShown(o) === mesh && setObjectUp(o, axis)) turned = true;
    }
    if (!turned) return;
    this.viewer.fitAll();
    this.refreshOverlays();
  }

  /** The mesh an object draws; the panes' objects are the shown mesh's. */
  private meshOfOrShown(object: THREE.Object3D): string | null {
    if (this.paneObjects.includes(object)) return this.object && this.meshOf(this.object);
    return this.meshOf(object);
  }

  private meshOf(object: THREE.Object3D): string | null {
    return this.callbacks.meshOf?.(object) ?? null;
  }

  /** The field drawn now (its range and full range, and its values for percentiles), or null. */
  setField(field: { range: [number, number]; full: [number, number]; values: Float32Array } | null): void {
    this.field = field;
    this.fieldBox.hidden = !field;
    if (field) {
      const text: [string, string] = [formatNumber(field.range[0]), formatNumber(field.range[1])];
      this.fieldShown = { text, exact: [...field.range] };
      [this.fieldMin.value, this.fieldMax.value] = text;
      this.fieldMin.title = `${field.range[0]}`;
      this.fieldMax.title = `${field.range[1]}`;
    }
  }

  /** Shows the view link's URL in the panel. */
  showLink(url: string): void {
    this.link.value = url;
    this.link.hidden = false;
    this.link.select();
  }

  /** Downloads the canvas as a PNG, drawn afresh (the drawing buffer is read in the frame's own task). */
  screenshot(fileName: string, done?: (blob: Blob | null) => void): void {
    this.viewer.redraw(() => {
      this.viewer.renderer.domElement.toBlob((blob) => {
        if (blob) saveBlob(blob, fileName);
        done?.(blob);
      }, 'image/png');
    });
  }

  private setDisplay(s: DisplaySettings): void {
    this.settings = s;
    this.syncInputs();
    for (const o of this.targets()) this.applyTo(o);
    this.report();
  }

  /** Draws `object` (one of the scene's) in the mode and material, in its own colour. */
  applyTo(object: THREE.Object3D | null): void {
    const mesh = object && this.meshOf(object);
    if (mesh) setObjectUp(object, this.upOf(mesh));
    if (!isSurface(object)) return;
    const color = this.callbacks.colorOf?.(object) ?? null;
    applyDisplay(object, color ? { ...this.settings, color } : this.settings, () => this.env());
  }

  private targets(): THREE.Object3D[] {
    return [...(this.object ? [this.object] : []), ...(this.callbacks.others?.() ?? []), ...this.paneSurfaces];
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
    this.setDisplay(s);
  }

  private readOverlayInputs(): void {
    this.overlays = {
      bbox: this.checks.bbox.input.checked,
      axes: this.checks.axes.input.checked,
      vertexNormals: this.checks.vertexNormals.input.checked,
      faceNormals: this.checks.faceNormals.input.checked,
      edges: this.checks.edges.input.checked,
      normalLength: Number(this.normalLength.value),
    };
    this.refreshOverlays();
  }

  /** Draws the overlays over `object` (a scene object chosen in the Scene panel); null: over the shown one. */
  setOverlayObject(object: THREE.Object3D | null): void {
    this.overlayObject = object;
    this.refreshOverlays();
  }

  /** Builds the overlays again (their object moved). */
  refreshOverlays(): void {
    this.info = updateOverlays(this.viewer, this.overlayObject ?? this.object, this.overlays);
    this.report();
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
    this.pointSizeRow.hidden = s.mode !== 'points';
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

  /** A new shown object: the mode and the overlays follow it (a default display leaves it as built). */
  private attach(object: THREE.Object3D | null): void {
    this.object = object;
    const mesh = object && this.meshOf(object);
    // Before the viewer frames it: the camera frames the object as drawn, turned.
    if (mesh) setObjectUp(object, this.upOf(mesh));
    this.up.value = mesh ? this.upOf(mesh) : 'y';
    if (object && (!isDefaultDisplay(this.settings) || this.callbacks.colorOf?.(object))) this.applyTo(object);
    else if (isSurface(object)) applyCrease(object, this.settings);
    // The slider stays for the other objects of the scene, but says when it does not apply to the shown one.
    const refusal = isSurface(object) ? creaseRefusal(object) : null;
    this.crease.disabled = refusal !== null;
    this.crease.title = refusal ?? CREASE_HELP;
    this.vertexColors.row.hidden = !(isSurface(object) && object.geometry.getAttribute('color') && !object.name.startsWith('scalar:'));
    this.refreshOverlays();
  }

  /** New panes of a comparison: their surfaces (a pane's object, or the surfaces in its group) are drawn in the mode too. */
  private attachPanes(panes: readonly THREE.Object3D[]): void {
    this.paneObjects = [...panes];
    const axis = this.upAxis();
    for (const p of panes) setObjectUp(p, axis);
    this.paneSurfaces = panes.flatMap((p) => (isSurface(p) ? [p] : p.children.filter(isSurface)));
    if (!isDefaultDisplay(this.settings)) for (const o of this.paneSurfaces) this.applyTo(o);
    else for (const o of this.paneSurfaces) applyCrease(o, this.settings);
  }

  private applyAll(): void {
    for (const o of this.targets()) this.applyTo(o);
    this.refreshOverlays();
  }

  /** Reflections for metals: a PMREM of three's room environment, made once, when first needed. */
  private env(): THREE.Texture {
    if (!this.environment) {
      const pmrem = new THREE.PMREMGenerator(this.viewer.renderer);
      const room = new RoomEnvironment();
      this.environment = pmrem.fromScene(room, 0.04).texture;
      room.dispose();
      pmrem.dispose();
    }
    return this.environment;
  }

  /** Updates the readout, and tells the app once a frame shows the settings. */
  private report(): void {
    const parts: string[] = [];
    if (this.info.size) parts.push(`Box ${formatSize(this.info.size)}`);
    if (this.info.boundaryEdges !== null) {
      parts.push(`${this.info.boundaryEdges} boundary edges, ${this.info.nonManifoldEdges} non-manifold`);
    }
    this.readout.textContent = parts.join(' · ');
    this.readout.dataset.boundary = this.info.boundaryEdges === null ? '' : String(this.info.boundaryEdges);
    this.readout.dataset.nonManifold = this.info.nonManifoldEdges === null ? '' : String(this.info.nonManifoldEdges);
    const object = this.object;
    const report: DisplayReport = {
      ...this.settings,
      ...this.info,
      overlays: { ...this.overlays },
      object: object?.name ?? null,
      up: this.upAxis(),
      crease: isSurface(object) ? creaseOf(object) : null,
    };
    this.viewer.redraw(() => {
      if (this.object === object) this.callbacks.drawn(report);
    });
  }
}
