// Algorithms and jobs: the algorithm menu, submitting a job (on the selected
// mesh, or on a job's output chosen with "Run on this"), importing data other
// tools made (an import job, done at once), following progress from the
// WebSocket's job_* events, cancelling, and handing what a job made to the
// artifact kinds (kinds/registry.ts). The job list and the algorithm form
// render from the state. A job's results are named after what they were made
// from ("elephant · simplify 1000"), and a mesh run on is stored by the server
// under that name.
import { dataKindWords, needsMesh, type DataKind } from '../api/data_files.ts';
import { ApiError, cancelJob, deleteJob, getJob, listAlgorithms, listJobs, submitJob, uploadData } from '../api/rest.ts';
import { jobMeshId, takesKind, type Algorithm, type Job, type JobInput, type JobProgress, type ParamSchema } from '../api/types.ts';
import { AlgorithmsPanel } from '../panels/algorithms.ts';
import { orderedParams } from '../panels/param_control.ts';
import { byId } from '../panels/dom.ts';
import { JobsPanel } from '../panels/jobs.ts';
import { openShareForm } from '../panels/share.ts';
import { artifactKey, withEntry, selectedMesh } from '../state/app_state.ts';
import { describe, isUnauthorized, jobOf, type AppContext, meshOf } from './context.ts';
import { uploadName } from './meshes.ts';
import type { Kinds } from '../kinds/registry.ts';
import type { MeshesController } from './meshes.ts';

/** What the jobs use of the others: the artifact kinds, the mesh list. */
export interface JobsDeps {
  kinds: Pick<Kinds, 'autoShown' | 'hide' | 'load' | 'open' | 'show' | 'of'>;
  meshes: Pick<MeshesController, 'refresh' | 'select'>;
}

const FINAL = new Set(['done', 'failed', 'cancelled', 'interrupted']);
/** Jobs the page runs for itself (a plugin's build): not listed, their artifacts not fetched. */
const HIDDEN = new Set(['plugin_build']);
/** The name the server gives a mesh it stored from a job's output ("<job id>-<artifact>.ply"). */
const CHAINED_NAME = /^([0-9a-f]{16})-(.+)\.ply$/;

/** A parameter's value as a result's name shows it: "1000", "laplacian", "outward=false", "12 faces". */
function paramWords(name: string, schema: ParamSchema | undefined, value: unknown): string {
  if (Array.isArray(value)) return `${value.length} ${typeof schema?.['x-cgview-selection'] === 'string' ? schema['x-cgview-selection'] : name}`;
  if (typeof value === 'boolean') return `${name}=${value}`;
  return String(value);
}

/**
 * The value of the job's first parameter, in the algorithm's declared order,
 * that differs from its default; '' when all are default (or the algorithm is
 * not known here).
 */
export function mainParamValue(job: Pick<Job, 'params'>, algorithm: Algorithm | undefined): string {
  const properties = algorithm?.params?.properties ?? {};
  for (const name of orderedParams(algorithm?.params)) {
    const schema = properties[name];
    if (!(name in (job.params ?? {}))) continue;
    const value = job.params[name];
    if (value === undefined || JSON.stringify(value) === JSON.stringify(schema?.default)) continue;
    return paramWords(name, schema, value);
  }
  return '';
}

export class JobsController {
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: JobsDeps;
  private readonly algorithms: AlgorithmsPanel;
  /** Jobs this page submitted: their scalar field is shown when they finish. */
  private readonly autoShow = new Set<string>();
  /** Jobs asked for with GET /jobs/{id} (progress of a job not seen yet). */
  private readonly asking = new Set<string>();
  /** The algorithms the server listed last: their parameters' defaults name results. */
  private known: readonly Algorithm[] = [];

