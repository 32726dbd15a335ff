// The job panel: every job, newest first, with its algorithm and mesh, state,
// stage and a live progress bar (updated from the WebSocket's job_* events),
// a cancel button while it is queued or running, and for a finished job its
// warnings (what the algorithm or an import says the user must know) and its
// artifacts, each in the row its kind builds (kinds/*.ts, found through the
// registry: scalar fields shown or compared, meshes added to the view or run
// on, metrics as a table...); a kind this viewer does not know gets a row of
// its name and download links.
import { jobMeshId } from '../api/types.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import type { ArtifactKind } from '../kinds/kind.ts';
import type { AppState } from '../state/app_state.ts';
import { artifactRow } from './artifact_row.ts';
import { el } from './dom.ts';

export interface JobsActions {
  cancel(id: string): void;
  /**
   * Shows an artifact by its kind (kinds/registry.ts): a scalar field on its
   * mesh, a mesh beside its input, a skeleton or a vector field over its
   * mesh, an animation with the player, a voxel grid's slices.
   */
  show(jobId: string, artifact: string, kind: string): void;
  /** Stops showing an artifact (a skeleton's second click, a vector field's Hide). */
  hide(jobId: string, artifact: string, kind: string): void;
  /** Makes a mesh or voxel-grid artifact the input of the next job (the algorithm form runs on it). */
  runOn(jobId: string, artifact: string): void;
  /** Opens the share form on a job (its state and artifacts, read-only for those it is shared with). */
  share(jobId: string): void;
  /** Deletes an ended job and its results (what of it is shown goes too). */
  remove(jobId: string): void;
}

export interface JobsView {
  jobs: readonly Job[];
  /** Mesh names by id (a job's input may have been deleted since). */
  meshName(id: string): string | null;
  /** The fields compared side by side now, as `${jobId}/${name}`. */
  compared: ReadonlySet<string>;
  /** The artifact the next job runs on (`${jobId}/${name}`), if one was chosen. */
  target: string | null;
  /** The state the list is built from: each kind's row reads its own part of it (kinds/slice.ts). */
  state: Readonly<AppState>;
  /** Whether the user may share a job of that owner. */
  mayChange(owner: string | undefined): boolean;
  /** The owner to name beside a job: another user's (a student's run, shared with the staff), else null. */
  ownerName?(owner: string | undefined): string | null;
}

/** The artifact kinds' modules by the server's kind string (kinds/registry.ts). */
export interface ArtifactKinds {
  of(kind: string): ArtifactKind | undefined;
}

/** A kind this viewer does not know, from an older server that lists no formats, is offered as JSON, the format most kinds serve. */
const UNKNOWN_KIND_FORMAT = 'json';

const ACTIVE = new Set(['queued', 'running']);

export class JobsPanel {
  private readonly root: HTMLElement;
  private readonly actions: JobsActions;
  private readonly kinds: ArtifactKinds;

  constructor(root: HTMLElement, actions: JobsActions, kinds: ArtifactKinds) {
    this.root = root;
    this.actions = actions;
    this.kinds = kinds;
  }

  // Items by job id with what they were built from: progress events (up to
  // about 10 a second per job) only update the bar and the texts of an item,
  // so that its buttons stay the same elements under the pointer.
  private readonly items = new Map<string, { signature: string; li: HTMLElement }>();
  private list: HTMLUListElement | null = null;
  private order = '';

  render(view: JobsView): void {
    if (view.jobs.length === 0) {
      this.items.clear();
      this.list = null;
      this.order = '';
      this.root.replaceChildren(el('p', { class: 'empty' }, 'No jobs yet.'));
      return;
    }
    const jobs = [...view.jobs].reverse();
    const seen = new Set<string>();
    const lis = jobs.map((job) => {
      seen.add(job.id);
      const signature = this.signature(job, view);
      const old = this.items.get(job.id);
      if (old && old.signature === signature) {
        this.update(old.li, job);
        return old.li;
      }
      const li = this.item(job, view);
      if (old) old.li.replaceWith(li);
      this.items.set(job.id, { signature, li });
      return li;
    });
    for (const id of [...this.items.keys()]) if (!seen.has(id)) this.items.delete(id);
    const order = jobs.map((j) => j.id).join(' ');
    if (!this.list || order !== this.order || !this.root.contains(this.list)) {
      this.list = el('ul', { class: 'job-list' }, ...lis);
      this.root.replaceChildren(this.list);
      this.order = order;
    }
  }

