// The viewer's orchestrator: makes the state (state/app_state.ts), the
// viewer and the panels that several parts draw in, the controllers (meshes,
// jobs, scene, comparison, view links, account, course, lecture) and the artifact kinds
// (kinds/registry.ts), and joins them to the server's events. Panels render
// from the state; the controllers and kinds are the only ones that change it.
import type { ServerEvent } from './api/types.ts';
import { CgviewSocket } from './api/ws.ts';
import { AccountController } from './controllers/account.ts';
import { CompareController } from './controllers/compare.ts';
import { CourseController } from './controllers/course.ts';
import { DisplayController } from './controllers/display.ts';
import type { AppContext } from './controllers/context.ts';
import { JobsController } from './controllers/jobs.ts';
import { LectureController } from './controllers/lecture.ts';
import { MeshLoader } from './controllers/mesh_loader.ts';
import { MeshesController } from './controllers/meshes.ts';
import { SceneController } from './controllers/scene.ts';
import { UndoOffers } from './controllers/undo.ts';
import { ViewLinks } from './controllers/view_links.ts';
import { Kinds } from './kinds/registry.ts';
import { AccountPanel } from './panels/account.ts';
import { byId } from './panels/dom.ts';
import { MessagesPanel } from './panels/messages.ts';
import { NavigationPanel } from './panels/navigation.ts';
import { installPlayground } from './panels/playground_toggle.ts';
import { ProgressPanel } from './panels/progress.ts';
import { SelectionPanel } from './panels/selection.ts';
import { UploadControl } from './panels/upload.ts';
import { initialState, type AppState } from './state/app_state.ts';
import { Store } from './state/store.ts';
import { installTestHooks, type TestHooks } from './test_hooks.ts';
import { DracoDecoder } from './viewer/draco_decoder.ts';
import { orbitFrameTimes } from './viewer/frame_timer.ts';
import { MeshTextures } from './viewer/textures.ts';
import { Navigation } from './viewer/navigation.ts';
import { SelectionTool } from './viewer/selection_tool.ts';
import { Viewer } from './viewer/viewer.ts';

export type { TestHooks };

/** How the page was opened: with a course's sign-in link (the Course panel opens), or with one refused. */
export interface AppOptions {
  openCourse?: boolean;
  refusedLink?: boolean;
}

export class App {
  private readonly store = new Store<AppState>(initialState());
  private readonly socket = new CgviewSocket();
  private readonly hooks: TestHooks;
  private readonly account: AccountController;
  private readonly meshes: MeshesController;
  private readonly scene: SceneController;
  private readonly kinds: Kinds;
  private readonly jobs: JobsController;
  private readonly links: ViewLinks;
  private readonly course: CourseController;
  /** Made last: a frame drawn before has no lecture to tell. */
  private readonly lecture: LectureController | undefined;
  private readonly error: (text: string) => void;
  private readonly options: AppOptions;

