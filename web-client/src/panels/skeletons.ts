// The skeleton comparison (the paper's Figure 5): one column per skeleton
// drawn over the mesh (its colour, its algorithm), one row per measure of its
// job's metrics (skeleton_metrics' names), and the distance of each to the
// first, measured by the server's skeleton_distance (symmetric Hausdorff and
// mean), so that the numbers are the API's.
import { el } from './dom.ts';
import { formatNumber, formatValue } from './format.ts';

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

export class SkeletonsPanel {
  /** A "Load skeleton file…" button and its hidden file input, kept across renders. */
  private readonly load: HTMLElement;

  /**
   * onSideBySide: show the skeletons in synchronized panes, one each;
   * onLoadFile: a skeleton file chosen with "Load skeleton file…", to attach to the shown mesh.
   */
  constructor(
    private readonly root: HTMLElement,
    private readonly onSideBySide: () => void,
    onLoadFile: (file: File) => void,
  ) {
    const input = el('input', { type: 'file', id: 'skeleton-file-input', accept: SKELETON_FILE_TYPES, hidden: '' });
    input.addEventListener('change', () => {
      const file = input.files?.[0];
      input.value = ''; // the same file chosen again is a change too
      if (file) onLoadFile(file);
    });
    const button = el(
      'button',
      { type: 'button', class: 'button small load-skeleton', title: 'A skeleton made by another tool: CGAL polylines, .cg, OBJ with l records or JSON' },
      'Load skeleton file…',
    );
    button.addEventListener('click', () => input.click());
    this.load = el('div', { class: 'load-skeleton-row' }, button, input);
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
      for (const c of columns) tr.append(el('td', {}, c.metrics === undefined ? '…' : formatValue(c.metrics[name])));
      return tr;
    });
    const distance = el('tr', { 'data-metric': 'distance' }, el('th', { scope: 'row' }, 'distance to the first (Hausdorff / mean)'));
    for (const c of columns)
      distance.append(el('td', {}, c.distance === null ? '—' : c.distance === undefined ? '…' : `${formatNumber(c.distance.hausdorff)} / ${formatNumber(c.distance.mean)}`));
    const side = el('button', { type: 'button', class: 'button small side-by-side' }, 'Side by side');
    side.disabled = columns.length < 2;
    side.addEventListener('click', () => this.onSideBySide());
    this.root.replaceChildren(el('table', { class: 'kv skeleton-table' }, head, ...rows, distance), side, this.load);
  }
}
