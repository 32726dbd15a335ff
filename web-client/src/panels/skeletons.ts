// The skeleton comparison (the paper's Figure 5): one column per skeleton
// drawn over the mesh (its colour, its algorithm), one row per measure of its
// job's metrics (skeleton_metrics' names), and the distance of each to the
// first, measured by the server's skeleton_distance (symmetric Hausdorff and
// mean), so that the numbers are the API's.
import { el } from './dom.ts';

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

function format(v: unknown): string {
  if (typeof v !== 'number') return '—';
  return Number.isInteger(v) ? String(v) : Number(v.toPrecision(4)).toString();
}

export class SkeletonsPanel {
  /** onSideBySide: show the skeletons in synchronized panes, one each. */
  constructor(
    private readonly root: HTMLElement,
    private readonly onSideBySide: () => void,
  ) {}

  render(columns: readonly SkeletonColumn[]): void {
    this.root.hidden = columns.length === 0;
    if (!columns.length) {
      this.root.replaceChildren();
      return;
    }
    const head = el('tr', {}, el('th', {}, ''));
    for (const c of columns)
      head.append(el('th', { 'data-skeleton': c.key }, el('span', { class: 'swatch', style: `background:${c.color}` }), ' ', c.algorithm));
    const rows = ROWS.map(([name, label]) => {
      const tr = el('tr', { 'data-metric': name }, el('th', { scope: 'row' }, label));
      for (const c of columns) tr.append(el('td', {}, c.metrics === undefined ? '…' : format(c.metrics[name])));
      return tr;
    });
    const distance = el('tr', { 'data-metric': 'distance' }, el('th', { scope: 'row' }, 'distance to the first (Hausdorff / mean)'));
    for (const c of columns)
      distance.append(el('td', {}, c.distance === null ? '—' : c.distance === undefined ? '…' : `${format(c.distance.hausdorff)} / ${format(c.distance.mean)}`));
    const side = el('button', { type: 'button', class: 'button small side-by-side' }, 'Side by side');
    side.disabled = columns.length < 2;
    side.addEventListener('click', () => this.onSideBySide());
    this.root.replaceChildren(el('table', { class: 'kv skeleton-table' }, head, ...rows, distance), side);
  }
}
