// The code playground: a user's own algorithm written in the browser, saved
// as a plugin on the server (created on the first save or build), built
// there in a build job (followed as any job: its progress from the
// WebSocket, its end read back from the plugin, whose build says "ok" with
// the algorithms it registers or "failed" with the compiler's messages), and
// run on the mesh shown through the jobs controller, so that what it makes
// appears as any algorithm's does. While a course's assignment is open the
// file is submitted to it (controllers/course.ts), and the staff read a
// student's submission here, read-only. Loaded with the code panel only.
import { buildPlugin, createPlugin, getPlugin, listPlugins, updatePlugin, type Plugin } from '../api/plugins.ts';
import { getJob, listAlgorithms } from '../api/rest.ts';
import type { Algorithm, Job } from '../api/types.ts';
import { CodeEditor } from '../panels/code_editor.ts';
import { PlaygroundPanel, type PluginGroup } from '../panels/playground.ts';
import { TEMPLATE, TEMPLATE_NAME } from '../panels/playground_template.ts';
import { openShareForm } from '../panels/share.ts';
import { submittable } from '../state/app_state.ts';
import { describe, type AppContext } from './context.ts';
import type { JobsController } from './jobs.ts';

/**
 * What the code panel runs through: the jobs, made before it; and the
 * course's Submit, called back, as the course is made after it (it opens
 * files in the code panel).
 */
export interface PluginsDeps {
  jobs: Pick<JobsController, 'loadAlgorithms' | 'run' | 'selectionFor' | 'upsert'>;
  /** Submits the code panel's file to the assignment open in the Course panel. */
  submit(): Promise<void>;
}

const FINAL = new Set(['done', 'failed', 'cancelled', 'interrupted']);
/** How often a job followed here is asked for, in case its events are missed (a reconnect). */
const POLL_MS = 2000;

export class PluginsController {
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: PluginsDeps;
  private readonly panel: PlaygroundPanel;
  private readonly editor: CodeEditor;
  /** The plugin open (null: a new file, not saved yet) as the server last answered it. */
  private plugin: Plugin | null = null;
  /** The text as last saved (or the template's, for a new file). */
  private saved = TEMPLATE;
  /** The algorithm Run runs: the built plugin's first. */
  private algorithm: Algorithm | null = null;
  private busy = false;
  private listsAsked = 0;
  /** A text shown read-only that is no plugin of the caller's (a student's submission, to the staff): its name. */
  private viewing: string | null = null;
  /** Who hears of each change of the text (a lecture's presenter's code). */
  private readonly textListeners: Array<(text: string) => void> = [];

  constructor(ctx: AppContext, deps: PluginsDeps, root: HTMLElement) {
    this.ctx = ctx;
    this.deps = deps;
    this.panel = new PlaygroundPanel(root, {
      open: (id) => void this.task(() => this.open(id)),
      create: () => void this.task(() => this.create()),
      save: () => void this.task(() => this.save()),
      rename: (name) => void this.task(() => this.rename(name)),
      share: () => this.share(),
      build: () => void this.task(async () => void (await this.build())),
      run: () => void this.task(() => this.run()),
      submit: () => void deps.submit(),
      goTo: (d) => this.editor.goTo(d.line, d.column),
      selection: (kind) => deps.jobs.selectionFor(kind),
    });
    this.panel.editorHost.replaceChildren();
    this.editor = new CodeEditor(this.panel.editorHost, TEMPLATE, () => this.edited());
    this.panel.nameInput.value = TEMPLATE_NAME;
    this.panel.setEditable(this.editable());
    this.panel.status('A new file from the template: Build compiles it, Run runs it on the mesh shown.');
    ctx.store.subscribe(
      (s) => s.inputName,
      (name) => this.panel.setTarget(name),
      { now: true },
    );
    ctx.store.subscribe(
      (s) => submittable(s)?.title ?? null,
      (title) => this.panel.setAssignment(title),
      { now: true },
    );
    void this.refreshList();
  }

