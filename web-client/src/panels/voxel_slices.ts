// The voxel slice panel: for a voxel grid artifact, an axis, a
// slider through the grid's slices and, for float grids, a threshold slider;
// each slice is fetched over the WebSocket (get_slice, a zlib-compressed
// binary frame), drawn in a 2D canvas with its legend (the colour ramp over
// the slice's range, what the values are and their unit, the threshold),
// and handed to the viewer, which shows it as a textured plane moving through
// the mesh. "3D" fetches the whole grid (its NRRD artifact) and shows the
// voxels above the threshold as cubes; the threshold slider updates both
// views. Each slider shows its value beside it.
import type { SliceBegin } from '../api/ws.ts';
import { buildVoxels, parseNrrd, valueRange, type VoxelVolume } from '../viewer/voxel_renderer.ts';
import type * as THREE from 'three';
import { AXES, type Axis, type VoxelSlice } from '../api/voxel_slice.ts';
import { el } from './dom.ts';
import { fieldUnit, formatNumber, withUnit } from './format.ts';

export interface SliceSource {
  getSlice(jobId: string, artifact: string, axis: Axis, index: number): Promise<{ begin: SliceBegin; slice: VoxelSlice }>;
}

export interface SliceShown {
  /** The slice drawn as a canvas, where it lies in the world (plane corner, size), or null to hide. */
  (shown: { canvas: HTMLCanvasElement; slice: VoxelSlice; begin: SliceBegin; cut: boolean } | null): void;
}

export interface VoxelsShown {
  /** The voxels above the threshold as one object (null: hide), with their counts. */
  (shown: { object: THREE.Object3D; count: number; kept: number; threshold: number } | null): void;
}

/** The colours of the slice's drawing: an empty voxel (or one under the threshold), and the ramp from the slice's min to its max. */
/** What the panel shows and how, as a lecture carries it (its part `slice`). */
export interface SliceView {
  job: string;
  artifact: string;
  axis: Axis;
  index: number;
  /** The threshold, as a share of the range (0: off). */
  threshold: number;
  /** The mesh cut at the slice. */
  cut: boolean;
  /** The voxels above the threshold in 3D. */
  voxels: boolean;
}

const OFF_RGB: [number, number, number] = [20, 22, 28];
const RAMP = (t: number): [number, number, number] => [80 + 175 * t, 160 + 60 * t, 230];
const css = ([r, g, b]: [number, number, number]): string => `rgb(${Math.round(r)}, ${Math.round(g)}, ${Math.round(b)})`;

export class VoxelSlicePanel {
  private readonly root: HTMLElement;
  private readonly source: SliceSource;
  private readonly onShown: SliceShown;
  private target: { jobId: string; artifact: string } | null = null;
  private axis: Axis = 'z';
  private index = 0;
  private threshold = 0;
  private dims: [number, number, number] | null = null;
  private last: { begin: SliceBegin; slice: VoxelSlice } | null = null;
  private inFlight = false;
  private again = false;
  /** The first slice fetched moves to the middle of the grid (not when a lecture said which). */
  private toMiddle = true;
  private readonly canvas = el('canvas', { class: 'slice-canvas', width: '1', height: '1' });
  private readonly slider = el('input', { type: 'range', min: '0', max: '0', value: '0', 'aria-label': 'Slice index' });
  private readonly thresholdSlider = el('input', { type: 'range', min: '0', max: '1000', value: '0', 'aria-label': 'Threshold' });
  private readonly label = el('span', { class: 'slice-label' });
  private readonly thresholdLabel = el('span', { class: 'threshold-label' }, 'off');
  private readonly legendTitle = el('div', { class: 'slice-legend-title' });
  private readonly legendMin = el('span', { class: 'slice-legend-min' });
  private readonly legendCut = el('span', { class: 'slice-legend-cut' });
  private readonly legendMax = el('span', { class: 'slice-legend-max' });
  private readonly legendMark = el('div', { class: 'slice-legend-mark' });
  private readonly legend = el(
    'div',
    { class: 'slice-legend', role: 'group', 'aria-label': 'Slice legend' },
    this.legendTitle,
    el('div', { class: 'slice-legend-bar', style: `background: linear-gradient(to right, ${css(RAMP(0))}, ${css(RAMP(1))})` }, this.legendMark),
    el('div', { class: 'slice-legend-labels' }, this.legendMin, this.legendCut, this.legendMax),
    el('div', { class: 'slice-legend-note' }, el('span', { class: 'slice-legend-off', style: `background: ${css(OFF_RGB)}` }), ' empty, or under the threshold'),
  );
  private readonly cut = el('input', { type: 'checkbox', 'aria-label': 'Cut the mesh at the slice' });
  private readonly error = el('p', { class: 'empty' });
  private readonly show3d = el('input', { type: 'checkbox', 'aria-label': 'Show the voxels above the threshold in 3D', class: 'voxels-3d' });
  private volume: { key: string; data: Promise<VoxelVolume> } | null = null;
  private voxelsToken = 0;

