// One module per kind of artifact (Polyscope's one class per quantity): it
// loads, shows, hides and disposes what a job made of that kind, and builds
// its row in the job list. The registry (registry.ts) maps the server's kind
// string to its module, so a new kind is one file here and one line there.
import type { ArtifactInfo, Job } from '../api/types.ts';
import type { JobsActions, JobsView } from '../panels/jobs.ts';
import type { DataKind } from '../api/data_files.ts';
import type { CompareController } from '../controllers/compare.ts';
import type { MeshLoader } from '../controllers/mesh_loader.ts';
import type { MeshesController } from '../controllers/meshes.ts';
import type { SceneController } from '../controllers/scene.ts';

/**
 * What of the controllers the kinds use: each kind's module is made with it
 * (kinds/registry.ts). The loader, the mesh list and the scene are made
 * before the kinds; the comparison and the jobs after them (they use the
 * kinds), so what the kinds ask of those is called back.
 */
export interface KindDeps {
  loader: Pick<MeshLoader, 'showing' | 'ply' | 'decode'>;
  meshes: Pick<MeshesController, 'select' | 'selectMeshOf'>;
  scene: Pick<SceneController, 'addResult' | 'removeResult'>;
  /** Leaves the comparison, if one is shown. */
  leaveComparison(): void;
  /** Artifacts of the selected mesh drawn as objects side by side (CompareController.compareObjects). */
  compareObjects: CompareController['compareObjects'];
  /** Every scalar field of the job side by side. */
  compareJob(jobId: string): void;
  /** A field added to the comparison as a pane. */
  addToComparison(jobId: string, artifact: string): void;
  /** Imports another tool's data file for the mesh shown (an import job). */
  importFile(file: File, kind: DataKind): Promise<void>;
  /** A job this page submitted itself (a skeleton's distance), listed and followed as any. */
  upsertJob(job: Job): void;
}

export interface ArtifactKind {
  /** The server's artifact kind this module handles (protocol/API.md, a Job's artifacts). */
  readonly kind: string;
  /** The format the server stores this kind in: the one download offered when a Job lists no `formats` (an older server). */
  readonly storedFormat: string;
  /** A job with an artifact of this kind is done: fetches what the job list shows of it (most kinds fetch on show). */
  load(job: Job, artifact: ArtifactInfo): void;
  /** Draws or opens the artifact: its button in the job list. Resolves once it is shown (or has failed, with an error shown). */
  show(jobId: string, artifact: string): Promise<void>;
  /** Opens the artifact from elsewhere than its row (a graded run from the Course panel); default: show(). */
  open?(job: Job, artifact: string): Promise<void>;
  /** Shows the artifact when the job this page ran ends, before kinds of a later rank (lower first); none: not shown by itself. */
  readonly autoShow?: number;
  /** Stops drawing the artifact, if it is drawn. */
  hide(jobId: string, artifact: string): void;
  /** The artifacts of this kind drawn or open now, as `${jobId}/${artifact}` keys, which view links keep (`show=`); none: this kind is not kept. */
  shownKeys?(): string[];
  /** Another mesh is chosen, or the one shown is gone: forgets what is drawn of this kind on it. */
  dispose(): void;
  /**
   * The artifact's row in the job list (panels/artifact_row.ts): its name,
   * this kind's buttons and what it shows, and a download link per format.
   */
  row(job: Job, artifact: ArtifactInfo, view: JobsView, actions: JobsActions): HTMLElement;
  /**
   * What the row is built from besides the Job, as JSON can write it: the job
   * list builds the row again only when this changes, so that progress events
   * leave its buttons the same elements under the pointer.
   */
  rowState(job: Job, artifact: ArtifactInfo, view: JobsView): unknown;
  /** Buttons this kind adds to a done job as a whole (the fields' Compare), or null. */
  jobControls?(job: Job): HTMLElement | null;
}