  /** Opens a plugin (the student's copy of a starter), as "Open" does; what went wrong is said in the status line. */
  openPlugin(id: string): Promise<void> {
    return this.task(() => this.open(id));
  }

  /** Shows a text read-only, named `name`, with a note in the status line (a student's submission, to the staff). */
  showSource(name: string, text: string, note: string): Promise<void> {
    return this.task(async () => {
      await this.keepEdits();
      this.plugin = null;
      this.algorithm = null;
      this.viewing = name;
      this.saved = text;
      this.editor.setText(text, true);
      this.textChanged();
      this.panel.nameInput.value = name;
      this.panel.setEditable(this.editable());
      this.panel.setDiagnostics([]);
      this.panel.setAlgorithm(null);
      this.panel.status(note);
      void this.refreshList();
    });
  }

  /**
   * The file to submit, saved first (created the first time): its plugin's
   * id. Throws, saying why, when there is none of the caller's to submit.
   */
  async fileToSubmit(): Promise<string> {
    if (this.busy) throw new Error('The code panel is busy: submit once it is done.');
    if (this.viewing !== null) throw new Error("The code panel shows a student's submission, read-only: open your own file to submit it.");
    if (!this.plugin && !this.dirty()) throw new Error('Open the starter first, or write your code in the code panel.');
    let failure: unknown = null;
    let id = '';
    await this.task(async () => {
      try {
        if (this.editable().change) await this.save();
        id = this.plugin!.id;
      } catch (e) {
        failure = e;
        throw e;
      }
    });
    if (failure) throw failure;
    return id;
  }

  /** The text in the editor. */
  get text(): string {
    return this.editor.text;
  }

  /** Calls `listener` with the text at each change, typed or another file's. */
  onText(listener: (text: string) => void): void {
    this.textListeners.push(listener);
  }

  private textChanged(): void {
    for (const listener of this.textListeners) listener(this.editor.text);
  }

  /** Says something in the status line (how a submission went). */
  note(text: string, level: 'info' | 'ok' | 'error' = 'info'): void {
    this.panel.status(text, level);
  }

  /** The panel was shown again: the list may have changed meanwhile (another tab, a share). */
  shown(): void {
    void this.refreshList();
  }

  private editable(): { change: boolean; share: boolean } {
    if (this.viewing !== null) return { change: false, share: false };
    const p = this.plugin;
    const mine = !p || (p.origin !== 'lab' && this.ctx.account.mayChange(p.owner));
    return { change: mine, share: !!p && mine };
  }

  private dirty(): boolean {
    return this.editor.text !== this.saved;
  }

  private edited(): void {
    this.textChanged();
    if (this.plugin?.build.state === 'ok' || this.plugin?.build.state === 'failed') {
      this.panel.status(this.dirty() ? 'Changed since the build.' : 'As built.');
    }
  }

  /** Runs one action at a time, the buttons disabled meanwhile; its failure is said in the status line. */
  private async task(action: () => Promise<void>): Promise<void> {
    if (this.busy) return;
    this.busy = true;
    this.panel.setBusy(true, this.editable());
    try {
      await action();
    } catch (e) {
      this.panel.status(describe(e), 'error');
    } finally {
      this.busy = false;
      this.panel.setBusy(false, this.editable());
    }
  }

  private async refreshList(): Promise<void> {
    // Lists asked for earlier may answer later: only the latest is shown, or a rename could be undone on screen.
    const asked = ++this.listsAsked;
    let plugins: Plugin[];
    try {
      plugins = await listPlugins();
    } catch (e) {
      if (asked === this.listsAsked) this.panel.status(`Cannot list the plugins: ${describe(e)}`, 'error');
      return;
    }
    if (asked !== this.listsAsked) return;
    const me = this.ctx.store.get().me?.user;
    const group = (p: Plugin): PluginGroup => (p.origin === 'lab' ? 'lab' : !me || p.owner === me ? 'yours' : 'shared');
    const sorted = [...plugins].sort((a, b) => a.name.localeCompare(b.name));
    this.panel.setPlugins(
      sorted.map((plugin) => ({ plugin, group: group(plugin) })),
      this.plugin?.id ?? null,
    );
  }

