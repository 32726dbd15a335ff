// One module per kind of artifact (Polyscope's one class per quantity): it
// loads, shows, hides and disposes what a job made of that kind. The registry
// (registry.ts) maps the server's kind string to its module, so a new kind is
// one file here and one line there.
import type { ArtifactInfo, Job } from '../api/types.ts';

export interface ArtifactKind {
  /** The server's artifact kind this module handles (protocol/API.md, a Job's artifacts). */
  readonly kind: string;
  /** A job with an artifact of this kind is done: fetches what the job list shows of it (most kinds fetch on show). */
  load(job: Job, artifact: ArtifactInfo): void;
  /** Draws or opens the artifact: its button in the job list. Resolves once it is shown (or has failed, with an error shown). */
  show(jobId: string, artifact: string): Promise<void>;
  /** Stops drawing the artifact, if it is drawn. */
  hide(jobId: string, artifact: string): void;
  /** Another mesh is chosen, or the one shown is gone: forgets what is drawn of this kind on it. */
  dispose(): void;
}
