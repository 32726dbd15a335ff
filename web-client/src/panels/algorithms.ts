// The algorithm menu and, for the chosen algorithm, a form generated from its
// params JSON Schema (API.md "Algorithms and jobs"): integer / number → a
// number input with min, max, step and the default; boolean → a checkbox;
// enum → a select; string → a text input; a selection (an array with
// x-cgview-selection: faces or vertices) → "use current selection (N faces)",
// which sends the viewer's selection's ids. Titles are the labels,
// descriptions the help text. The fields come in the algorithm's declared
// order (x-cgview-order), those marked x-cgview-advanced folded under
// "Advanced", and one with x-cgview-when only shown, and sent, while the
// parameter it names has one of the values listed. Run submits a job on the
// selected mesh; the server's validation errors (400 detail) are shown beside
// the form. While a job started here is queued or running, its stage,
// percentage, bar and a Cancel button sit under Run (where the student
// looks: the job list may be below the fold), updated from the same job_*
// events as the job list, and Run reads "Running…" (aria-busy) and is
// disabled for that same request; changed parameters, another algorithm or
// another mesh may be run meanwhile, as a notebook queues cells (the server
// queues jobs; an identical second click would only queue a duplicate). An
// algorithm of several inputs (hausdorff's `reference`) gets a mesh chooser
// for each input after the first.
//
// The menu is grouped by the algorithms' area, narrowed by a search box, and,
// once a job's output is chosen with "Run on this", holds only the
// algorithms whose first input is of that output's kind. Nothing here knows
// any algorithm by name: a new one needs no JavaScript.
import { takesKind, type Algorithm, type Job, type ParamSchema } from '../api/types.ts';
import { el } from './dom.ts';
import { control, orderedParams } from './param_control.ts';
import './algorithms.css';

export interface AlgorithmsActions {
  /**
   * Submits a job; `inputs` holds the mesh ids chosen for the inputs after the
   * first. Resolves when it is submitted, rejects with a sentence to show beside the form.
   */
  run(algorithm: Algorithm, params: Record<string, unknown>, inputs: Record<string, string>): Promise<Job>;
  /** Cancels a job (the Cancel beside Run). */
  cancel(id: string): void;
  /** The ids of the current selection of that kind ('faces', 'vertices') on the mesh jobs run on (empty: none). */
  selection?(kind: string): number[];
}

export interface MeshChoice {
  id: string;
  name: string;
}

interface Field {
  name: string;
  schema: ParamSchema;
  row: HTMLElement;
  advanced: boolean;
  /** The value to send, or undefined to leave the parameter to the server's default. */
  read(): unknown;
  reset(): void;
}

const ACTIVE = new Set(['queued', 'running']);

/** A job started from this panel, shown under Run while it is queued or running. */
interface Started {
  /** The request it was started for (requestKey): Run stays busy while the form asks for the same. */
  key: string;
  title: string;
}

/** The parts of a started job's line under Run that its progress events change. */
interface StartedLine {
  line: HTMLElement;
  bar: HTMLProgressElement;
  stage: HTMLElement;
  percent: HTMLElement;
}

/** Areas listed after the others: examples teach, they are not tools. */
const LAST_AREAS = ['examples', 'other'];

/** The kind of object an algorithm runs on: its first input's. */
function firstKind(algorithm: Algorithm): string {
  return algorithm.inputs?.[0]?.kind ?? 'mesh';
}

/** "voxel_grid" → "a voxel grid". */
function aKind(kind: string): string {
  const words = kind.replace(/_/g, ' ');
  return /^[aeiou]/i.test(words) ? `an ${words}` : `a ${words}`;
}

/**
 * The algorithms the search words find, each word anywhere. Those it finds by
 * name, title or area come alone when there are any: a word that only a
 * description mentions ("voxel" in how skeleton_projection works inside)
 * would otherwise bury what the user asked for; descriptions are searched
 * when nothing else matches ("medial").
 */
export function searchAlgorithms(algorithms: readonly Algorithm[], query: string): Algorithm[] {
  const words = query.toLowerCase().split(/\s+/).filter(Boolean);
  if (!words.length) return [...algorithms];
  const has = (text: string) => words.every((w) => text.includes(w));
  const named = algorithms.filter((a) => has(`${a.name} ${a.name.replace(/_/g, ' ')} ${a.title ?? ''} ${a.area ?? ''}`.toLowerCase()));
  if (named.length) return named;
  return algorithms.filter((a) => has(`${a.name} ${a.title ?? ''} ${a.area ?? ''} ${a.description ?? ''}`.toLowerCase()));
}

