// `metrics` artifacts: a JSON object of numbers, fetched when the job is done
// and shown as a table in its row of the job list.
import { fetchArtifactJson } from '../api/rest.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { describe, jobOf, type AppContext } from '../controllers/context.ts';
import { artifactRow } from '../panels/artifact_row.ts';
import { el } from '../panels/dom.ts';
import { formatValue } from '../panels/format.ts';
import type { JobsView } from '../panels/jobs.ts';
import { artifactKey, withEntry } from '../state/app_state.ts';
import type { ArtifactKind } from './kind.ts';

/** The metrics as a table of name and value (a nested object's names joined), or the error sentence fetching them gave. */
function metricsTable(data: unknown): HTMLElement {
  if (typeof data === 'string') return el('p', { class: 'form-error' }, data);
  const rows: HTMLTableRowElement[] = [];
  const add = (prefix: string, value: unknown) => {
    if (value && typeof value === 'object' && !Array.isArray(value)) {
      for (const [k, v] of Object.entries(value as Record<string, unknown>)) add(prefix ? `${prefix} ${k}` : k, v);
    } else {
      rows.push(el('tr', {}, el('th', { scope: 'row' }, prefix.replace(/_/g, ' ')), el('td', {}, formatValue(value))));
    }
  };
  add('', data);
  return el('table', { class: 'kv metrics' }, ...rows);
}

export class MetricsKind implements ArtifactKind {
  readonly kind = 'metrics';
  readonly storedFormat = 'json';
  private readonly ctx: AppContext;

  constructor(ctx: AppContext) {
    this.ctx = ctx;
  }

  load(job: Job, artifact: ArtifactInfo): void {
    const { store } = this.ctx;
    const key = artifactKey(job.id, artifact.name);
    if (store.get().metrics.has(key)) return;
    const set = (value: unknown) => store.update((s) => ({ metrics: withEntry(s.metrics, key, value) }));
    set(undefined);
    fetchArtifactJson(job.id, artifact.name).then(
      (data) => set(data),
      (e) => set(`Cannot fetch ${artifact.name}: ${describe(e)}`),
    );
  }

  /** The metrics as a table, under the download links. */
  row(job: Job, a: ArtifactInfo, view: JobsView): HTMLElement {
    const data = view.metrics.get(artifactKey(job.id, a.name));
    return artifactRow(job, a, this.storedFormat, [], data === undefined ? el('p', { class: 'empty' }, 'loading…') : metricsTable(data));
  }

  rowState(job: Job, a: ArtifactInfo, view: JobsView): boolean {
    return view.metrics.get(artifactKey(job.id, a.name)) !== undefined;
  }

  async show(jobId: string, artifact: string): Promise<void> {
    const job = jobOf(this.ctx, jobId);
    const info = job?.artifacts?.find((a) => a.name === artifact);
    if (job && info) this.load(job, info);
  }

  hide(): void {
    // A table in the job list: nothing is drawn in the view.
  }

  dispose(): void {
    // The table belongs to the job, whatever mesh is shown.
  }
}