  constructor(
    root: HTMLElement,
    source: SliceSource,
    onShown: SliceShown,
    private readonly fetchGrid: (jobId: string, artifact: string) => Promise<ArrayBuffer>,
    private readonly onVoxels: VoxelsShown,
  ) {
    this.root = root;
    this.source = source;
    this.onShown = onShown;
    this.show3d.addEventListener('change', () => this.drawVoxels());
    this.slider.addEventListener('input', () => {
      this.index = Number(this.slider.value);
      this.fetch();
    });
    this.cut.addEventListener('change', () => this.draw());
    this.thresholdSlider.addEventListener('input', () => {
      this.threshold = Number(this.thresholdSlider.value) / 1000;
      this.draw();
      this.drawVoxels();
    });
    this.render();
  }

  /** Opens the panel on a job's voxel grid artifact (the middle z slice first). */
  open(jobId: string, artifact: string): void {
    this.target = { jobId, artifact };
    this.drawVoxels();
    this.dims = null;
    this.index = 0;
    this.toMiddle = true;
    this.render();
    this.fetch();
  }

  /** The slice shown and how, or null when the panel is closed. */
  view(): SliceView | null {
    const t = this.target;
    if (!t) return null;
    return { job: t.jobId, artifact: t.artifact, axis: this.axis, index: this.index, threshold: this.threshold, cut: this.cut.checked, voxels: this.show3d.checked };
  }

  /** Shows a slice as a lecture's presenter shows it (null: closed). */
  setView(v: SliceView | null): void {
    if (!v) {
      if (this.target) this.close();
      return;
    }
    if (this.target?.jobId !== v.job || this.target.artifact !== v.artifact) {
      this.target = { jobId: v.job, artifact: v.artifact };
      this.dims = null;
      this.last = null;
    }
    this.toMiddle = false;
    this.axis = v.axis;
    this.index = v.index;
    this.threshold = Math.min(1, Math.max(0, v.threshold));
    this.thresholdSlider.value = String(Math.round(1000 * this.threshold));
    this.cut.checked = v.cut;
    this.show3d.checked = v.voxels;
    this.render();
    this.fetch();
    this.drawVoxels();
  }

  /** The grid the panel is open on, or null. */
  opened(): { jobId: string; artifact: string } | null {
    return this.target;
  }

  close(): void {
    this.target = null;
    this.last = null;
    this.onShown(null);
    this.show3d.checked = false;
    this.drawVoxels();
    this.render();
  }

  private render(): void {
    this.root.replaceChildren();
    if (!this.target) {
      this.root.hidden = true;
      return;
    }
    this.root.hidden = false;
    const axes = el('span', { class: 'slice-axes' });
    for (const a of AXES) {
      const b = el('button', { type: 'button', class: a === this.axis ? 'button small active' : 'button small' }, a);
      b.addEventListener('click', () => {
        this.axis = a;
        this.index = this.dims ? Math.floor(this.dims[AXES.indexOf(a)] / 2) : 0;
        this.render();
        this.fetch();
      });
      axes.append(b);
    }
    const close = el('button', { type: 'button', class: 'button small' }, 'Close');
    close.addEventListener('click', () => this.close());
    this.root.append(
      el('h2', {}, `Slices of ${this.target.artifact}`),
      el('div', { class: 'slice-controls' }, 'axis ', axes, ' ', close),
      el('label', {}, 'slice ', this.slider, ' ', this.label),
      el('label', {}, 'threshold ', this.thresholdSlider, ' ', this.thresholdLabel),
      el('label', {}, this.cut, ' cut the mesh at the slice (section view)'),
      el('label', {}, this.show3d, ' the voxels above the threshold in 3D'),
      this.canvas,
      this.legend,
      this.error,
    );
    this.legend.hidden = !this.last;
  }