  constructor(options: AppOptions = {}) {
    this.options = options;
    const { store } = this;
    const hooks = (this.hooks = installTestHooks((frames) => orbitFrameTimes(viewer, frames)));
    const viewer = new Viewer(byId('viewport'), {
      onFrame: () => {
        ++hooks.frames;
        hooks.scene = this.scene.report();
        this.links.changed();
        this.lecture?.frame();
      },
    });
    // Before the Display panel's listener: the overlays measure the object where the scene puts it.
    viewer.onShownChange((object) => this.scene.shownChanged(object));
    const error = (this.error = (text: string, topic?: string): void => {
      hooks.lastError = text;
      store.update({ message: { level: 'error', text, topic } });
    });
    const notice = (text: string): void => store.update({ message: { level: 'notice', text } });
    const warning = (text: string): void => store.update({ message: { level: 'warning', text } });
    const undo = new UndoOffers(store, hooks);
    const textures = new MeshTextures(
      byId('texture-panel'),
      (onDrawn) => viewer.redraw(onDrawn),
      (state) => (hooks.texture = state),
      error,
    );
    // Messages stack at the top of the left sidebar, which the code panel never replaces: never over the view.
    const messagesRoot = byId('messages');
    document.querySelector('.sidebar.left')?.prepend(messagesRoot);
    const messages = new MessagesPanel(messagesRoot);
    store.subscribe(
      (s) => s.message,
      (m) => {
        if (m) messages.show(m);
      },
    );
    const status = byId('connection');
    store.subscribe(
      (s) => s.connected,
      (connected) => {
        status.dataset.state = connected ? 'connected' : 'disconnected';
        status.title = connected ? 'Connected to the server' : 'Not connected; retrying';
      },
    );
    new UploadControl(byId<HTMLInputElement>('file-input'), document.body, (files) => void this.meshes.upload(files));
    byId('fit').addEventListener('click', () => viewer.fitToView());
    const navigation = new Navigation(viewer);
    new NavigationPanel(byId('navigation'), navigation, error);
    let selectionPanel: SelectionPanel | null = null;
    const selectionTool = new SelectionTool(
      viewer,
      byId('viewport'),
      (state) => {
        selectionPanel?.render(state);
        this.jobs.selectionChanged(state.kind, state.ids.length);
        hooks.selection = { meshId: state.meshId, ready: state.ready, kind: state.kind, count: state.ids.length, ids: state.ids, area: state.area };
      },
      (enabled) => navigation.setEnabled(enabled),
    );
    selectionPanel = new SelectionPanel(byId('selection'), selectionTool, () => navigation.mode !== 'fly', undo);
    hooks.camera = () => navigation.state();
    hooks.clipping = () => ({ near: viewer.camera.near, far: viewer.camera.far });
    hooks.selectionView = () => selectionTool.view();
    const display = new DisplayController(byId('display'), store, viewer, {
      setFieldRange: (range) => this.kinds.field.setRange(range),
      drawn: (report) => (hooks.display = report),
      others: () => this.scene.others(),
      colorOf: (object) => this.scene.entryOf(object)?.color ?? null,
      meshOf: (object) => this.scene.entryOf(object)?.mesh ?? null,
      formatOf: (id) => store.get().meshes.find((m) => m.id === id)?.format ?? null,
    });
    const account = (this.account = new AccountController(store, new AccountPanel(byId('account'))));
    const ctx: AppContext = {
      account,
      store,
      hooks,
      viewer,
      socket: this.socket,
      display,
      progress: new ProgressPanel(byId('progress')),
      textures,
      selectionTool,
      undo,
      error,
      dismiss: (topic) => messages.dismiss(topic),
      notice,
      warning,
    };
    // Each is given what it uses of those made before it, and calls back
    // what it asks of those made after it (that use it in turn): the scene
    // selects meshes and shows panes, the mesh list ends the comparison and
    // the kinds, the kinds compare and import, the code panel submits.
    const loader = new MeshLoader(ctx, new DracoDecoder());
    const scene: SceneController = (this.scene = new SceneController(ctx, {
      loader,
      selectMesh: (id) => meshes.select(id),
      resultName: (jobId, artifact) => jobs.resultName(jobId, artifact),
      sourceMeshOf: (jobId) => jobs.sourceMeshOf(jobId),
      leaveComparison: () => compare.leave(),
      leaveComparisonWithUndo: () => compare.leaveWithUndo(),
      showPanes: (items) => compare.showScene(items),
    }));
    const meshes: MeshesController = (this.meshes = new MeshesController(ctx, {
      scene,
      loader,
      leaveComparison: () => compare.leave(),
      disposeKinds: () => kinds.dispose(),
      importFile: (file, kind) => jobs.importFile(file, kind),
    }));
    const kinds: Kinds = (this.kinds = new Kinds(ctx, {
      loader,
      meshes,
      scene,
      leaveComparison: () => compare.leave(),
      compareObjects: (list, build, what) => compare.compareObjects(list, build, what),
      compareJob: (jobId) => compare.compareJob(jobId),
      addToComparison: (jobId, artifact) => compare.addToComparison(jobId, artifact),
      importFile: (file, kind) => jobs.importFile(file, kind),
      upsertJob: (job) => jobs.upsert(job),
    }));
    const compare: CompareController = new CompareController(ctx, { kinds, loader, scene });
    const jobs: JobsController = (this.jobs = new JobsController(ctx, { kinds, meshes }));
    const links = (this.links = new ViewLinks(ctx, { meshes, loader, scene, kinds, compare }));
    byId('screenshot').addEventListener('click', () => {
      const name = (meshes.selected()?.name ?? 'view').replace(/\.[^.]*$/, '');
      display.screenshot(`cgview-${name}.png`, (blob) => (hooks.lastScreenshot = blob ? { bytes: blob.size } : null));
    });
    byId('copy-link').addEventListener('click', () => links.copy());
    const code = installPlayground(ctx, { jobs, submit: () => course.submit() });
    const course = (this.course = new CourseController(ctx, { meshes, jobs }, byId('course'), byId<HTMLButtonElement>('course-toggle'), code));
    this.lecture = new LectureController(ctx, { links, meshes, jobs, kinds }, byId('course'), code);
  }

  async start(): Promise<void> {
    const { socket } = this;
    socket.onEvent((ev) => this.onServerEvent(ev));
    let connectedBefore = false;
    socket.onStatus((connected) => {
      this.store.update({ connected });
      // Events may have been missed while disconnected.
      if (connected && connectedBefore) {
        void this.meshes.refresh();
        void this.jobs.refresh();
      }
      if (connected) connectedBefore = true;
    });
    socket.connect().catch(() => this.error('Cannot open the WebSocket to the server; retrying.'));
    if (this.options.refusedLink) this.error('This sign-in link is used or expired: ask your teacher for another.');
    await Promise.all([this.meshes.refresh(), this.jobs.loadAlgorithms(), this.account.refresh(), this.course.start(this.options.openCourse ?? false)]);
    this.hooks.ready = true;
    await this.links.restore();
  }

  private onServerEvent(ev: ServerEvent): void {
    if (ev.type !== 'job_progress') this.account.refreshSoon(); // storage or jobs in use changed
    switch (ev.type) {
      case 'mesh_added':
        this.meshes.upsert(ev.mesh);
        break;
      case 'mesh_deleted':
        this.meshes.forget(ev.mesh_id);
        break;
      case 'job_progress':
        this.jobs.progress(ev.job);
        break;
      case 'job_done':
      case 'job_failed':
      case 'job_cancelled':
        this.jobs.upsert(ev.job);
        break;
    }
  }
}
