// The job panel: every job, newest first, with its algorithm and mesh, state,
// stage and a live progress bar (updated from the WebSocket's job_* events),
// a cancel button while it is queued or running, and for a finished job its
// artifacts: scalar fields can be shown on the mesh or compared side by side
// ("Compare" shows every field of the job, "Add to comparison" adds one field
// of any job on the same mesh), metrics are a table,
// meshes can be added to the view beside their input, downloaded, or made the
// input of the next job ("Run on this": a chain, API.md "Jobs chain").
import { artifactUrl } from '../api/rest.ts';
import { jobMeshId } from '../api/types.ts';
import type { ArtifactInfo, Job } from '../api/types.ts';
import { el } from './dom.ts';
import { formatValue } from './format.ts';

export interface JobsActions {
  cancel(id: string): void;
  /**
   * Shows an artifact by its kind (kinds/registry.ts): a scalar field on its
   * mesh, a mesh beside its input, a skeleton over its mesh, an animation
   * with the player, a voxel grid's slices.
   */
  show(jobId: string, artifact: string, kind: string): void;
  /** Stops showing an artifact (a skeleton's second click). */
  hide(jobId: string, artifact: string, kind: string): void;
  /** Shows every scalar_field artifact of the job side by side, in synchronized views. */
  compare(jobId: string): void;
  /** Adds a scalar_field artifact to the fields compared side by side (or to the one shown). */
  addToComparison(jobId: string, artifact: string): void;
  /** Makes a mesh or voxel-grid artifact the input of the next job (the algorithm form runs on it). */
  runOn(jobId: string, artifact: string): void;
  /** Opens the share form on a job (its state and artifacts, read-only for those it is shared with). */
  share(jobId: string): void;
}

export interface JobsView {
  jobs: readonly Job[];
  /** Mesh names by id (a job's input may have been deleted since). */
  meshName(id: string): string | null;
  /** The field shown now: job id and artifact name. */
  shown: { jobId: string; artifact: string } | null;
  /** The fields compared side by side now, as `${jobId}/${name}`. */
  compared: ReadonlySet<string>;
  /** Mesh artifacts in the view, as `${jobId}/${name}`. */
  added: ReadonlySet<string>;
  /** The mesh artifact the next job runs on (`${jobId}/${name}`), if one was chosen. */
  target: string | null;
  /** Fetched metrics artifacts, by `${jobId}/${name}`: the JSON, or an error sentence. */
  metrics: ReadonlyMap<string, unknown>;
  /** Fetched text artifacts (chaos_extract's message), by `${jobId}/${name}`: the text, or undefined while loading. */
  texts: ReadonlyMap<string, string | undefined>;
  /** Skeleton artifacts drawn now, by `${jobId}/${name}`: their colour. */
  skeletons: ReadonlyMap<string, string>;
  /** Whether the user may share a job of that owner. */
  mayChange(owner: string | undefined): boolean;
}

const ACTIVE = new Set(['queued', 'running']);

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

export class JobsPanel {
  private readonly root: HTMLElement;
  private readonly actions: JobsActions;

  constructor(root: HTMLElement, actions: JobsActions) {
    this.root = root;
    this.actions = actions;
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
    const shown = view.shown?.jobId === job.id ? view.shown.artifact : '';
    const metrics = (job.artifacts ?? [])
      .map((a) => (view.metrics.get(`${job.id}/${a.name}`) === undefined && view.texts.get(`${job.id}/${a.name}`) === undefined ? 0 : 1))
      .join('');
    const added = (job.artifacts ?? [])
      .map((a) => (view.added.has(`${job.id}/${a.name}`) ? 1 : 0) + (view.compared.has(`${job.id}/${a.name}`) ? 2 : 0))
      .join('');
    const skeletons = (job.artifacts ?? []).map((a) => view.skeletons.get(`${job.id}/${a.name}`) ?? '').join(',');
    return JSON.stringify([job.state, job.cached, job.error, mesh, shown, metrics, added, skeletons, job.artifacts?.length ?? 0]);
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
    const mesh = meshId ? view.meshName(meshId) ?? meshId.slice(0, 8) : '';
    const fraction = Math.min(1, Math.max(0, job.state === 'done' ? 1 : job.progress || 0));
    const bar = el('progress', { max: '1', class: 'job-progress' });
    bar.value = fraction;
    const head = el(
      'div',
      { class: 'job-head' },
      el('span', { class: 'job-title', title: `${job.algorithm} ${JSON.stringify(job.params ?? {})}` }, job.algorithm),
      el('span', { class: `job-state state-${job.state}` }, job.cached ? `${job.state} (cached)` : job.state),
    );
    const status = el(
      'div',
      { class: 'job-status' },
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
      li.append(el('div', { class: 'job-actions' }, share));
    }
    if (job.error) li.append(el('p', { class: 'job-error' }, job.error));
    if (job.state === 'done') {
      if ((job.artifacts ?? []).filter((a) => a.kind === 'scalar_field').length >= 2) {
        const compare = el('button', { type: 'button', class: 'button small compare', title: "Show this job's fields side by side" }, 'Compare');
        compare.addEventListener('click', () => this.actions.compare(job.id));
        li.append(el('div', { class: 'job-actions' }, compare));
      }
      for (const a of job.artifacts ?? []) li.append(this.artifact(job, a, view));
    }
    return li;
  }