  constructor(ctx: AppContext, deps: JobsDeps) {
    this.ctx = ctx;
    this.deps = deps;
    const { store } = ctx;
    this.algorithms = new AlgorithmsPanel(byId('algorithms'), {
      run: (algorithm, params, inputs) => this.run(algorithm, params, inputs),
      cancel: (id) => void this.cancel(id),
      selection: (kind) => this.selectionFor(kind),
    });
    const panel = new JobsPanel(
      byId('jobs'),
      {
        cancel: (id) => void this.cancel(id),
        show: (jobId, artifact, kind) => void deps.kinds.show(jobId, artifact, kind),
        hide: (jobId, artifact, kind) => deps.kinds.hide(jobId, artifact, kind),
        runOn: (jobId, artifact) => this.setRunTarget(jobId, artifact),
        remove: (jobId) => void this.remove(jobId),
        share: (jobId) => openShareForm('jobs', jobId, `job ${jobOf(ctx, jobId)?.algorithm ?? ''} ${jobId.slice(0, 8)}`),
      },
      deps.kinds,
    );
    store.subscribe(
      (s) => [s.jobs, s.meshes, s.artifacts, s.compared, s.runTarget, s.me?.user, s.me?.admin],
      () => {
        const s = store.get();
        panel.render({
          jobs: [...s.jobs.values()].filter((j) => !HIDDEN.has(j.algorithm)).sort((a, b) => String(a.created ?? '').localeCompare(String(b.created ?? ''))),
          meshName: (id) => s.meshes.find((m) => m.id === id)?.name ?? null,
          compared: new Set(s.compared.map((c) => artifactKey(c.jobId, c.artifact))),
          target: s.runTarget ? artifactKey(s.runTarget.jobId, s.runTarget.artifact) : null,
          state: s,
          mayChange: (owner) => ctx.account.mayChange(owner),
          ownerName: (owner) => ctx.account.otherOwner(owner),
        });
      },
      { now: true },
    );
    // The jobs started from the form show their progress and Cancel under Run.
    store.subscribe(
      (s) => s.jobs,
      (jobs) => this.algorithms.setJobs(jobs),
      { now: true },
    );
    store.subscribe(
      (s) => s.inputName,
      (name) => this.algorithms.setMesh(name),
      { now: true },
    );
    store.subscribe(
      (s) => s.runTarget?.kind ?? null,
      (kind) => this.algorithms.setRunKind(kind),
      { now: true },
    );
    store.subscribe(
      (s) => s.meshes,
      (meshes) => this.algorithms.setMeshes(meshes.map((m) => ({ id: m.id, name: m.name }))),
    );
  }

  /** The selection changed: the form's selection parameters say its size. */
  selectionChanged(kind: string, count: number): void {
    this.algorithms.setSelection(kind, count);
  }

  /** Asks for the algorithm menu; a 404 means this server has no algorithms API. */
  async loadAlgorithms(): Promise<void> {
    const { store, hooks } = this.ctx;
    try {
      const algorithms = await listAlgorithms();
      hooks.algorithmsApi = true;
      store.update({ algorithmsApi: true });
      this.known = algorithms;
      this.algorithms.render(algorithms);
      this.algorithms.setMesh(store.get().inputName);
      await this.refresh();
    } catch (e) {
      hooks.algorithmsApi = false;
      store.update({ algorithmsApi: false });
      if (e instanceof ApiError && e.status === 404) {
        this.algorithms.unavailable('This server has no algorithms API (GET /api/v1/algorithms: 404).');
      } else if (isUnauthorized(e)) {
        this.algorithms.unavailable('Sign in to see the algorithms.');
      } else {
        this.algorithms.unavailable(`Cannot list algorithms: ${describe(e)}`);
      }
    }
  }

  /** Reloads the job list (after a reconnect, events may have been missed). */
  async refresh(): Promise<void> {
    if (this.ctx.store.get().algorithmsApi !== true) return;
    try {
      this.upsertAll(await listJobs());
    } catch (e) {
      if (!isUnauthorized(e)) this.ctx.error(`Cannot list jobs: ${describe(e)}`);
    }
  }

