// The skeleton comparison (the paper's Figure 5): one column per skeleton
// drawn over the mesh (its colour, its algorithm), one row per measure of its
// job's metrics (skeleton_metrics' names), and the distance of each to the
// first, measured by the server's skeleton_distance (symmetric Hausdorff and
// mean), so that the numbers are the API's. Below it, the buttons that load
// what another tool made for the mesh shown: a skeleton, or a field's values
// (a PLY with a scalar property, which the upload control takes for a mesh).
import { el } from './dom.ts';
import { formatMetric, metricCell } from './format.ts';

export interface SkeletonColumn {
  key: string;
  color: string;
  algorithm: string;
  /** Its job's metrics, undefined while loading. */
  metrics: Record<string, unknown> | undefined;
  /** Hausdorff and mean distance to the first skeleton (undefined: being measured; null: it is the first). */
  distance: { hausdorff: number; mean: number } | undefined | null;
}

const ROWS: Array<[string, string]> = [
  ['nodes', 'nodes'],
  ['branches', 'branches'],
  ['endpoints', 'endpoints'],
  ['junctions', 'branch nodes'],
  ['loops', 'loops'],
  ['length', 'length'],
  ['inside_fraction', 'nodes inside'],
  ['centredness_mean', 'centredness (mean)'],
];

/** The skeleton files the server reads (io/skeleton_io.h: the extension names the format). */
export const SKELETON_FILE_TYPES = '.cg,.polylines,.txt,.obj,.json';
/** The scalar field files the server reads for a stored mesh (API.md, POST /data). */
export const FIELD_FILE_TYPES = '.ply,.txt';

export class SkeletonsPanel {
  /** The "Load skeleton file…" and "Load field file…" buttons and their hidden file inputs, kept across renders. */
  private readonly load: HTMLElement;
  /** The "X-ray" check, kept across renders. */
  private readonly xray: HTMLElement;

  /**
   * onSideBySide: show the skeletons in synchronized panes, one each;
   * onLoadFile: a skeleton file chosen with "Load skeleton file…", to attach to the shown mesh;
   * onLoadField: a file chosen with "Load field file…", values for the shown mesh;
   * onXray: whether the skeletons show through the surface (on at first).
   */
  constructor(
    private readonly root: HTMLElement,
    private readonly onSideBySide: () => void,
    onLoadFile: (file: File) => void,
    onLoadField: (file: File) => void,
    onXray: (on: boolean) => void,
  ) {
    const xray = el('input', { type: 'checkbox', class: 'skeleton-xray' });
    xray.checked = true;
    xray.addEventListener('change', () => onXray(xray.checked));
    this.xray = el('label', { class: 'check skeleton-xray-row', title: 'Show the skeletons through the surface; off, the surface hides them' }, xray, ' X-ray');
    const skeleton = loadButton(
      { id: 'skeleton-file-input', accept: SKELETON_FILE_TYPES },
      { class: 'load-skeleton', title: 'A skeleton made by another tool: CGAL polylines, .cg, OBJ with l records or JSON' },
      'Load skeleton file…',
      onLoadFile,
    );
    const field = loadButton(
      { id: 'field-file-input', accept: FIELD_FILE_TYPES },
      {
        class: 'load-field',
        title: 'Values another tool computed for this mesh: a PLY whose vertices or faces carry a scalar property, or text with one value a line (nan for none)',
      },
      'Load field file…',
      onLoadField,
    );
    this.load = el('div', { class: 'load-skeleton-row' }, ...skeleton, ...field);
  }

  /** hasMesh: a mesh is shown, which a skeleton file can be attached to. */
  render(columns: readonly SkeletonColumn[], hasMesh = true): void {
    this.root.hidden = columns.length === 0 && !hasMesh;
    if (!columns.length) {
      this.root.replaceChildren(this.load);
      return;
    }
    const head = el('tr', {}, el('th', {}, ''));
    for (const c of columns) head.append(el('th', { 'data-skeleton': c.key }, el('span', { class: 'swatch', style: `background:${c.color}` }), ' ', c.algorithm));
    const rows = ROWS.map(([name, label]) => {
      const tr = el('tr', { 'data-metric': name }, el('th', { scope: 'row' }, label));
      for (const c of columns) tr.append(c.metrics === undefined ? el('td', {}, '…') : metricCell(name, c.metrics[name]));
      return tr;
    });
    const distance = el('tr', { 'data-metric': 'distance' }, el('th', { scope: 'row' }, 'distance to the first (Hausdorff / mean)'));
    for (const c of columns) distance.append(c.distance === null ? el('td', {}, '—') : c.distance === undefined ? el('td', {}, '…') : distanceCell(c.distance));
    const side = el('button', { type: 'button', class: 'button small side-by-side' }, 'Side by side');
    side.disabled = columns.length < 2;
    side.addEventListener('click', () => this.onSideBySide());
    this.root.replaceChildren(el('table', { class: 'kv skeleton-table' }, head, ...rows, distance), el('div', { class: 'skeleton-actions' }, side, this.xray), this.load);
  }
}

/** A button that opens a hidden file input, and the input, which hands the file chosen to `onFile`. */
function loadButton(input: { id: string; accept: string }, button: { class: string; title: string }, label: string, onFile: (file: File) => void): [HTMLElement, HTMLElement] {
  const picker = el('input', { type: 'file', id: input.id, accept: input.accept, hidden: '' });
  picker.addEventListener('change', () => {
    const file = picker.files?.[0];
    picker.value = ''; // the same file chosen again is a change too
    if (file) onFile(file);
  });
  const open = el('button', { type: 'button', class: `button small ${button.class}`, title: button.title }, label);
  open.addEventListener('click', () => picker.click());
  return [open, picker];
}

/** "0.01 / 0.005 mesh units": both distances are lengths, so the unit is written once, after them. */
function distanceCell(d: { hausdorff: number; mean: number }): HTMLTableCellElement {
  const hausdorff = formatMetric('hausdorff', d.hausdorff);
  const mean = formatMetric('mean', d.mean);
  const td = el('td', { title: `Hausdorff ${hausdorff.title}; mean ${mean.title}` }, `${hausdorff.value} / ${mean.value}`);
  if (mean.unit) td.append(el('span', { class: 'unit' }, ` ${mean.unit}`));
  return td;
}