/** The algorithms by area: areas alphabetical (examples last), the algorithms in the order given. */
function byArea(algorithms: readonly Algorithm[]): Array<[string, Algorithm[]]> {
  const areas = new Map<string, Algorithm[]>();
  for (const a of algorithms) {
    const area = a.area || 'other';
    if (!areas.has(area)) areas.set(area, []);
    areas.get(area)!.push(a);
  }
  const rank = (area: string) => LAST_AREAS.indexOf(area);
  return [...areas].sort(([x], [y]) => rank(x) - rank(y) || x.localeCompare(y));
}

export class AlgorithmsPanel {
  private readonly root: HTMLElement;
  private readonly actions: AlgorithmsActions;
  private algorithms: Algorithm[] = [];
  private chosen: string | null = null;
  private meshName: string | null = null;
  private meshes: MeshChoice[] = [];
  /** The kind of the job output chosen with "Run on this"; null: jobs run on the selected mesh. */
  private runKind: string | null = null;
  private readonly search: HTMLInputElement;
  private readonly menu: HTMLSelectElement;
  /** Why the menu is empty (nothing found, nothing runs on the chosen output). */
  private readonly none: HTMLElement;
  private formElement: HTMLFormElement | null = null;
  /** The choosers of the chosen algorithm's extra inputs, by input name. */
  private inputSelects = new Map<string, HTMLSelectElement>();
  /** The request being submitted now (its requestKey), or null. */
  private submitting: string | null = null;
  /** The request the form shows now, as a string compared with those started; null without a form. */
  private requestKey: () => string | null = () => null;
  /** Counts the selection's changes: a request of "use current selection" differs after one. */
  private selectionVersion = 0;
  /** The jobs the state holds (the job_* events and REST answers merged). */
  private jobs: ReadonlyMap<string, Job> = new Map();
  /** Jobs started here that have not ended, by id. */
  private readonly started = new Map<string, Started>();
  private readonly startedLines = new Map<string, StartedLine>();
  /** Under Run: a line for each job started here while it is queued or running. */
  private readonly runProgress = el('div', { class: 'run-progress', 'aria-label': 'Jobs started here', hidden: '' });
  private runButton: HTMLButtonElement | null = null;
  private target: HTMLElement | null = null;
  private errorBox: HTMLElement | null = null;

  constructor(root: HTMLElement, actions: AlgorithmsActions) {
    this.root = root;
    this.actions = actions;
    this.search = el('input', {
      type: 'search',
      id: 'algorithm-search',
      class: 'algorithm-search',
      'aria-label': 'Search algorithms',
      placeholder: 'Search algorithms',
      autocomplete: 'off',
      spellcheck: 'false',
    });
    this.search.addEventListener('input', () => this.refreshMenu());
    this.search.addEventListener('keydown', (ev) => {
      if (ev.key === 'Escape' && this.search.value) {
        this.search.value = '';
        this.refreshMenu();
      }
    });
    this.menu = el('select', { id: 'algorithm-menu', 'aria-label': 'Algorithm' });
    this.menu.addEventListener('change', () => {
      this.chosen = this.menu.value;
      this.showForm();
    });
    this.none = el('p', { class: 'empty algorithm-none', role: 'status', hidden: '' });
  }

  /** Shows why there is no menu (no algorithms API on this server, say). */
  unavailable(text: string): void {
    this.algorithms = [];
    this.formElement = null;
    this.root.replaceChildren(el('p', { class: 'empty' }, text));
  }

  /** Rebuilds the menu and the chosen algorithm's form (keeps the choice when it still exists). */
  render(algorithms: Algorithm[]): void {
    this.algorithms = algorithms;
    if (algorithms.length === 0) {
      this.unavailable('The server has no algorithms.');
      return;
    }
    // A new list may have changed the chosen algorithm's schema (a plugin rebuilt).
    this.formElement = null;
    this.root.replaceChildren(this.search, this.menu, this.none);
    this.refreshMenu();
  }