  /**
   * Submits a job on the selected mesh, or on the job output chosen with "Run
   * on this" (a chain: the server stores that output as a mesh of its own and
   * announces it); `extra` names the meshes of the algorithm's other inputs.
   * Resolves with the Job submitted; rejects with the server's detail (shown beside the form).
   */
  async run(algorithm: Algorithm, params: Record<string, unknown>, extra: Record<string, string> = {}): Promise<Job> {
    const { store } = this.ctx;
    const { deps } = this;
    const target = store.get().runTarget;
    const mesh = selectedMesh(this.ctx.store.get());
    // The algorithm's first input: the selected mesh, or the output chosen with "Run on this".
    const first = algorithm.inputs?.[0] ?? { name: 'mesh', kind: 'mesh' };
    if (first.kind !== 'mesh' && !takesKind(first.kind, target?.kind ?? 'mesh')) {
      throw new Error(`${algorithm.name} runs on a ${first.kind}: choose one with "Run on this" in the job list.`);
    }
    if (!target && !mesh) throw new Error('Choose a mesh first.');
    let input: JobInput = target ? { job: target.jobId, artifact: target.artifact } : mesh!.id;
    // The server stores a result run on as a mesh, under the name it has here.
    if (target?.kind === 'mesh' && first.kind === 'mesh')
      input = { job: target.jobId, artifact: target.artifact, name: uploadName(this.resultName(target.jobId, target.artifact)) };
    const inputs: Record<string, JobInput> = { ...extra, [first.name]: input };
    let job: Job;
    try {
      job = await submitJob(algorithm.name, inputs, params, algorithm.plugin);
    } catch (e) {
      throw new Error(describe(e));
    }
    if (target) {
      // A chained mesh is a stored mesh now: later runs and fields use it.
      store.update({ runTarget: null });
      const stored = typeof job.inputs.mesh === 'string' ? job.inputs.mesh : null;
      if (stored && !meshOf(this.ctx, stored)) await deps.meshes.refresh();
      if (stored) deps.meshes.select(stored);
    }
    this.autoShow.add(job.id);
    // A job_done event may have come before this answer: upsert keeps the later state.
    this.upsert(job);
    this.ctx.account.refreshSoon(); // one more job in use
    return job;
  }

  /**
   * Uploads a file another tool made (POST /data) as `kind`, for the mesh
   * shown (a voxel grid needs none, and is tied to the mesh when one is
   * shown), then shows what it became as its button in the job list would: a
   * field on the mesh, a skeleton over it, a grid's slices. The server
   * answers with the import job done; its warnings (values missing, parts of
   * the file not used) are in its entry of the job list and said in a warning.
   */
  async importFile(file: File, kind: DataKind): Promise<void> {
    const { progress } = this.ctx;
    const { deps } = this;
    const mesh = selectedMesh(this.ctx.store.get());
    if (!mesh && needsMesh(kind)) {
      return this.ctx.error(`Choose a mesh first: ${file.name} is ${dataKindWords(kind)} for the mesh shown.`);
    }
    let job: Job;
    progress.show('uploading', null, file.name);
    try {
      job = await uploadData(file.name, file, { kind, mesh: mesh?.id });
    } catch (e) {
      return this.ctx.error(`Cannot load ${file.name}: ${describe(e)}`);
    } finally {
      progress.hide();
    }
    // A job_done event may have come before this answer: upsert keeps the later state.
    this.upsert(job);
    this.ctx.account.refreshSoon(); // its files count against the caller's storage
    for (const w of job.warnings ?? []) this.ctx.warning(`${file.name}: ${w}`);
    const artifact = job.artifacts?.find((a) => a.kind === kind);
    if (artifact) await deps.kinds.show(job.id, artifact.name, artifact.kind);
  }

  /**
   * The selection to send as a job's faces or vertices parameter: its ids (the
   * stored mesh's), when it is of that kind and on the mesh the job runs on.
   */
  selectionFor(kind: string): number[] {
    const { selectionTool, store } = this.ctx;
    const state = selectionTool.state();
    if (store.get().runTarget || state.meshId !== store.get().selectedId || state.kind !== kind) return [];
    // Vertices split at attribute seams in the PLY are not the stored ones (docs/DESIGN.md).
    if (kind === 'vertices' && state.ids.length && selectionTool.vertexCount !== selectedMesh(this.ctx.store.get())?.report.vertices) {
      this.ctx.error('This mesh has seams (separate normal or UV indices): its vertex selection cannot be sent as stored ids.');
      return [];
    }
    return state.ids;
  }