  /** "Run on this": the artifact (a mesh, a voxel grid) becomes the next job's input. */
  private runOnButton(job: Job, a: ArtifactInfo, view: JobsView): HTMLButtonElement {
    const targeted = view.target === `${job.id}/${a.name}`;
    const runOn = el('button', { type: 'button', class: targeted ? 'button small run-on active' : 'button small run-on', title: 'Run the next algorithm on this result' }, targeted ? 'Input of next run' : 'Run on this');
    runOn.disabled = targeted;
    runOn.addEventListener('click', () => this.actions.runOn(job.id, a.name));
    return runOn;
  }

  private artifact(job: Job, a: ArtifactInfo, view: JobsView): HTMLElement {
    const row = el('div', { class: `artifact artifact-${a.kind}`, 'data-artifact': a.name });
    const label = el('span', { class: 'artifact-name', title: a.kind }, a.name);
    if (a.kind === 'scalar_field') {
      const shown = view.shown?.jobId === job.id && view.shown.artifact === a.name;
      const show = el('button', { type: 'button', class: shown ? 'button small show active' : 'button small show' }, shown ? 'Shown' : 'Show');
      show.addEventListener('click', () => this.actions.show(job.id, a.name, a.kind));
      const compared = view.compared.has(`${job.id}/${a.name}`);
      const add = el('button', { type: 'button', class: compared ? 'button small compare-add active' : 'button small compare-add', title: 'Show beside the fields compared now (or the one shown)' }, compared ? 'Compared' : 'Add to comparison');
      add.disabled = compared;
      add.addEventListener('click', () => this.actions.addToComparison(job.id, a.name));
      row.append(label, show, add, el('a', { href: artifactUrl(job.id, a.name, 'csv'), download: '' }, 'csv'));
    } else if (a.kind === 'mesh') {
      const added = view.added.has(`${job.id}/${a.name}`);
      const add = el('button', { type: 'button', class: added ? 'button small add active' : 'button small add' }, added ? 'Added' : 'Add to view');
      add.disabled = added;
      add.addEventListener('click', () => this.actions.show(job.id, a.name, a.kind));
      row.append(label, add, ' ', this.runOnButton(job, a, view), ' ', el('a', { href: artifactUrl(job.id, a.name, 'ply'), download: '' }, 'ply'), ' ', el('a', { href: artifactUrl(job.id, a.name, 'obj'), download: '' }, 'obj'));
    } else if (a.kind === 'animation') {
      const play = el('button', { type: 'button', class: 'button small play-animation' }, 'Play');
      play.addEventListener('click', () => this.actions.show(job.id, a.name, a.kind));
      row.append(label, play, ' ', el('a', { href: artifactUrl(job.id, a.name, 'frames'), download: '' }, 'frames'));
    } else if (a.kind === 'text') {
      row.append(label, ' ', el('a', { href: artifactUrl(job.id, a.name, 'txt'), download: '' }, 'txt'));
      const text = view.texts.get(`${job.id}/${a.name}`);
      // At most 2000 characters here; the link has all the bytes.
      const shown = text === undefined ? 'loading…' : text.length > 2000 ? `${text.slice(0, 2000)}…` : text;
      row.append(el('pre', { class: 'text-content' }, shown));
    } else if (a.kind === 'voxel_grid') {
      const slices = el('button', { type: 'button', class: 'button small slices' }, 'Slices');
      slices.addEventListener('click', () => this.actions.show(job.id, a.name, a.kind));
      row.append(label, slices, ' ', this.runOnButton(job, a, view));
      for (const f of ['nrrd', 'vti', 'binvox']) row.append(' ', el('a', { href: artifactUrl(job.id, a.name, f), download: '' }, f));
    } else if (a.kind === 'metrics') {
      row.append(label);
      const data = view.metrics.get(`${job.id}/${a.name}`);
      row.append(data === undefined ? el('p', { class: 'empty' }, 'loading…') : metricsTable(data));
    } else if (a.kind === 'skeleton') {
      const color = view.skeletons.get(`${job.id}/${a.name}`);
      const show = el(
        'button',
        { type: 'button', class: color ? 'button small show-skeleton active' : 'button small show-skeleton' },
        color ? 'Shown' : 'Show',
      );
      show.addEventListener('click', () => (color ? this.actions.hide(job.id, a.name, a.kind) : this.actions.show(job.id, a.name, a.kind)));
      row.append(label, show);
      if (color) row.append(' ', el('span', { class: 'swatch', style: `background:${color}`, title: color }));
      for (const f of ['obj', 'cg', 'polylines', 'json']) row.append(' ', el('a', { href: artifactUrl(job.id, a.name, f), download: '' }, f));
    } else {
      row.append(label, ' ', el('a', { href: artifactUrl(job.id, a.name, 'json'), download: '' }, 'json'));
    }
    return row;
  }
}