  /** Shows a plugin as the server answered it (with its source): text, name, messages, form. */
  private async show(plugin: Plugin, text = plugin.source ?? ''): Promise<void> {
    this.viewing = null;
    this.plugin = plugin;
    this.saved = text;
    if (this.editor.text !== text) {
      this.editor.setText(text, !this.editable().change);
      this.textChanged();
    } else this.editor.setReadOnly(!this.editable().change);
    this.panel.nameInput.value = plugin.name;
    this.panel.setEditable(this.editable());
    this.showBuild(plugin);
    await this.loadAlgorithm();
    void this.refreshList();
  }

  private showBuild(plugin: Plugin): void {
    const b = plugin.build;
    this.panel.setDiagnostics(b.diagnostics);
    this.editor.showDiagnostics(b.diagnostics);
    const errors = b.diagnostics.filter((d) => d.severity.includes('error')).length;
    const warnings = b.diagnostics.filter((d) => d.severity === 'warning').length;
    const said = (n: number, what: string): string => `${n} ${what}${n === 1 ? '' : 's'}`;
    switch (b.state) {
      case 'ok':
        this.panel.status(`Built: ${b.algorithms.join(', ') || 'no algorithm'}${warnings ? ` (${said(warnings, 'warning')})` : ''}.`, 'ok');
        break;
      case 'failed':
        this.panel.status(errors ? `Does not build: ${said(errors, 'error')}.` : `Does not build: ${b.error ?? 'no reason given'}`, 'error');
        break;
      case 'changed':
        this.panel.status('Changed since the last build.');
        break;
      case 'building':
        this.panel.status('Building…', 'info', 0);
        break;
      default:
        this.panel.status('Not built yet.');
    }
  }

  /** The algorithm of the built plugin (GET /algorithms lists a user's built plugins' algorithms with their plugin's id). */
  private async loadAlgorithm(): Promise<void> {
    const p = this.plugin;
    this.algorithm = null;
    if (p?.build.state === 'ok' || p?.build.state === 'changed') {
      const all = await listAlgorithms();
      const ours = all.filter((a) => a.plugin === p.id);
      this.algorithm = ours.find((a) => a.name === p.build.algorithms[0]) ?? ours[0] ?? null;
    }
    this.panel.setAlgorithm(this.algorithm);
  }

  private async open(id: string): Promise<void> {
    await this.keepEdits();
    this.panel.status('Opening…');
    await this.show(await getPlugin(id));
  }

  private async create(): Promise<void> {
    await this.keepEdits();
    this.viewing = null;
    this.plugin = null;
    this.algorithm = null;
    this.saved = TEMPLATE;
    this.editor.setText(TEMPLATE, false);
    this.textChanged();
    this.panel.nameInput.value = TEMPLATE_NAME;
    this.panel.setEditable(this.editable());
    this.panel.setDiagnostics([]);
    this.panel.setAlgorithm(null);
    this.panel.status('A new file from the template.');
    void this.refreshList();
  }

  /** Before another file replaces this one: its edits are saved (a new file's, unless it is the template as it came). */
  private async keepEdits(): Promise<void> {
    if (this.dirty() && this.editable().change) await this.save();
  }

  /** Saves the text (creating the plugin the first time); the name typed is the new plugin's. */
  private async save(): Promise<void> {
    const text = this.editor.text;
    if (!this.plugin) {
      const name = this.panel.nameInput.value.trim() || TEMPLATE_NAME;
      this.plugin = await createPlugin(name, text);
    } else if (text !== this.saved) {
      this.plugin = await updatePlugin(this.plugin.id, { source: text });
    }
    this.saved = text;
    this.panel.status(`Saved ${this.plugin.name}.`, 'ok');
    this.panel.setEditable(this.editable());
    void this.refreshList();
  }

