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
// the form. An algorithm of several inputs (hausdorff's `reference`) gets a
// mesh chooser for each input after the first.
//
// The menu is grouped by the algorithms' area, narrowed by a search box, and,
// once a job's output is chosen with "Run on this", holds only the
// algorithms whose first input is of that output's kind. Nothing here knows
// any algorithm by name: a new one needs no JavaScript.
import type { Algorithm, ParamSchema } from '../api/types.ts';
import { el } from './dom.ts';
import { control, orderedParams } from './param_control.ts';
import './algorithms.css';

export interface AlgorithmsActions {
  /**
   * Submits a job; `inputs` holds the mesh ids chosen for the inputs after the
   * first. Resolves when it is submitted, rejects with a sentence to show beside the form.
   */
  run(algorithm: Algorithm, params: Record<string, unknown>, inputs: Record<string, string>): Promise<void>;
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
  private running = false;
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
    const fitting = this.runKind ? this.algorithms.filter((a) => firstKind(a) === this.runKind) : this.algorithms;
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

  private updateRun(): void {
    if (this.runButton) this.runButton.disabled = this.running || this.meshName === null;
    if (!this.target) return;
    const algorithm = this.algorithms.find((a) => a.name === this.chosen);
    const kind = algorithm ? firstKind(algorithm) : 'mesh';
    if (!this.runKind && kind !== 'mesh') this.target.textContent = `needs ${aKind(kind)}: choose one with "Run on this" in the job list`;
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
    form.append(el('div', { class: 'run-row' }, this.runButton, this.target), this.errorBox);
    this.updateRun();

    form.addEventListener('submit', (ev) => {
      ev.preventDefault();
      const params: Record<string, unknown> = {};
      for (const f of fields) {
        if (!applies(f)) continue;
        const v = f.read();
        if (v !== undefined) params[f.name] = v;
      }
      const errorBox = this.errorBox!;
      errorBox.hidden = true;
      errorBox.textContent = '';
      this.running = true;
      this.updateRun();
      const inputs: Record<string, string> = {};
      for (const [name, select] of this.inputSelects) if (select.value) inputs[name] = select.value;
      this.actions
        .run(algorithm, params, inputs)
        .catch((e: unknown) => {
          errorBox.textContent = e instanceof Error ? e.message : String(e);
          errorBox.hidden = false;
        })
        .finally(() => {
          this.running = false;
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
