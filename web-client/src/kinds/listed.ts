// Kinds shown in the job list itself rather than drawn in the view (text,
// metrics): the artifact is fetched once its job is done, kept in the
// application state (the kind's part: kinds/slice.ts) by `${jobId}/${name}`, and shown under its row's
// download links. A subclass says how to fetch it and how to show it.
import type { ArtifactInfo, Job } from '../api/types.ts';
import { describe, jobOf, type AppContext } from '../controllers/context.ts';
import { artifactRow } from '../panels/artifact_row.ts';
import type { JobsView } from '../panels/jobs.ts';
import { artifactKey, withEntry } from '../state/app_state.ts';
import type { ArtifactKind } from './kind.ts';
import type { KindSlice } from './slice.ts';

/** What a listed kind fetched, by `${jobId}/${name}` (undefined: loading; a string: the error sentence, for metrics). */
export type Listed = ReadonlyMap<string, unknown>;

export abstract class ListedKind<T> implements ArtifactKind {
  abstract readonly kind: string;
  abstract readonly storedFormat: string;
  protected readonly ctx: AppContext;
  private readonly slice: KindSlice<Listed>;

  constructor(ctx: AppContext, slice: KindSlice<Listed>) {
    this.ctx = ctx;
    this.slice = slice;
  }

  /** The artifact as the row shows it. */
  protected abstract fetch(jobId: string, name: string): Promise<T>;
  /** What the row shows under its links: `value` undefined while loading, or an error sentence. */
  protected abstract content(value: T | string | undefined): HTMLElement;

  load(job: Job, artifact: ArtifactInfo): void {
    const { store } = this.ctx;
    const key = artifactKey(job.id, artifact.name);
    if (this.slice.get(store.get()).has(key)) return;
    const set = (value: unknown) => this.slice.set(store, (entries) => withEntry(entries, key, value));
    set(undefined);
    this.fetch(job.id, artifact.name).then(
      (value) => set(value),
      (e) => set(`Cannot fetch ${artifact.name}: ${describe(e)}`),
    );
  }

  row(job: Job, a: ArtifactInfo, view: JobsView): HTMLElement {
    const value = this.slice.get(view.state).get(artifactKey(job.id, a.name)) as T | string | undefined;
    return artifactRow(job, a, this.storedFormat, [], this.content(value));
  }

  rowState(job: Job, a: ArtifactInfo, view: JobsView): boolean {
    return this.slice.get(view.state).get(artifactKey(job.id, a.name)) !== undefined;
  }

  async show(jobId: string, artifact: string): Promise<void> {
    const job = jobOf(this.ctx, jobId);
    const info = job?.artifacts?.find((a) => a.name === artifact);
    if (job && info) this.load(job, info);
  }

  hide(): void {
    // Shown in the job list: nothing is drawn in the view.
  }

  dispose(): void {
    // It belongs to the job, whatever mesh is shown.
  }
}
