// `text` artifacts (chaos_extract's message): fetched when the job is done and
// shown in the job list. Not necessarily UTF-8: undecodable bytes show as
// U+FFFD.
import { fetchArtifactBytes } from '../api/rest.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { describe, jobOf, type AppContext } from '../controllers/context.ts';
import { artifactRow } from '../panels/artifact_row.ts';
import { el } from '../panels/dom.ts';
import type { JobsView } from '../panels/jobs.ts';
import { artifactKey, withEntry } from '../state/app_state.ts';
import type { ArtifactKind } from './kind.ts';

export class TextKind implements ArtifactKind {
  readonly kind = 'text';
  readonly storedFormat = 'txt';
  private readonly ctx: AppContext;

  constructor(ctx: AppContext) {
    this.ctx = ctx;
  }

  load(job: Job, artifact: ArtifactInfo): void {
    const { store } = this.ctx;
    const key = artifactKey(job.id, artifact.name);
    if (store.get().texts.has(key)) return;
    const set = (value: string | undefined) => store.update((s) => ({ texts: withEntry(s.texts, key, value) }));
    set(undefined);
    fetchArtifactBytes(job.id, artifact.name, 'txt').then(
      (bytes) => set(new TextDecoder('utf-8').decode(bytes)),
      (e) => set(`Cannot fetch ${artifact.name}: ${describe(e)}`),
    );
  }

  /** The text itself, under its download links. */
  row(job: Job, a: ArtifactInfo, view: JobsView): HTMLElement {
    const text = view.texts.get(artifactKey(job.id, a.name));
    // At most 2000 characters here; the links have all the bytes.
    const shown = text === undefined ? 'loading…' : text.length > 2000 ? `${text.slice(0, 2000)}…` : text;
    return artifactRow(job, a, this.storedFormat, [], el('pre', { class: 'text-content' }, shown));
  }

  rowState(job: Job, a: ArtifactInfo, view: JobsView): boolean {
    return view.texts.get(artifactKey(job.id, a.name)) !== undefined;
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
    // The text belongs to the job, whatever mesh is shown.
  }
}
