// The algorithm menu and, for the chosen algorithm, a form generated from its
// params JSON Schema (API.md "Algorithms and jobs"): integer / number → a
// number input with min, max, step and the default; boolean → a checkbox;
// enum → a select; string → a text input; a selection (an array with
// x-cgview-selection: faces or vertices) → "use current selection (N faces)",
// which sends the viewer's selection's ids. Titles are the labels,
// descriptions the help text. Run submits a job on the selected mesh; the
// server's validation errors (400 detail) are shown beside the form. An
// algorithm of several inputs (hausdorff's `reference`) gets a mesh chooser
// for each input after the first. Nothing here knows any algorithm by name: a
// new one needs no JavaScript.
import type { Algorithm, ParamSchema } from '../api/types.ts';
import { el } from './dom.ts';

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
  /** The value to send, or undefined to leave the parameter to the server's default. */
  read(): unknown;
}

function stepFor(schema: ParamSchema): string {
  if (schema.type === 'integer') return '1';
  if (typeof schema.multipleOf === 'number') return String(schema.multipleOf);
  const lo = typeof schema.minimum === 'number' ? schema.minimum : null;
  const hi = typeof schema.maximum === 'number' ? schema.maximum : null;
  if (lo !== null && hi !== null && hi > lo) {
    // About a hundredth of the range, a power of ten: 0.1..4 → 0.01.
    return String(10 ** Math.floor(Math.log10((hi - lo) / 100)));
  }
  return 'any';
}

/** The input of one parameter (also the playground's form) and how to read its value. */
export function control(name: string, schema: ParamSchema, id: string, selection: (kind: string) => number[]): { input: HTMLElement; read: () => unknown } {
  const kind = schema['x-cgview-selection'];
  if (typeof kind === 'string') {
    const box = el('input', { id, name, type: 'checkbox', 'data-param': name, 'data-selection': kind });
    box.checked = true;
    const text = el('span', { class: 'selection-use', 'data-selection-kind': kind }, `use current selection (${selection(kind).length} ${kind})`);
    const label = el('label', { class: 'check' }, box, ' ', text);
    return { input: label, read: () => (box.checked ? selection(kind) : undefined) };
  }
  if (Array.isArray(schema.enum)) {
    const values = schema.enum;
    const select = el('select', { id, name, 'data-param': name });
    values.forEach((v, i) => {
      const option = el('option', { value: String(i) }, String(v));
      if (v === schema.default) option.selected = true;
      select.append(option);
    });
    return { input: select, read: () => values[Number(select.value)] };
  }
  switch (schema.type) {
    case 'boolean': {
      const input = el('input', { id, name, type: 'checkbox', 'data-param': name });
      input.checked = schema.default === true;
      return { input, read: () => input.checked };
    }
    case 'integer':
    case 'number': {
      const input = el('input', { id, name, type: 'number', 'data-param': name, step: stepFor(schema) });
      if (typeof schema.minimum === 'number') input.min = String(schema.minimum);
      if (typeof schema.maximum === 'number') input.max = String(schema.maximum);
      if (typeof schema.default === 'number') input.value = String(schema.default);
      return {
        input,
        read: () => {
          const text = input.value.trim();
          if (text === '') return undefined;
          // What the user typed goes to the server as typed: it checks the rules.
          return Number(text);
        },
      };
    }
    default: {
      const input = el('input', { id, name, type: 'text', 'data-param': name });
      if (typeof schema.default === 'string') input.value = schema.default;
      return { input, read: () => input.value };
    }
  }
}

export class AlgorithmsPanel {
  private readonly root: HTMLElement;
  private readonly actions: AlgorithmsActions;
  private algorithms: Algorithm[] = [];
  private chosen: string | null = null;
  private meshName: string | null = null;
  private meshes: MeshChoice[] = [];
  /** The choosers of the chosen algorithm's extra inputs, by input name. */
  private inputSelects = new Map<string, HTMLSelectElement>();
  private running = false;
  private runButton: HTMLButtonElement | null = null;
  private target: HTMLElement | null = null;
  private errorBox: HTMLElement | null = null;

  constructor(root: HTMLElement, actions: AlgorithmsActions) {
    this.root = root;
    this.actions = actions;
  }

  /** Shows why there is no menu (no algorithms API on this server, say). */
  unavailable(text: string): void {
    this.algorithms = [];
    this.root.replaceChildren(el('p', { class: 'empty' }, text));
  }

  /** Rebuilds the menu and the chosen algorithm's form (keeps the choice when it still exists). */
  render(algorithms: Algorithm[]): void {
    this.algorithms = algorithms;
    if (algorithms.length === 0) {
      this.unavailable('The server has no algorithms.');
      return;
    }
    if (!this.chosen || !algorithms.some((a) => a.name === this.chosen)) this.chosen = algorithms[0]!.name;
    const menu = el('select', { id: 'algorithm-menu', 'aria-label': 'Algorithm' });
    const areas = new Map<string, Algorithm[]>();
    for (const a of algorithms) {
      const area = a.area || 'other';
      if (!areas.has(area)) areas.set(area, []);
      areas.get(area)!.push(a);
    }
    for (const [area, list] of areas) {
      const group = el('optgroup', { label: area });
      for (const a of list) {
        const option = el('option', { value: a.name, title: a.description }, a.title || a.name);
        if (a.name === this.chosen) option.selected = true;
        group.append(option);
      }
      menu.append(group);
    }
    menu.addEventListener('change', () => {
      this.chosen = menu.value;
      this.root.querySelector('form')?.replaceWith(this.form());
    });
    this.root.replaceChildren(menu, this.form());
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

  private fillChooser(select: HTMLSelectElement): void {
    const keep = select.value;
    select.replaceChildren(...this.meshes.map((m) => el('option', { value: m.id }, m.name)));
    if (this.meshes.some((m) => m.id === keep)) select.value = keep;
  }

  private updateRun(): void {
    if (this.runButton) this.runButton.disabled = this.running || this.meshName === null;
    if (this.target) this.target.textContent = this.meshName ? `on ${this.meshName}` : 'Choose a mesh first.';
  }

  private form(): HTMLFormElement {
    const algorithm = this.algorithms.find((a) => a.name === this.chosen)!;
    const form = el('form', { class: 'algorithm-form', 'data-algorithm': algorithm.name, novalidate: '' });
    form.append(el('p', { class: 'algorithm-description' }, algorithm.description));
    const fields: Field[] = [];
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
    const properties = algorithm.params?.properties ?? {};
    for (const [name, schema] of Object.entries(properties)) {
      const id = `param-${algorithm.name}-${name}`;
      const { input, read } = control(name, schema, id, (kind) => this.actions.selection?.(kind) ?? []);
      fields.push({ name, schema, read });
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
      form.append(row);
    }
    this.errorBox = el('div', { class: 'form-error', role: 'alert', hidden: '' });
    this.runButton = el('button', { type: 'submit', class: 'button run' }, 'Run');
    this.target = el('span', { class: 'run-target' });
    form.append(el('div', { class: 'run-row' }, this.runButton, this.target), this.errorBox);
    this.updateRun();

    form.addEventListener('submit', (ev) => {
      ev.preventDefault();
      const params: Record<string, unknown> = {};
      for (const f of fields) {
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
}