  private async rename(name: string): Promise<void> {
    if (!/^[A-Za-z0-9_-]{1,64}$/.test(name)) {
      this.panel.status('A name is 1 to 64 letters, digits, _ or -.', 'error');
      return;
    }
    if (!this.plugin) {
      await this.save(); // created under the name typed
      return;
    }
    this.plugin = await updatePlugin(this.plugin.id, { name });
    this.panel.nameInput.value = this.plugin.name;
    await this.refreshList(); // the chooser shows the new name by the time the status says so
    this.panel.status(`Renamed ${this.plugin.name}.`, 'ok');
  }

  private share(): void {
    const p = this.plugin;
    if (p) openShareForm('plugins', p.id, `plugin ${p.name}`);
  }

  /** Saves, builds, waits for the build job, then reads the plugin for how it went. Resolves true when it built. */
  private async build(): Promise<boolean> {
    await this.save();
    const id = this.plugin!.id;
    this.panel.setDiagnostics([]);
    this.editor.showDiagnostics([]);
    this.panel.status('Building: queued', 'info', 0);
    const job = await this.follow(await buildPlugin(id), (j) => `Building: ${j.stage || j.state}`);
    if (job.state !== 'done' && job.state !== 'failed') throw new Error(`The build was ${job.state}.`);
    const plugin = await getPlugin(id);
    // The text may have been edited during the build: what was built is what was saved.
    this.plugin = plugin;
    this.showBuild(plugin);
    if (this.dirty()) this.panel.status('Built what was saved; changed since.', plugin.build.state === 'ok' ? 'ok' : 'error');
    await this.loadAlgorithm();
    if (plugin.build.state === 'ok') await this.deps.jobs.loadAlgorithms(); // the algorithm menu lists it now
    void this.refreshList();
    return plugin.build.state === 'ok';
  }

  /** Runs the built algorithm on the mesh shown (building first when the text changed since). */
  private async run(): Promise<void> {
    const state = this.plugin?.build.state;
    if (this.editable().change && (!this.plugin || this.dirty() || state !== 'ok')) {
      if (!(await this.build())) return;
    }
    const algorithm = this.algorithm;
    if (!algorithm) throw new Error(this.plugin?.build.state === 'ok' ? 'The plugin registers no algorithm.' : 'Build it first.');
    const selection = this.ctx.selectionTool.state();
    this.panel.setSelection(selection.kind, selection.ids.length);
    this.panel.status(`Running ${algorithm.name}…`, 'info', 0);
    const job = await this.follow(await this.deps.jobs.run(algorithm, this.panel.params()), (j) => `Running ${algorithm.name}: ${j.stage || j.state}`);
    if (job.state === 'done') this.panel.status(`${algorithm.name} done${job.cached ? ' (cached)' : ''}: its results are in the job list.`, 'ok');
    else this.panel.status(`${algorithm.name} ${job.state}: ${job.error ?? 'no reason given'}`, 'error');
  }

  /**
   * Follows a job to its end from the state (the jobs controller merges its
   * events in), asking the server now and then as well; shows its progress.
   */
  private follow(first: Job, say: (job: Job) => string): Promise<Job> {
    const { store } = this.ctx;
    const { deps } = this;
    deps.jobs.upsert(first);
    return new Promise((resolve) => {
      let timer = 0;
      let stop = (): void => {};
      const seen = (job: Job | undefined): void => {
        if (!job) return;
        if (!FINAL.has(job.state)) {
          this.panel.status(say(job), 'info', job.progress);
          return;
        }
        stop();
        window.clearInterval(timer);
        resolve(job);
      };
      stop = store.subscribe(
        (s) => s.jobs.get(first.id),
        (job) => seen(job),
      );
      timer = window.setInterval(() => {
        getJob(first.id).then(
          (job) => deps.jobs.upsert(job),
          () => {},
        );
      }, POLL_MS);
      seen(store.get().jobs.get(first.id) ?? first);
    });
  }
}
