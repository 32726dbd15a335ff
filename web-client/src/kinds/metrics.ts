// `metrics` artifacts: a JSON object of numbers, fetched when the job is done
// and shown as a table in its row of the job list, each number with the unit
// its name says (panels/format.ts).
import { fetchArtifactJson } from '../api/rest.ts';
import type { AppContext } from '../controllers/context.ts';
import { el } from '../panels/dom.ts';
import { metricCell } from '../panels/format.ts';
import type { AppState } from '../state/app_state.ts';
import { ListedKind, type Listed } from './listed.ts';
import { KindSlice } from './slice.ts';

const slice = new KindSlice<Listed>('metrics', new Map());

/** The metrics fetched, by `${jobId}/${name}` (the skeletons' table shows them too). */
export function metricsOf(state: Readonly<AppState>): Listed {
  return slice.get(state);
}

/** The metrics as a table of name and value with its unit (a nested object's names joined), or the error sentence fetching them gave. */
function metricsTable(data: unknown): HTMLElement {
  if (typeof data === 'string') return el('p', { class: 'form-error' }, data);
  const rows: HTMLTableRowElement[] = [];
  const add = (prefix: string, value: unknown) => {
    if (value && typeof value === 'object' && !Array.isArray(value)) {
      for (const [k, v] of Object.entries(value as Record<string, unknown>)) add(prefix ? `${prefix} ${k}` : k, v);
    } else {
      rows.push(el('tr', { 'data-metric': prefix }, el('th', { scope: 'row' }, prefix.replace(/_/g, ' ')), metricCell(prefix, value)));
    }
  };
  add('', data);
  return el('table', { class: 'kv metrics' }, ...rows);
}

export class MetricsKind extends ListedKind<unknown> {
  readonly kind = 'metrics';
  readonly storedFormat = 'json';

  constructor(ctx: AppContext) {
    super(ctx, slice);
  }

  protected fetch(jobId: string, name: string): Promise<unknown> {
    return fetchArtifactJson(jobId, name);
  }

  /** The metrics as a table, under the download links. */
  protected content(value: unknown): HTMLElement {
    return value === undefined ? el('p', { class: 'empty' }, 'loading…') : metricsTable(value);
  }
}
