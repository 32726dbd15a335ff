// `metrics` artifacts: a JSON object of numbers, fetched when the job is done
// and shown as a table in the job list (panels/jobs.ts).
import { fetchArtifactJson } from '../api/rest.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { describe, jobOf, type AppContext } from '../controllers/context.ts';
import { artifactKey, withEntry } from '../state/app_state.ts';
import type { ArtifactKind } from './kind.ts';

export class MetricsKind implements ArtifactKind {
  readonly kind = 'metrics';
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