  /**
   * The kind of the job output the next job runs on ("Run on this"), or null
   * for the selected mesh: the menu offers only the algorithms that run on it.
   */
  setRunKind(kind: string | null): void {
    if (kind === this.runKind) return;
    this.runKind = kind;
    if (this.algorithms.length) this.refreshMenu();
  }

  /** The mesh jobs will run on (its name), or null: Run is disabled. */
  setMesh(name: string | null): void {
    this.meshName = name;
    this.updateRun();
  }

  /** The selection changed: the selection parameters' labels show its size. */
  setSelection(kind: string, count: number): void {
    for (const span of this.root.querySelectorAll<HTMLElement>('[data-selection-kind]')) {
      const k = span.dataset.selectionKind!;
      span.textContent = `use current selection (${k === kind ? count : 0} ${k})`;
    }
    ++this.selectionVersion;
    this.updateRun(); // a selection parameter asks for other ids now
  }

  /** The jobs changed (a job_* event, a REST answer): the lines under Run follow those started here. */
  setJobs(jobs: ReadonlyMap<string, Job>): void {
    this.jobs = jobs;
    this.showStarted();
  }

  /**
   * The lines under Run: one per job started here until it ends (then its
   * result or failure shows as for any job, and the line goes); the bar,
   * stage and percentage change in place, so that Cancel stays the same
   * element under the pointer.
   */
  private showStarted(): void {
    // A job leaves the state only when deleted (or the user changes): ended too.
    for (const id of [...this.started.keys()]) {
      const job = this.jobs.get(id);
      if (!job || !ACTIVE.has(job.state)) this.started.delete(id);
    }
    for (const [id, line] of this.startedLines) {
      if (this.started.has(id)) continue;
      line.line.remove();
      this.startedLines.delete(id);
    }
    for (const [id, started] of this.started) {
      let line = this.startedLines.get(id);
      if (!line) {
        line = this.startedLine(id, started.title);
        this.startedLines.set(id, line);
        this.runProgress.append(line.line);
      }
      const job = this.jobs.get(id)!;
      const fraction = Math.min(1, Math.max(0, job.progress || 0));
      line.line.dataset.state = job.state;
      line.stage.textContent = job.state === 'running' ? job.stage || 'running' : job.state;
      line.percent.textContent = `${Math.floor(fraction * 100)}%`;
      line.bar.value = fraction;
    }
    this.runProgress.hidden = this.started.size === 0;
    this.updateRun();
  }

  private startedLine(id: string, title: string): StartedLine {
    const stage = el('span', { class: 'run-job-stage' });
    const percent = el('span', { class: 'run-job-percent' });
    const bar = el('progress', { class: 'run-job-progress', max: '1', 'aria-label': `${title}: progress` });
    bar.value = 0;
    const cancel = el('button', { type: 'button', class: 'button small cancel', title: 'Cancel this job' }, 'Cancel');
    cancel.addEventListener('click', () => {
      cancel.disabled = true;
      this.actions.cancel(id);
    });
    const line = el(
      'div',
      { class: 'run-job', 'data-job-id': id },
      el('div', { class: 'run-job-head' }, el('span', { class: 'run-job-title', title }, title), stage, percent, cancel),
      bar,
    );
    return { line, bar, stage, percent };
  }

  /** The meshes an extra input may name (the server's mesh list). */
  setMeshes(meshes: MeshChoice[]): void {
    this.meshes = meshes;
    for (const select of this.inputSelects.values()) this.fillChooser(select);
  }

  /**
   * Fills the menu with the algorithms that run on the chosen object and that
   * the search finds, grouped by area; the form follows the choice, which
   * moves to the first one offered when the old one is no longer offered.
   */
  private refreshMenu(): void {
    // A stored mesh is the default input: every algorithm stays listed, and
    // one that needs another kind says so beside Run.
    const fitting = this.runKind ? this.algorithms.filter((a) => takesKind(firstKind(a), this.runKind!)) : this.algorithms;
    const found = searchAlgorithms(fitting, this.search.value);
    let why = '';
    if (!fitting.length) why = `No algorithm runs on ${aKind(this.runKind!)}: choose a mesh, or another result with "Run on this".`;
    else if (!found.length) why = `No algorithm matches “${this.search.value.trim()}”.`;
    this.none.textContent = why;
    this.none.hidden = !why;
    this.search.hidden = !fitting.length;
    this.menu.hidden = !found.length;
    if (!found.length) {
      this.menu.replaceChildren();
      this.formElement?.remove();
      this.formElement = null;
      return;
    }
    if (!found.some((a) => a.name === this.chosen)) this.chosen = found[0]!.name;
    this.menu.replaceChildren(
      ...byArea(found).map(([area, list]) => el('optgroup', { label: area }, ...list.map((a) => el('option', { value: a.name, title: a.description }, a.title || a.name)))),
    );
    this.menu.value = this.chosen!;
    if (this.formElement?.dataset.algorithm !== this.chosen) this.showForm();
  }