  private signature(job: Job, view: JobsView): string {
    const meshId = jobMeshId(job);
    const mesh = meshId ? view.meshName(meshId) : null;
    const artifacts = (job.artifacts ?? []).map((a) => [a.name, a.kind, a.formats ?? null, a.bytes ?? null, this.kinds.of(a.kind)?.rowState(job, a, view) ?? null]);
    return JSON.stringify([job.state, job.cached, job.error, job.warnings ?? [], mesh, view.mayChange(job.owner), view.ownerName?.(job.owner) ?? null, artifacts]);
  }

  /** The parts that progress events change. */
  private update(li: HTMLElement, job: Job): void {
    const fraction = Math.min(1, Math.max(0, job.state === 'done' ? 1 : job.progress || 0));
    const bar = li.querySelector<HTMLProgressElement>('progress.job-progress');
    if (bar) bar.value = fraction;
    const stage = li.querySelector('.job-stage');
    if (stage) stage.textContent = job.stage || '';
    const percent = li.querySelector('.job-percent');
    if (percent) percent.textContent = `${Math.floor(fraction * 100)}%`;
  }

  private item(job: Job, view: JobsView): HTMLElement {
    const meshId = jobMeshId(job);
    const mesh = meshId ? (view.meshName(meshId) ?? meshId.slice(0, 8)) : '';
    const fraction = Math.min(1, Math.max(0, job.state === 'done' ? 1 : job.progress || 0));
    const bar = el('progress', { max: '1', class: 'job-progress' });
    bar.value = fraction;
    const head = el(
      'div',
      { class: 'job-head' },
      el('span', { class: 'job-title', title: `${job.algorithm} ${JSON.stringify(job.params ?? {})}` }, job.algorithm),
      el('span', { class: `job-state state-${job.state}` }, job.cached ? `${job.state} (cached)` : job.state),
    );
    const owner = view.ownerName?.(job.owner) ?? null;
    const status = el(
      'div',
      { class: 'job-status' },
      owner ? el('span', { class: 'job-owner', title: `${owner}'s job` }, owner) : null,
      el('span', { class: 'job-mesh' }, mesh),
      el('span', { class: 'job-stage' }, job.stage || ''),
      el('span', { class: 'job-percent' }, `${Math.floor(fraction * 100)}%`),
    );
    const li = el('li', { class: 'job', 'data-job-id': job.id, 'data-algorithm': job.algorithm, 'data-state': job.state }, head, status, bar);
    if (ACTIVE.has(job.state)) {
      const cancel = el('button', { type: 'button', class: 'button small cancel', title: 'Cancel this job' }, 'Cancel');
      cancel.addEventListener('click', () => {
        cancel.disabled = true;
        this.actions.cancel(job.id);
      });
      li.append(el('div', { class: 'job-actions' }, cancel));
    }
    if (view.mayChange(job.owner)) {
      const share = el('button', { type: 'button', class: 'button small share', title: 'Share this job and its results' }, 'Share…');
      share.addEventListener('click', () => this.actions.share(job.id));
      const actions = el('div', { class: 'job-actions' }, share);
      if (!ACTIVE.has(job.state)) {
        const remove = el('button', { type: 'button', class: 'button small delete', title: 'Delete this job and its results' }, 'Delete');
        remove.addEventListener('click', () => {
          remove.disabled = true;
          this.actions.remove(job.id);
        });
        actions.append(remove);
      }
      li.append(actions);
    }
    if (job.error) li.append(el('p', { class: 'job-error' }, job.error));
    if (job.state === 'done') {
      const warnings = job.warnings ?? [];
      if (warnings.length) li.append(el('ul', { class: 'warnings job-warnings' }, ...warnings.map((w) => el('li', {}, w))));
      const artifacts = job.artifacts ?? [];
      for (const kind of new Set(artifacts.map((a) => a.kind))) {
        const controls = this.kinds.of(kind)?.jobControls?.(job);
        if (controls) li.append(controls);
      }
      for (const a of artifacts) li.append(this.artifact(job, a, view));
    }
    return li;
  }

  /** The artifact's row, built by its kind's module; a kind this viewer does not know offers its downloads. */
  private artifact(job: Job, a: ArtifactInfo, view: JobsView): HTMLElement {
    const kind = this.kinds.of(a.kind);
    return kind ? kind.row(job, a, view, this.actions) : artifactRow(job, a, UNKNOWN_KIND_FORMAT);
  }
}