  // One request at a time; a slider moved meanwhile asks again once it is answered.
  private fetch(): void {
    if (!this.target) return;
    if (this.inFlight) {
      this.again = true;
      return;
    }
    this.inFlight = true;
    const { jobId, artifact } = this.target;
    const first = this.dims === null;
    this.source
      .getSlice(jobId, artifact, this.axis, this.index)
      .then((r) => {
        this.error.textContent = '';
        this.dims = r.begin.dims;
        const n = this.dims[AXES.indexOf(this.axis)];
        this.slider.max = String(n - 1);
        this.slider.value = String(this.index);
        this.label.textContent = `${this.index} / ${n - 1}`;
        this.last = r;
        this.draw();
        if (first && this.toMiddle) {
          // Start in the middle of the grid.
          this.index = Math.floor(n / 2);
          this.again = true;
        }
      })
      .catch((e: Error) => {
        this.error.textContent = e.message;
      })
      .finally(() => {
        this.inFlight = false;
        if (this.again) {
          this.again = false;
          this.fetch();
        }
      });
  }

  private draw(): void {
    if (!this.last) return;
    const { slice } = this.last;
    this.canvas.width = slice.width;
    this.canvas.height = slice.height;
    const ctx = this.canvas.getContext('2d');
    if (!ctx) return;
    const image = ctx.createImageData(slice.width, slice.height);
    let lo = Infinity;
    let hi = -Infinity;
    for (const v of slice.values) {
      if (v < lo) lo = v;
      if (v > hi) hi = v;
    }
    const span = hi > lo ? hi - lo : 1;
    const cut = lo + this.threshold * span;
    this.drawLegend(lo, hi, cut);
    for (let y = 0; y < slice.height; ++y) {
      for (let x = 0; x < slice.width; ++x) {
        const v = slice.values[x + slice.width * y]!;
        // Row 0 at the bottom, as the axes run in the 3D view.
        const o = 4 * (x + slice.width * (slice.height - 1 - y));
        const on = v !== 0 && v > cut - (this.threshold === 0 ? Infinity : 0);
        const t = (v - lo) / span;
        const [r, g, b] = on ? RAMP(t) : OFF_RGB;
        image.data[o] = r;
        image.data[o + 1] = g;
        image.data[o + 2] = b;
        image.data[o + 3] = on ? 230 : 90;
      }
    }
    ctx.putImageData(image, 0, 0);
    this.onShown({ canvas: this.canvas, slice, begin: this.last.begin, cut: this.cut.checked });
  }

  /**
   * The legend of the slice drawn: the ramp's ends are the slice's own min
   * and max (each slice is scaled to its range), the mark where the threshold
   * cuts; and the threshold slider's value, as the share of the range and the
   * value it stands for in this slice.
   */
  private drawLegend(lo: number, hi: number, cut: number): void {
    const unit = this.target ? fieldUnit(this.target.artifact) : null;
    const symbol = unit ? ` ${unit.symbol}` : '';
    this.legendTitle.textContent = `${withUnit(this.target?.artifact ?? 'values', unit)}, over this slice’s range`;
    this.legendTitle.title = this.legendTitle.textContent;
    this.legendMin.textContent = formatNumber(lo);
    this.legendMax.textContent = formatNumber(hi);
    const on = this.threshold > 0;
    this.legendCut.textContent = on ? `≥ ${formatNumber(cut)}` : '';
    this.legendMark.hidden = !on;
    this.legendMark.style.left = `${100 * this.threshold}%`;
    this.thresholdLabel.textContent = on ? `${formatNumber(100 * this.threshold)}\u00a0% (≥ ${formatNumber(cut)}${symbol})` : 'off';
    this.legend.hidden = false;
  }

  /** The voxels above the threshold in 3D (the grid fetched once per artifact). */
  private drawVoxels(): void {
    const token = ++this.voxelsToken;
    if (!this.target || !this.show3d.checked) {
      this.onVoxels(null);
      return;
    }
    const { jobId, artifact } = this.target;
    const key = `${jobId}/${artifact}`;
    if (this.volume?.key !== key) this.volume = { key, data: this.fetchGrid(jobId, artifact).then(parseNrrd) };
    const threshold = this.threshold;
    this.volume.data
      .then((v) => {
        if (token !== this.voxelsToken) return;
        const [lo, hi] = valueRange(v);
        const cut = threshold === 0 ? -Infinity : lo + threshold * (hi > lo ? hi - lo : 1);
        const { object, count, kept } = buildVoxels(v, cut);
        this.onVoxels({ object, count, kept, threshold });
      })
      .catch((e: Error) => {
        this.volume = null;
        this.error.textContent = `Cannot show the voxels: ${e.message}`;
      });
  }
}