  private showForm(): void {
    const form = this.form();
    if (this.formElement?.isConnected) this.formElement.replaceWith(form);
    else this.root.append(form);
    this.formElement = form;
    this.menu.title = this.menu.selectedOptions[0]?.textContent ?? '';
  }

  private fillChooser(select: HTMLSelectElement): void {
    const keep = select.value;
    select.replaceChildren(...this.meshes.map((m) => el('option', { value: m.id }, m.name)));
    if (this.meshes.some((m) => m.id === keep)) select.value = keep;
  }

  /**
   * Run is busy ("Running…", aria-busy, disabled) while the request the form
   * shows is being submitted or its job is queued or running.
   */
  private updateRun(): void {
    const button = this.runButton;
    if (button) {
      const key = this.requestKey();
      const busy = key !== null && (this.submitting === key || [...this.started.values()].some((s) => s.key === key));
      button.disabled = busy || this.meshName === null;
      button.textContent = busy ? 'Running…' : 'Run';
      if (busy) {
        button.setAttribute('aria-busy', 'true');
        button.title = 'This run is under way: Cancel it below, or change a parameter to run another';
      } else {
        button.removeAttribute('aria-busy');
        button.removeAttribute('title');
      }
    }
    if (!this.target) return;
    const algorithm = this.algorithms.find((a) => a.name === this.chosen);
    const kind = algorithm ? firstKind(algorithm) : 'mesh';
    if (!this.runKind && !takesKind(kind, 'mesh')) this.target.textContent = `needs ${aKind(kind)}: choose one with "Run on this" in the job list`;
    else this.target.textContent = this.meshName ? `on ${this.meshName}` : 'Choose a mesh first.';
    this.target.title = this.target.textContent;
  }

