// The report of the shown mesh: every key the server sends, in its order,
// each value with its unit (panels/format.ts), then the mesh's metadata,
// warnings and download links.
import { downloadUrl, meshFormats } from '../api/rest.ts';
import type { Mesh } from '../api/types.ts';
import { el, formatBytes } from './dom.ts';
import { metricCell } from './format.ts';

function label(key: string): string {
  return key.replace(/_/g, ' ');
}

// The keys protocol/API.md names come first, in its order; then the rest as sent.
const FIRST = ['vertices', 'faces', 'edges', 'bbox', 'components', 'boundary_loops', 'genus', 'manifold', 'degenerate_faces'];

function ordered(report: Record<string, unknown>): Array<[string, unknown]> {
  const entries = Object.entries(report);
  const rank = (key: string) => {
    const i = FIRST.indexOf(key);
    return i < 0 ? FIRST.length : i;
  };
  return entries
    .map((e, i) => ({ e, i }))
    .sort((a, b) => rank(a.e[0]) - rank(b.e[0]) || a.i - b.i)
    .map(({ e }) => e);
}

// Facts that are defects when true (a closed mesh facing inward), marked as a "no" is.
const BAD_WHEN_TRUE = new Set(['faces_inward']);

/** The bounding box's diagonal, which the relative metrics of the jobs are fractions of; null without a box. */
function diagonal(bbox: unknown): number | null {
  const box = bbox as { min?: unknown; max?: unknown } | null;
  const ok = (p: unknown): p is number[] => Array.isArray(p) && p.length === 3 && p.every((c) => typeof c === 'number');
  if (!box || !ok(box.min) || !ok(box.max)) return null;
  const [a, b] = [box.min, box.max];
  return Math.hypot(b[0]! - a[0]!, b[1]! - a[1]!, b[2]! - a[2]!);
}

function rows(report: Record<string, unknown>, prefix = ''): HTMLTableRowElement[] {
  const out: HTMLTableRowElement[] = [];
  for (const [key, value] of prefix ? Object.entries(report) : ordered(report)) {
    const name = prefix ? `${prefix} ${label(key)}` : label(key);
    if (value && typeof value === 'object' && !Array.isArray(value)) {
      // The server's JSON objects come with sorted keys: a box reads min first.
      const inner = Object.entries(value as Record<string, unknown>).sort(([a], [b]) => Number(b === 'min') - Number(a === 'min'));
      out.push(...rows(Object.fromEntries(inner), name));
      const d = key === 'bbox' && !prefix ? diagonal(value) : null;
      if (d !== null) {
        out.push(
          el(
            'tr',
            { class: 'derived' },
            el('th', { scope: 'row', title: 'computed here from bbox min and max; the relative metrics of jobs are fractions of it' }, 'bbox diagonal'),
            metricCell('bbox diagonal', d),
          ),
        );
      }
      continue;
    }
    const good = BAD_WHEN_TRUE.has(key) ? !value : value;
    const cls = typeof value === 'boolean' ? (good ? 'yes' : 'no') : '';
    out.push(el('tr', { 'data-key': prefix ? undefined : key }, el('th', { scope: 'row', title: key }, name), metricCell(name, value, cls)));
  }
  return out;
}

export class ReportPanel {
  private readonly root: HTMLElement;
  /** The formats a mesh downloads in (the server's GET /api/v1/formats, can_write); empty till it answers. */
  private writable: string[] = [];
  private shown: Mesh | null = null;

  constructor(root: HTMLElement) {
    this.root = root;
  }

  /** Asks the server for its writable formats, and shows the links when they come. */
  private learnFormats(): void {
    meshFormats().then(
      (formats) => {
        this.writable = formats.filter((f) => f.can_write).map((f) => f.name);
        this.render(this.shown);
      },
      () => undefined,
    );
  }

  render(mesh: Mesh | null): void {
    this.shown = mesh;
    if (mesh && !this.writable.length) this.learnFormats();
    if (!mesh) {
      this.root.replaceChildren(el('p', { class: 'empty' }, 'Choose a mesh to see its report.'));
      return;
    }
    const meta = el(
      'table',
      { class: 'kv meta' },
      el('tr', {}, el('th', { scope: 'row' }, 'name'), el('td', {}, mesh.name)),
      el('tr', {}, el('th', { scope: 'row' }, 'format'), el('td', {}, mesh.format)),
      el('tr', {}, el('th', { scope: 'row' }, 'size'), el('td', { title: `${mesh.bytes} bytes` }, formatBytes(mesh.bytes))),
      el('tr', {}, el('th', { scope: 'row' }, 'uploaded'), el('td', {}, mesh.created)),
      mesh.sha256 ? el('tr', {}, el('th', { scope: 'row' }, 'sha256'), el('td', { class: 'hash', title: mesh.sha256 }, mesh.sha256.slice(0, 16) + '…')) : null,
    );
    const warnings = mesh.warnings?.length ? el('ul', { class: 'warnings' }, ...mesh.warnings.map((w) => el('li', {}, w))) : null;
    const downloads = el(
      'p',
      { class: 'downloads' },
      'Download: ',
      ...this.writable.flatMap((f, i) => [i ? ' ' : '', el('a', { href: downloadUrl(mesh.id, f), download: '' }, f)]),
    );
    const parts: Node[] = [el('h3', {}, mesh.name), el('table', { class: 'kv report' }, ...rows(mesh.report as Record<string, unknown>))];
    if (warnings) parts.push(el('h4', {}, 'Warnings'), warnings);
    parts.push(el('h4', {}, 'File'), meta, downloads);
    this.root.replaceChildren(...parts);
  }
}
