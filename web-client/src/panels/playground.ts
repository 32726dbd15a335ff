// The code panel's DOM: the plugin chooser ("Open"), "New", the name with
// "Rename", "Save" and "Share…", the editor, "Build" and "Run" with the mesh
// they run on, "Submit" while a course's assignment is open, the build's or
// run's progress, the compiler's messages (a click puts the cursor on one)
// and the form of the plugin algorithm's parameters (the algorithm panel's
// controls). It draws what the controller
// (controllers/plugins.ts) tells it and hands it the clicks.
import type { Plugin, PluginDiagnostic } from '../api/plugins.ts';
import type { Algorithm } from '../api/types.ts';
import { control, orderedParams } from './param_control.ts';
import { el } from './dom.ts';

export interface PlaygroundActions {
  open(id: string): void;
  create(): void;
  save(): void;
  rename(name: string): void;
  share(): void;
  build(): void;
  run(): void;
  /** Saves the file and submits it to the assignment open in the Course panel. */
  submit(): void;
  /** A compiler's message was clicked: the editor shows its place. */
  goTo(d: PluginDiagnostic): void;
  /** The ids of the current selection of that kind for a selection parameter (empty: none). */
  selection(kind: string): number[];
}

/** A plugin in the chooser: whose it is. */
export type PluginGroup = 'yours' | 'shared' | 'lab';

interface ParamField {
  name: string;
  read(): unknown;
}

const GROUP_LABELS: Record<PluginGroup, string> = { yours: 'Yours', shared: 'Shared with you', lab: 'Lab' };

export class PlaygroundPanel {
  /** Where the controller puts the editor. */
  readonly editorHost: HTMLElement;
  readonly nameInput: HTMLInputElement;
  private readonly chooser: HTMLSelectElement;
  private readonly buttons: Record<'create' | 'rename' | 'save' | 'share' | 'build' | 'run' | 'submit', HTMLButtonElement>;
  private readonly assignment: HTMLElement;
  private readonly target: HTMLElement;
  private readonly statusText: HTMLElement;
  private readonly bar: HTMLProgressElement;
  private readonly messages: HTMLUListElement;
  private readonly form: HTMLFormElement;
  private fields: ParamField[] = [];
  private readonly actions: PlaygroundActions;

  constructor(root: HTMLElement, actions: PlaygroundActions) {
    this.actions = actions;
    const button = (label: string, title: string, onClick: () => void, cls = ''): HTMLButtonElement => {
      const b = el('button', { type: 'button', class: `button ${cls}`.trim(), title }, label);
      b.addEventListener('click', onClick);
      return b;
    };
    this.chooser = el('select', { class: 'playground-open', 'aria-label': 'Open a plugin' });
    this.chooser.addEventListener('change', () => {
      const id = this.chooser.value;
      this.chooser.value = '';
      if (id) actions.open(id);
    });
    this.nameInput = el('input', {
      type: 'text',
      class: 'playground-name',
      'aria-label': 'Plugin name',
      maxlength: '64',
      pattern: '[A-Za-z0-9_\\-]{1,64}',
      spellcheck: 'false',
      autocomplete: 'off',
    });
    this.buttons = {
      create: button('New', 'A new file from the template', () => actions.create()),
      rename: button('Rename', 'Give the plugin the name typed beside', () => actions.rename(this.nameInput.value.trim())),
      save: button('Save', 'Save the file on the server (it is not built)', () => actions.save()),
      share: button('Share…', 'Let other users run and read it', () => actions.share()),
      build: button('Build', 'Save, then compile it on the server', () => actions.build(), 'playground-build'),
      run: button('Run', 'Run its algorithm on the mesh shown (built first when changed)', () => actions.run(), 'run'),
      submit: button('Submit', 'Save this file and submit it to the assignment', () => actions.submit(), 'playground-submit'),
    };
    this.assignment = el('div', { class: 'playground-row playground-assignment', hidden: '' }, el('span', { class: 'playground-assignment-title' }), this.buttons.submit);
    this.nameInput.addEventListener('keydown', (ev) => {
      if (ev.key === 'Enter') actions.rename(this.nameInput.value.trim());
    });
    this.editorHost = el('div', { class: 'playground-editor' }, el('p', { class: 'empty' }, 'Loading the editor…'));
    this.target = el('span', { class: 'run-target' });
    this.statusText = el('span', { class: 'playground-status-text' });
    this.bar = el('progress', { max: '1', hidden: '' });
    this.messages = el('ul', { class: 'playground-diagnostics', 'aria-label': 'Compiler messages' });
    this.form = el('form', { class: 'playground-params', novalidate: '', 'aria-label': 'Parameters' });
    this.form.addEventListener('submit', (ev) => {
      ev.preventDefault();
      actions.run();
    });
    root.append(
      el('div', { class: 'playground-row' }, el('h2', {}, 'Code'), this.chooser, this.buttons.create),
      el('div', { class: 'playground-row' }, this.nameInput, this.buttons.rename, this.buttons.save, this.buttons.share),
      this.editorHost,
      el('div', { class: 'playground-row' }, this.buttons.build, this.buttons.run, this.target),
      this.assignment,
      el('div', { class: 'playground-status', role: 'status' }, this.statusText, this.bar),
      this.messages,
      this.form,
    );
  }