  private form(): HTMLFormElement {
    const algorithm = this.algorithms.find((a) => a.name === this.chosen)!;
    const form = el('form', { class: 'algorithm-form', 'data-algorithm': algorithm.name, novalidate: '' });
    form.append(el('p', { class: 'algorithm-description' }, algorithm.description));
    this.inputSelects = new Map();
    for (const input of (algorithm.inputs ?? []).slice(1)) {
      if (input.kind !== 'mesh') continue;
      const id = `input-${algorithm.name}-${input.name}`;
      const select = el('select', { id, name: input.name, 'data-input': input.name });
      this.fillChooser(select);
      this.inputSelects.set(input.name, select);
      const row = el('div', { class: 'param param-input', 'data-input-row': input.name });
      row.append(el('label', { for: id, class: 'param-label' }, input.name), select);
      if (input.description) row.append(el('small', { class: 'param-help' }, input.description));
      form.append(row);
    }

    const fields = this.fields(algorithm);
    const byName = new Map(fields.map((f) => [f.name, f]));
    // A parameter applies while the one it depends on applies and has one of
    // the values named (a boolean's as "true" / "false").
    const applies = (f: Field, seen: Set<string> = new Set()): boolean => {
      const when = f.schema['x-cgview-when'];
      if (!when || typeof when.param !== 'string' || !Array.isArray(when.in)) return true;
      const on = byName.get(when.param);
      if (!on || seen.has(on.name)) return true;
      seen.add(f.name);
      return applies(on, seen) && when.in.map(String).includes(String(on.read()));
    };
    const basic = fields.filter((f) => !f.advanced);
    const advanced = fields.filter((f) => f.advanced);
    form.append(...basic.map((f) => f.row));
    const fold = advanced.length
      ? el('details', { class: 'advanced' }, el('summary', {}, 'Advanced'), el('div', { class: 'advanced-params' }, ...advanced.map((f) => f.row)))
      : null;
    if (fold) form.append(fold);
    const showApplicable = () => {
      for (const f of fields) f.row.hidden = !applies(f);
      if (fold) fold.hidden = advanced.every((f) => f.row.hidden);
    };
    showApplicable();
    form.addEventListener('change', showApplicable);

    this.errorBox = el('div', { class: 'form-error', role: 'alert', hidden: '' });
    if (fields.length) {
      const reset = el('button', { type: 'button', class: 'button small reset-params', title: 'Put every parameter back to its default' }, 'Reset to defaults');
      reset.addEventListener('click', () => {
        for (const f of fields) f.reset();
        showApplicable();
      });
      form.append(el('div', { class: 'form-tools' }, reset));
    }
    this.runButton = el('button', { type: 'submit', class: 'button run' }, 'Run');
    this.target = el('span', { class: 'run-target' });
    form.append(el('div', { class: 'run-row' }, this.runButton, this.target), this.runProgress, this.errorBox);

    // What the form asks for, told from its controls' values rather than by
    // reading the parameters: a selection's ids are not gathered (nor its
    // seams complained of) on every progress event.
    this.requestKey = () => {
      const values = [...form.querySelectorAll<HTMLInputElement | HTMLSelectElement>('input, select')].map((c) =>
        c instanceof HTMLInputElement && c.type === 'checkbox' ? c.checked : c.value,
      );
      const selection = form.querySelector<HTMLInputElement>('input[data-selection]:checked') ? this.selectionVersion : 0;
      return JSON.stringify([algorithm.name, this.meshName, selection, values]);
    };
    form.addEventListener('input', () => this.updateRun());
    form.addEventListener('change', () => this.updateRun());
    this.updateRun();

    form.addEventListener('submit', (ev) => {
      ev.preventDefault();
      const params: Record<string, unknown> = {};
      for (const f of fields) {
        if (!applies(f)) continue;
        const v = f.read();
        if (v !== undefined) params[f.name] = v;
      }
      const inputs: Record<string, string> = {};
      for (const [name, select] of this.inputSelects) if (select.value) inputs[name] = select.value;
      const key = this.requestKey();
      const errorBox = this.errorBox!;
      errorBox.hidden = true;
      errorBox.textContent = '';
      this.submitting = key;
      this.updateRun();
      this.actions
        .run(algorithm, params, inputs)
        .then((job) => {
          // Its state is in this.jobs already (the controller merged it in, a job_done that came first included).
          this.started.set(job.id, { key: key ?? '', title: algorithm.title || algorithm.name });
          this.showStarted();
          // Run may have been at the panel's lower edge: its progress comes into view.
          if (!this.runProgress.hidden) this.runProgress.scrollIntoView({ block: 'nearest' });
        })
        .catch((e: unknown) => {
          errorBox.textContent = e instanceof Error ? e.message : String(e);
          errorBox.hidden = false;
        })
        .finally(() => {
          this.submitting = null;
          this.updateRun();
        });
    });
    return form;
  }

  /** A row per parameter, in the declared order. */
  private fields(algorithm: Algorithm): Field[] {
    const properties = algorithm.params?.properties ?? {};
    return orderedParams(algorithm.params).map((name) => {
      const schema = properties[name]!;
      const id = `param-${algorithm.name}-${name}`;
      const { input, read, reset } = control(name, schema, id, (kind) => this.actions.selection?.(kind) ?? []);
      const label = el('label', { for: id, class: 'param-label' }, schema.title || name);
      const help = schema.description ? el('small', { class: 'param-help' }, schema.description) : null;
      const range =
        typeof schema.minimum === 'number' || typeof schema.maximum === 'number'
          ? el('small', { class: 'param-range' }, `${schema.minimum ?? '−∞'} … ${schema.maximum ?? '∞'}`)
          : null;
      const row = el('div', { class: `param param-${schema.type}`, 'data-param-row': name });
      if (schema.type === 'boolean' && !Array.isArray(schema.enum)) row.append(input, label);
      else row.append(label, input, ...(range ? [range] : []));
      if (help) row.append(help);
      return { name, schema, row, advanced: schema['x-cgview-advanced'] === true, read, reset };
    });
  }
}