  /** "Run on this": the next job's input is this job's output mesh. */
  setRunTarget(jobId: string, artifact: string): void {
    const job = jobOf(this.ctx, jobId);
    if (!job) return;
    const kind = job.artifacts?.find((a) => a.name === artifact)?.kind ?? 'mesh';
    this.ctx.store.update({ runTarget: { jobId, artifact, kind }, inputName: this.resultName(jobId, artifact) });
  }

  /**
   * What a job's result is called: "<source mesh's name> · <algorithm> <main
   * parameter value>" ("elephant · simplify 1000"), the source named without
   * its extension, the value that of the first declared parameter that
   * differs from its default (none when all are default), and the artifact's
   * name after it when the job made several of its kind.
   */
  resultName(jobId: string, artifact: string): string {
    return this.nameOf(jobId, artifact, 0);
  }

  /** The stored mesh a job's results lie over: its first input, or the source of the result it ran on. */
  sourceMeshOf(jobId: string): string | null {
    for (let depth = 0, job = jobOf(this.ctx, jobId); job && depth < 8; ++depth) {
      const input = job.inputs?.[this.firstInput(job)];
      if (typeof input === 'string') return input;
      job = input ? jobOf(this.ctx, input.job) : undefined;
    }
    return null;
  }

  private nameOf(jobId: string, artifact: string, depth: number): string {
    const job = jobOf(this.ctx, jobId);
    if (!job) return artifact;
    const value = mainParamValue(job, this.algorithmOf(job));
    const kind = job.artifacts?.find((a) => a.name === artifact)?.kind;
    const several = (job.artifacts ?? []).filter((a) => a.kind === kind).length > 1;
    const input = job.inputs?.[this.firstInput(job)];
    let source = 'mesh';
    // A chain's depth is bounded so that a cycle of jobs (never made by the server) cannot hang the page.
    if (typeof input === 'string') source = this.meshStem(input, depth);
    else if (input && depth < 8) source = this.nameOf(input.job, input.artifact, depth + 1);
    return `${source} · ${job.algorithm}${value ? ` ${value}` : ''}${several ? ` ${artifact}` : ''}`;
  }

  /** A stored mesh's name without its extension; one the server named after a job ("<job id>-mesh.ply") is named as that job's result. */
  private meshStem(meshId: string, depth: number): string {
    const mesh = meshOf(this.ctx, meshId);
    if (!mesh?.name) return 'mesh';
    const name = mesh.name;
    const chained = CHAINED_NAME.exec(name);
    if (chained && depth < 8 && jobOf(this.ctx, chained[1]!)) return this.nameOf(chained[1]!, chained[2]!, depth + 1);
    // The extension of the stored format (the server's Mesh.format); a result's name ("elephant · smooth 0.5") has none to strip.
    const extension = `.${mesh.format}`;
    return (name.toLowerCase().endsWith(extension.toLowerCase()) ? name.slice(0, -extension.length) : name) || name;
  }

  private algorithmOf(job: Job): Algorithm | undefined {
    return this.known.find((a) => a.name === job.algorithm);
  }

  /** The name of the job's first input ("mesh" for most algorithms, "grid" for grid_surface). */
  private firstInput(job: Job): string {
    return this.algorithmOf(job)?.inputs?.[0]?.name ?? ('mesh' in (job.inputs ?? {}) ? 'mesh' : (Object.keys(job.inputs ?? {})[0] ?? 'mesh'));
  }

  /**
   * Opens a job's result as its row in the job list would (the job asked for
   * first when the page does not know it ended: one shared with the caller,
   * a graded run the staff open from the Course panel): the artifact named,
   * else the job's first. Rejects, saying why, when it has none to show.
   */
  async openResult(jobId: string, artifact?: string): Promise<void> {
    const { deps } = this;
    let job = jobOf(this.ctx, jobId);
    if (!job || !FINAL.has(job.state)) {
      job = await getJob(jobId);
      this.upsert(job);
    }
    if (job.state !== 'done') throw new Error(`its job is ${job.state}${job.error ? `: ${job.error}` : ''}`);
    const a = job.artifacts?.find((x) => x.name === artifact) ?? job.artifacts?.[0];
    if (!a) throw new Error('its job made nothing to show');
    await deps.kinds.open(job, a);
  }