  /** The plugins to open, grouped by whose they are; `current` is marked. */
  setPlugins(plugins: ReadonlyArray<{ plugin: Plugin; group: PluginGroup }>, current: string | null): void {
    const options: HTMLElement[] = [el('option', { value: '' }, plugins.length ? 'Open…' : 'Open… (none saved yet)')];
    for (const group of ['yours', 'shared', 'lab'] as PluginGroup[]) {
      const list = plugins.filter((p) => p.group === group);
      if (!list.length) continue;
      const g = el('optgroup', { label: GROUP_LABELS[group] });
      for (const { plugin } of list) {
        const mark = plugin.id === current ? ' (open)' : '';
        const owner = group === 'shared' ? ` — ${plugin.owner}` : '';
        g.append(el('option', { value: plugin.id, 'data-plugin-id': plugin.id }, `${plugin.name}${owner}${mark}`));
      }
      options.push(g);
    }
    this.chooser.replaceChildren(...options);
    this.chooser.value = '';
  }

  /** The assignment open in the Course panel, which "Submit" submits this file to (null: none, no button). */
  setAssignment(title: string | null): void {
    this.assignment.hidden = title === null;
    this.assignment.querySelector('.playground-assignment-title')!.textContent = title === null ? '' : `Assignment: ${title}`;
  }

  /** What may be done to the file open: a read-only one (the lab's, another user's) is run, not changed. */
  setEditable(editable: { change: boolean; share: boolean }): void {
    this.nameInput.readOnly = !editable.change;
    this.buttons.rename.disabled = this.buttons.save.disabled = this.buttons.build.disabled = !editable.change;
    this.buttons.share.disabled = !editable.share;
  }

  /** While a request or a build is under way, the buttons that start another wait. */
  setBusy(busy: boolean, editable: { change: boolean; share: boolean }): void {
    for (const b of Object.values(this.buttons)) b.disabled = busy;
    if (!busy) this.setEditable(editable);
    this.root().dataset.busy = String(busy);
  }

  /** The mesh Run runs on, or null (Run says why it cannot). */
  setTarget(name: string | null): void {
    this.target.textContent = name ? `on ${name}` : 'Choose a mesh first.';
  }

  /** The status line: what is under way or how it ended; `progress` in 0..1 shows the bar, null hides it. */
  status(text: string, level: 'info' | 'ok' | 'error' = 'info', progress: number | null = null): void {
    this.statusText.textContent = text;
    this.statusText.parentElement!.dataset.level = level;
    this.bar.hidden = progress === null;
    if (progress !== null) this.bar.value = Math.min(1, Math.max(0, progress));
  }

  /** The compiler's messages, each "file:line:column severity: message". */
  setDiagnostics(messages: readonly PluginDiagnostic[]): void {
    this.messages.replaceChildren(
      ...messages.map((d) => {
        const where = d.line > 0 ? `${d.file}:${d.line}${d.column > 0 ? `:${d.column}` : ''}` : d.file;
        const item = el(
          'li',
          { class: 'playground-diagnostic', 'data-severity': d.severity, 'data-line': String(d.line), tabindex: '0' },
          el('span', { class: 'diagnostic-where' }, where),
          ' ',
          el('span', { class: 'diagnostic-severity' }, `${d.severity}:`),
          ' ',
          el('span', { class: 'diagnostic-message' }, d.message),
        );
        const go = () => this.actions.goTo(d);
        item.addEventListener('click', go);
        item.addEventListener('keydown', (ev) => {
          if (ev.key === 'Enter') go();
        });
        return item;
      }),
    );
  }

  /** The form of the algorithm Run runs (null: none built yet), from its params schema as the algorithm panel makes it. */
  setAlgorithm(algorithm: Algorithm | null): void {
    this.fields = [];
    this.form.replaceChildren();
    this.form.dataset.algorithm = algorithm?.name ?? '';
    if (!algorithm) return;
    this.form.append(el('p', { class: 'algorithm-description' }, `${algorithm.title || algorithm.name}: ${algorithm.description}`));
    const properties = algorithm.params?.properties ?? {};
    for (const name of orderedParams(algorithm.params)) {
      const schema = properties[name]!;
      const id = `playground-param-${name}`;
      const { input, read } = control(name, schema, id, (kind) => this.actions.selection(kind));
      this.fields.push({ name, read });
      const label = el('label', { for: id, class: 'param-label' }, schema.title || name);
      const row = el('div', { class: `param param-${schema.type}`, 'data-param-row': name });
      if (schema.type === 'boolean' && !Array.isArray(schema.enum)) row.append(input, label);
      else row.append(label, input);
      if (schema.description) row.append(el('small', { class: 'param-help' }, schema.description));
      this.form.append(row);
    }
  }

  /** The values of the form's parameters (those left empty take the server's defaults). */
  params(): Record<string, unknown> {
    const out: Record<string, unknown> = {};
    for (const f of this.fields) {
      const v = f.read();
      if (v !== undefined) out[f.name] = v;
    }
    return out;
  }

  /** The selection changed: the selection parameters' labels say its size. */
  setSelection(kind: string, count: number): void {
    for (const span of this.form.querySelectorAll<HTMLElement>('[data-selection-kind]')) {
      const k = span.dataset.selectionKind!;
      span.textContent = `use current selection (${k === kind ? count : 0} ${k})`;
    }
  }

  private root(): HTMLElement {
    return this.editorHost.parentElement!;
  }
}
