// `text` artifacts (chaos_extract's message): fetched when the job is done and
// shown in the job list. Not necessarily UTF-8: undecodable bytes show as
// U+FFFD.
import { fetchArtifactBytes } from '../api/rest.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { describe, jobOf, type AppContext } from '../controllers/context.ts';
import { artifactKey, withEntry } from '../state/app_state.ts';
import type { ArtifactKind } from './kind.ts';

export class TextKind implements ArtifactKind {
  readonly kind = 'text';
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