  async cancel(id: string): Promise<void> {
    try {
      this.upsert(await cancelJob(id));
    } catch (e) {
      this.ctx.error(`Cannot cancel the job: ${describe(e)}`);
      void getJob(id).then(
        (j) => this.upsert(j),
        () => {},
      );
    }
  }

  /** Deletes an ended job: what of it is shown is hidden first, then it leaves the list. */
  async remove(id: string): Promise<void> {
    const { store } = this.ctx;
    const { deps } = this;
    const job = store.get().jobs.get(id);
    try {
      await deleteJob(id);
    } catch (e) {
      this.ctx.error(`Cannot delete the job: ${describe(e)}`);
      return;
    }
    for (const a of job?.artifacts ?? []) deps.kinds.hide(id, a.name, a.kind);
    const next = new Map(store.get().jobs);
    next.delete(id);
    store.update({ jobs: next });
  }

  /** Merges a Job in; a finished job never goes back to queued or running (events and answers may cross). */
  upsert(job: Job): void {
    this.upsertAll([job]);
  }

  /** Merges Jobs in, as upsert does, with one update of the state. */
  private upsertAll(jobs: readonly Job[]): void {
    const { store } = this.ctx;
    const next = new Map(store.get().jobs);
    const merged: Job[] = [];
    const ended: Job[] = [];
    for (const job of jobs) {
      const old = next.get(job.id);
      if (old && FINAL.has(old.state) && !FINAL.has(job.state)) {
        // Its end came first (a small job's job_done event before the answer to its submission): what a run of this page shows when it ends is due now.
        ended.push(old);
        continue;
      }
      const m = { ...old, ...job };
      next.set(job.id, m);
      merged.push(m);
    }
    if (merged.length) store.update({ jobs: next });
    for (const m of merged) this.settled(m);
    for (const m of ended) this.ranHere(m);
  }

  /** What a job's new state brings: a done job's artifacts to their kinds, and what a run of this page shows when it ends. */
  private settled(job: Job): void {
    if (HIDDEN.has(job.algorithm)) return;
    if (job.state === 'done') this.deps.kinds.load(job);
    this.ranHere(job);
  }

  /** What a job submitted here shows once it has ended: done, its kinds' autoShow (a scalar field, else a vector field); failed, its error. */
  private ranHere(job: Job): void {
    if (HIDDEN.has(job.algorithm) || !FINAL.has(job.state) || !this.autoShow.delete(job.id)) return;
    if (job.state === 'done') {
      // A run of this page that succeeds: the failure of an earlier one of the same algorithm on the same mesh no longer holds.
      this.ctx.dismiss(failureTopic(job));
      const field = this.deps.kinds.autoShown(job);
      if (field) void this.deps.kinds.show(job.id, field.name, field.kind);
    } else if (job.state === 'failed') {
      this.ctx.error(`${job.algorithm} failed: ${job.error ?? 'no reason given'}`, failureTopic(job));
    }
  }

  /** A job_progress event. */
  progress(p: JobProgress): void {
    const old = jobOf(this.ctx, p.id);
    if (!old) {
      // A job from another client that this page has not seen yet: ask for it once.
      if (this.asking.has(p.id)) return;
      this.asking.add(p.id);
      void getJob(p.id)
        .then(
          (j) => this.upsert(j),
          () => {},
        )
        .finally(() => this.asking.delete(p.id));
      return;
    }
    if (FINAL.has(old.state)) return;
    this.ctx.store.update((s) => ({ jobs: withEntry(s.jobs, p.id, { ...old, state: p.state, progress: p.progress, stage: p.stage }) }));
  }
}

/** The topic of a job's failure message: its algorithm on its mesh (a later run there that succeeds takes it away). */
function failureTopic(job: Job): string {
  return `job-failed:${job.algorithm}:${jobMeshId(job) ?? ''}`;
}
