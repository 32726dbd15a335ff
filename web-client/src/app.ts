// The one place that owns the view state: the list of meshes, the chosen
// mesh, the scene (the meshes shown at once, the chosen one first, with their
// visibility, colour and transform), the load in progress and what the
// viewer shows. Panels render from it and call its actions; nothing else
// changes it.
import * as THREE from 'three';
import {
  ApiError,
  cancelJob,
  deleteMesh,
  fetchArtifactBytes,
  fetchArtifactF32,
  fetchArtifactJson,
  fetchMeshBytes,
  getJob,
  getMe,
  listAlgorithms,
  listJobs,
  listMeshes,
  submitJob,
  uploadMesh,
} from './api/rest.ts';
import { parseSkeleton, type SkeletonData } from './api/skeleton.ts';
import { jobMeshId } from './api/types.ts';
import type { Algorithm, ArtifactInfo, Job, JobInput, JobProgress, Me, Mesh, ServerEvent } from './api/types.ts';
import { CgviewSocket, ServerError, type MeshTransfer } from './api/ws.ts';
import { AccountPanel } from './panels/account.ts';
import { AlgorithmsPanel } from './panels/algorithms.ts';
import { JobsPanel } from './panels/jobs.ts';
import { MeshListPanel } from './panels/mesh_list.ts';
import { MessagesPanel } from './panels/messages.ts';
import { ProgressPanel } from './panels/progress.ts';
import { ReportPanel } from './panels/report.ts';
import { openShareForm } from './panels/share.ts';
import { UploadControl, uploadsOf } from './panels/upload.ts';
import { VoxelSlicePanel } from './panels/voxel_slices.ts';
import { SkeletonsPanel } from './panels/skeletons.ts';
import { NavigationPanel } from './panels/navigation.ts';
import { SelectionPanel } from './panels/selection.ts';
import { Navigation, type CameraState } from './viewer/navigation.ts';
import { SelectionTool } from './viewer/selection_tool.ts';
import { DisplayPanel, type DisplayReport } from './panels/display.ts';
import { ScenePanel } from './panels/scene.ts';
import { defaultSceneObject, isIdentity, MAX_SCENE_OBJECTS, sanitizeScene, sceneColor, type SceneObjectState } from './viewer/scene_state.ts';
import { applySceneTransform, projectedBox } from './viewer/scene_objects.ts';
import { applyCamera, readCamera } from './viewer/camera_state.ts';
import { decodeViewHash, encodeViewHash, type ViewState } from './viewer/view_state.ts';
import { buildSlicePlane, sliceClipPlane } from './viewer/slice_plane.ts';
import { byId } from './panels/dom.ts';
import { AnimationPlayer } from './viewer/animation_player.ts';
import { DracoDecoder } from './viewer/draco_decoder.ts';
import { decodeFrames, framePositions } from './viewer/frames.ts';
import { defaultMapFor } from './viewer/colormaps.ts';
import { ComparisonView } from './viewer/comparison.ts';
import { Legend } from './viewer/legend.ts';
import { buildSkeleton, SKELETON_COLORS } from './viewer/skeleton_renderer.ts';
import { parsePly, type PlyMesh } from './viewer/ply.ts';
import { buildScalarSurface, colourGeometry, finiteRange, type ScalarField } from './viewer/scalar_field_renderer.ts';
import { buildPlainSurface, buildSurface, SURFACE_COLOR } from './viewer/surface_renderer.ts';
import { orbitFrameTimes, type OrbitTimes } from './viewer/frame_timer.ts';
import { LoadTimer, type LoadTimings } from './viewer/timings.ts';
import { MeshTextures, type TextureState } from './viewer/textures.ts';
import { Viewer } from './viewer/viewer.ts';

/** What tests read (window.__cgview). */
export interface TestHooks {
  /** True once the page is set up and the first mesh list has been asked for. */
  ready: boolean;
  /**
   * The mesh in the viewer, set after the first frame showing it has rendered;
   * bytes: the Draco payload received for it.
   */
  lastLoaded: { id: string; vertices: number; faces: number; bytes: number } | null;
  /**
   * The durations of the load of lastLoaded (see viewer/timings.ts): null
   * when lastLoaded changes, set once the GPU has finished its first frame.
   */
  timings: LoadTimings | null;
  /** Frames rendered so far. */
  frames: number;
  /** The last error message shown in the page, or null. */
  lastError: string | null;
  /**
   * The scalar field drawn on the mesh, set after the first frame showing it
   * (and again after a colour-map change); null when none is drawn.
   */
  lastField: { jobId: string; artifact: string; meshId: string; location: string; count: number; range: [number, number]; map: string } | null;
  /** The voxels drawn in 3D from the slice panel: boundary cubes drawn, voxels kept, the threshold (0..1 of the range). */
  lastVoxels: { count: number; kept: number; threshold: number } | null;
  /**
   * The fields compared side by side, in pane order (left to right, top to
   * bottom), with the colour map and the range of each; set after the first frame showing
   * them (and again after a colour-map change); null when not comparing.
   */
  lastCompare: { meshId: string; panes: Array<{ jobId: string; artifact: string; map: string; range: [number, number] }> } | null;
  /** Whether the server answered GET /api/v1/algorithms (null until asked). */
  algorithmsApi: boolean | null;
  /** The last mesh artifact added to the view, set after the first frame with it. */
  lastExtra: { jobId: string; artifact: string; vertices: number; faces: number } | null;
  /**
   * The animation frame drawn (chaos_animate), set after the frame is
   * rendered: which frame of how many, and the first vertex's position and
   * the sum of all coordinates as drawn.
   */
  lastAnimation: { jobId: string; artifact: string; frame: number; frames: number; vertices: number; first: [number, number, number]; sum: number } | null;
  /** The skeletons drawn over the mesh, set after the first frame with each change: key, colour, nodes, edges. */
  skeletons: Array<{ key: string; color: string; nodes: number; edges: number }>;
  /** The selection (ids of the stored mesh), set after the frame that draws it. */
  selection?: { meshId: string | null; ready: boolean; kind: string; count: number; ids: number[]; area: number | null };
  /** The camera now: position, view direction, up, orbit centre, navigation mode. */
  camera?: () => CameraState;
  /** The camera's view for the selection: canvas size in CSS pixels, projection × view (column-major). */
  selectionView?: () => { width: number; height: number; viewProjection: number[] };
  /** The display mode, material and overlays of the shown object, set after the first frame with each change (panels/display.ts). */
  display: DisplayReport | null;
  /** The last view link made with "Copy link". */
  lastLink: string | null;
  /** The camera after a view link was restored (set after the frame showing it), or the error that stopped it. */
  viewRestored: { camera: ViewState['camera']; mode: string } | { error: string } | null;
  /** The last screenshot downloaded: its PNG's size in bytes. */
  lastScreenshot: { bytes: number } | null;
  /** The texture on the surface (a mesh with UVs), set after the first frame with it; null when none. */
  texture: TextureState | null;
  /**
   * The decimated preview of a big mesh, set after the first frame showing
   * it, with the camera then; fullCamera: the camera after the first frame of
   * the full mesh that replaced it (null until then).
   */
  lastPreview: { id: string; vertices: number; faces: number; camera: ViewState['camera']; fullCamera: ViewState['camera'] | null } | null;
  /** Renders `frames` frames orbiting the shown object and times them (viewer/frame_timer.ts; for bench/frame_bench.mjs). */
  orbit: (frames: number) => OrbitTimes;
  /**
   * The scene as the last frame drew it: each object (the shown mesh first)
   * with its state, whether it is drawn (loaded), the pane it is in (-1: the
   * one view) and its world box projected into that pane or the canvas in
   * normalized device coordinates ([-1, 1], y up); panes: how many.
   */
  scene: {
    panes: number;
    /** The object chosen in the Scene panel, whose overlays the Display panel draws. */
    picked: number;
    objects: Array<SceneObjectState & { name: string; loaded: boolean; pane: number; box: [number, number, number, number] | null }>;
  };
}

/** An object of the scene: its state, its mesh's name, and (for those beside the first) the surface drawn once loaded. */
interface SceneEntry extends SceneObjectState {
  name: string;
  object: THREE.Mesh | null;
}

declare global {
  interface Window {
    __cgview: TestHooks;
  }
}

/** A scalar_field artifact to draw: its job, its description in the Job, and the mesh it is on. */
interface FieldSource {
  job: Job;
  artifact: ArtifactInfo;
  meshId: string;
}

function describe(e: unknown): string {
  if (e instanceof ApiError || e instanceof ServerError) return e.detail || e.message;
  if (e instanceof Error) return e.message;
  return String(e);
}

/** A `${jobId}/${artifact}` key back into its parts. */
function splitKey(key: string): { jobId: string; artifact: string } {
  const i = key.indexOf('/');
  return { jobId: key.slice(0, i), artifact: key.slice(i + 1) };
}

function isAbort(e: unknown): boolean {
  return e instanceof DOMException && e.name === 'AbortError';
}

export class App {
  private meshes: Mesh[] = [];
  private selectedId: string | null = null;
  private load: { id: string; controller: AbortController } | null = null;
  /** The latest show(): a field to draw waits for its mesh. */
  private showing: Promise<void> = Promise.resolve();

  // Algorithms and jobs.
  private jobs = new Map<string, Job>();
  /** Jobs this page submitted: their scalar field is shown when they finish. */
  private readonly autoShow = new Set<string>();
  private readonly metrics = new Map<string, unknown>();
  private readonly texts = new Map<string, string | undefined>();
  /** Jobs asked for with GET /jobs/{id} (progress of a job not seen yet). */
  private readonly asking = new Set<string>();
  /** Mesh artifacts in the view (`${jobId}/${name}`), beside the selected mesh. */
  private readonly added = new Set<string>();
  /** Skeleton artifacts drawn over the mesh, by `${jobId}/${name}`, in the order shown. */
  private readonly skeletons = new Map<string, { object: THREE.Object3D; data: SkeletonData; color: string; nodes: number; edges: number }>();
  /** skeleton_distance jobs submitted for the comparison table, by `${first key}|${other key}`. */
  private readonly distanceJobs = new Map<string, string>();
  private readonly skeletonsPanel = new SkeletonsPanel(
    byId('skeletons'),
    () => void this.compareSkeletons(),
    (file) => void this.loadSkeletonFile(file),
  );
  /** skeleton_file jobs from "Load skeleton file…": their skeleton is drawn when done. */
  private readonly drawWhenDone = new Set<string>();
  /** A job's output mesh that the next job runs on ("Run on this"), instead of the selected mesh. */
  private runTarget: { jobId: string; artifact: string; kind: string } | null = null;
  /** The scalar field drawn now (or being prepared: token). */
  private field: { jobId: string; artifact: string; meshId: string; data: ScalarField; object: THREE.Mesh; map: string; fullRange: [number, number] } | null = null;
  private fieldToken = 0;
  private mapName: string | null = null; // null: the field's hint chooses
  /** The fields compared side by side (empty: one view), and the token of the comparison being prepared. */
  private compared: Array<{ jobId: string; artifact: string }> = [];
  private compareToken = 0;
  private readonly plyCache = new Map<string, Promise<PlyMesh>>();
  /** The scene: the selected mesh first (drawn as the viewer's shown object), then the meshes added beside it (the viewer's extras). */
  private scene: SceneEntry[] = [];
  /** Whether the scene's objects are side by side, one per pane. */
  private scenePanes = false;
  /** The scene object chosen in the Scene panel: the Display panel's overlays are drawn over it. */
  private picked = 0;

  private readonly hooks: TestHooks = {
    ready: false,
    lastLoaded: null,
    timings: null,
    frames: 0,
    lastError: null,
    lastField: null,
    lastVoxels: null,
    lastCompare: null,
    algorithmsApi: null,
    lastExtra: null,
    lastAnimation: null,
    skeletons: [],
    display: null,
    lastLink: null,
    viewRestored: null,
    lastScreenshot: null,
    texture: null,
    lastPreview: null,
    orbit: (frames) => orbitFrameTimes(this.viewer, frames),
    scene: { panes: 0, picked: 0, objects: [] },
  };
  private readonly socket = new CgviewSocket();
  private readonly decoder = new DracoDecoder();
  private readonly viewer: Viewer;
  private readonly list: MeshListPanel;
  private readonly report: ReportPanel;
  private readonly progress: ProgressPanel;
  private readonly messages: MessagesPanel;
  private readonly algorithmsPanel: AlgorithmsPanel;
  private readonly jobsPanel: JobsPanel;
  private readonly slicePanel: VoxelSlicePanel;
  private readonly legend: Legend;
  private readonly comparison: ComparisonView;
  private readonly leaveCompare: HTMLButtonElement;
  private readonly player: AnimationPlayer;
  private animationToken = 0;
  private readonly status: HTMLElement;
  private readonly navigation: Navigation;
  private readonly selectionTool: SelectionTool;
  private readonly display: DisplayPanel;
  private readonly textures: MeshTextures;
  private readonly scenePanel: ScenePanel;
  /** The signed-in user and their quota use (GET /me), shown in the header. */
  private me: Me | null = null;
  private readonly account = new AccountPanel(byId('account'));
  private accountTimer: ReturnType<typeof setTimeout> | null = null;

  constructor() {
    window.__cgview = this.hooks;
    this.viewer = new Viewer(byId('viewport'), {
      onFrame: () => {
        ++this.hooks.frames;
        this.hooks.scene = this.sceneReport();
      },
    });
    // Before the Display panel's listener: the overlays measure the object where the scene puts it.
    this.viewer.onShownChange((object) => this.shownChanged(object));
    this.scenePanel = new ScenePanel(byId('scene'), {
      change: (i, patch) => this.changeSceneObject(i, patch),
      remove: (i) => this.removeSceneObject(i),
      fitAll: () => this.viewer.fitAll(),
      pick: (i) => this.pickSceneObject(i),
      sideBySide: (on) => (on ? this.showSceneSideBySide() : this.leaveComparison()),
    });
    this.textures = new MeshTextures(
      byId('texture-panel'),
      (onDrawn) => this.viewer.redraw(onDrawn),
      (state) => (this.hooks.texture = state),
      (text) => this.error(text),
    );
    this.list = new MeshListPanel(byId('mesh-list'), {
      select: (id) => this.select(id),
      addToScene: (id) => void this.addToScene(id),
      remove: (id) => void this.remove(id),
      share: (id) => openShareForm('meshes', id, this.meshes.find((m) => m.id === id)?.name ?? id),
      mayChange: (owner) => this.mayChange(owner),
    });
    this.report = new ReportPanel(byId('report'));
    this.progress = new ProgressPanel(byId('progress'));
    this.messages = new MessagesPanel(byId('messages'));
    this.status = byId('connection');
    this.algorithmsPanel = new AlgorithmsPanel(byId('algorithms'), {
      run: (algorithm, params, inputs) => this.runJob(algorithm, params, inputs),
      selection: (kind) => this.selectionFor(kind),
    });
    this.jobsPanel = new JobsPanel(byId('jobs'), {
      cancel: (id) => void this.cancel(id),
      showField: (jobId, artifact) => void this.showField(jobId, artifact),
      compare: (jobId) => this.compareJob(jobId),
      addToComparison: (jobId, artifact) => this.addToComparison(jobId, artifact),
      addMesh: (jobId, artifact) => void this.addMeshArtifact(jobId, artifact),
      runOn: (jobId, artifact) => this.setRunTarget(jobId, artifact),
      playAnimation: (jobId, artifact) => void this.showAnimation(jobId, artifact),
      showSlices: (jobId, artifact) => this.slicePanel.open(jobId, artifact),
      toggleSkeleton: (jobId, artifact) => void this.toggleSkeleton(jobId, artifact),
      share: (jobId) => openShareForm('jobs', jobId, `job ${this.jobs.get(jobId)?.algorithm ?? ''} ${jobId.slice(0, 8)}`),
    });
    this.slicePanel = new VoxelSlicePanel(
      byId('voxel-slices'),
      this.socket,
      (shown) => {
        this.viewer.setOverlay('voxel-slice', shown ? buildSlicePlane(shown.canvas, shown.slice) : null);
        this.viewer.setClipPlane(shown?.cut ? sliceClipPlane(shown.slice) : null);
      },
      (jobId, artifact) => fetchArtifactBytes(jobId, artifact, 'nrrd'),
      (shown) => {
        this.viewer.setOverlay('voxels', shown?.object ?? null);
        this.hooks.lastVoxels = shown ? { count: shown.count, kept: shown.kept, threshold: shown.threshold } : null;
      },
    );
    this.legend = new Legend(byId('viewport'), (name) => this.setColorMap(name), 'legend');
    this.comparison = new ComparisonView(this.viewer, byId('viewport'), (panes) => {
      const meshId = this.selectedId;
      this.hooks.lastCompare = meshId && this.compared.length ? { meshId, panes: panes.map((p, i) => ({ ...this.compared[i]!, map: p.map, range: p.range })) } : null;
    });
    this.leaveCompare = byId<HTMLButtonElement>('leave-compare');
    this.leaveCompare.addEventListener('click', () => this.leaveComparison());
    this.player = new AnimationPlayer(byId('viewport'));
    new UploadControl(byId<HTMLInputElement>('file-input'), document.body, (files) => void this.upload(files));
    byId('fit').addEventListener('click', () => this.viewer.fitToView());
    this.navigation = new Navigation(this.viewer);
    new NavigationPanel(byId('navigation'), this.navigation, (text) => this.error(text));
    let selectionPanel: SelectionPanel | null = null;
    this.selectionTool = new SelectionTool(
      this.viewer,
      byId('viewport'),
      (state) => {
        selectionPanel?.render(state);
        this.algorithmsPanel.setSelection(state.kind, state.ids.length);
        this.hooks.selection = { meshId: state.meshId, ready: state.ready, kind: state.kind, count: state.ids.length, ids: state.ids, area: state.area };
      },
      (enabled) => this.navigation.setEnabled(enabled),
    );
    selectionPanel = new SelectionPanel(byId('selection'), this.selectionTool, () => this.navigation.mode !== 'fly');
    this.hooks.camera = () => this.navigation.state();
    this.hooks.selectionView = () => this.selectionTool.view();
    this.display = new DisplayPanel(byId('display'), this.viewer, {
      setFieldRange: (range) => this.setFieldRange(range),
      drawn: (report) => (this.hooks.display = report),
      others: () => this.scene.slice(1).flatMap((e) => (e.object ? [e.object] : [])),
      colorOf: (object) => this.sceneEntryOf(object)?.color ?? null,
    });
    byId('screenshot').addEventListener('click', () => {
      const name = (this.selectedMesh()?.name ?? 'view').replace(/\.[^.]*$/, '');
      this.display.screenshot(`cgview-${name}.png`, (blob) => (this.hooks.lastScreenshot = blob ? { bytes: blob.size } : null));
    });
    byId('copy-link').addEventListener('click', () => this.copyViewLink());
  }

  async start(): Promise<void> {
    this.report.render(null);
    this.algorithmsPanel.setMesh(null);
    this.renderJobs();
    this.socket.onEvent((ev) => this.onServerEvent(ev));
    let connectedBefore = false;
    this.socket.onStatus((connected) => {
      this.status.dataset.state = connected ? 'connected' : 'disconnected';
      this.status.title = connected ? 'Connected to the server' : 'Not connected; retrying';
      // Events may have been missed while disconnected.
      if (connected && connectedBefore) {
        void this.refresh();
        void this.refreshJobs();
      }
      if (connected) connectedBefore = true;
    });
    this.socket.connect().catch(() => this.error('Cannot open the WebSocket to the server; retrying.'));
    await Promise.all([this.refresh(), this.loadAlgorithms(), this.refreshAccount()]);
    this.hooks.ready = true;
    await this.restoreView();
  }

  /** Asks the server again who the user is and what they use (soon after a change, once for a burst of them). */
  private refreshAccountSoon(): void {
    if (this.accountTimer) return;
    this.accountTimer = setTimeout(() => {
      this.accountTimer = null;
      void this.refreshAccount();
    }, 300);
  }

  async refreshAccount(): Promise<void> {
    try {
      const first = this.me === null;
      this.me = await getMe();
      this.account.render(this.me);
      if (first) this.renderList(); // the share buttons depend on who asks
    } catch {
      // An older server without /me: no account line.
    }
  }

  /** Whether the user may share or delete an item of that owner (the server decides in the end). */
  private mayChange(owner: string | undefined): boolean {
    return !this.me || this.me.admin || owner === undefined || owner === this.me.user;
  }

  private onServerEvent(ev: ServerEvent): void {
    if (ev.type !== 'job_progress') this.refreshAccountSoon(); // storage or jobs in use changed
    switch (ev.type) {
      case 'mesh_added':
        this.upsert(ev.mesh);
        break;
      case 'mesh_deleted':
        this.forget(ev.mesh_id);
        break;
      case 'job_progress':
        this.progressJob(ev.job);
        break;
      case 'job_done':
      case 'job_failed':
      case 'job_cancelled':
        this.upsertJob(ev.job);
        break;
    }
  }

  /** Asks for the algorithm menu; a 404 means this server has no algorithms API. */
  async loadAlgorithms(): Promise<void> {
    try {
      const algorithms = await listAlgorithms();
      this.hooks.algorithmsApi = true;
      this.algorithmsPanel.render(algorithms);
      this.algorithmsPanel.setMesh(this.selectedMesh()?.name ?? null);
      await this.refreshJobs();
    } catch (e) {
      this.hooks.algorithmsApi = false;
      if (e instanceof ApiError && e.status === 404) {
        this.algorithmsPanel.unavailable('This server has no algorithms API (GET /api/v1/algorithms: 404).');
      } else {
        this.algorithmsPanel.unavailable(`Cannot list algorithms: ${describe(e)}`);
      }
    }
  }

  /** Reloads the job list (after a reconnect, events may have been missed). */
  async refreshJobs(): Promise<void> {
    if (this.hooks.algorithmsApi !== true) return;
    try {
      const jobs = await listJobs();
      for (const job of jobs) this.upsertJob(job, false);
      this.renderJobs();
    } catch (e) {
      this.error(`Cannot list jobs: ${describe(e)}`);
    }
  }

  /**
   * Submits a job on the selected mesh, or on the job output chosen with "Run
   * on this" (a chain: the server stores that output as a mesh of its own and
   * announces it); `extra` names the meshes of the algorithm's other inputs.
   * Rejects with the server's detail (shown beside the form).
   */
  async runJob(algorithm: Algorithm, params: Record<string, unknown>, extra: Record<string, string> = {}): Promise<void> {
    const target = this.runTarget;
    const mesh = this.selectedMesh();
    // The algorithm's first input: the selected mesh, or the output chosen with "Run on this".
    const first = algorithm.inputs?.[0] ?? { name: 'mesh', kind: 'mesh' };
    if (first.kind !== 'mesh' && target?.kind !== first.kind) {
      throw new Error(`${algorithm.name} runs on a ${first.kind}: choose one with "Run on this" in the job list.`);
    }
    if (!target && !mesh) throw new Error('Choose a mesh first.');
    const inputs: Record<string, JobInput> = {
      ...extra,
      [first.name]: target ? { job: target.jobId, artifact: target.artifact } : mesh!.id,
    };
    let job: Job;
    try {
      job = await submitJob(algorithm.name, inputs, params);
    } catch (e) {
      throw new Error(describe(e));
    }
    if (target) {
      // A chained mesh is a stored mesh now: later runs and fields use it.
      this.runTarget = null;
      const stored = typeof job.inputs.mesh === 'string' ? job.inputs.mesh : null;
      if (stored && !this.meshes.some((m) => m.id === stored)) await this.refresh();
      if (stored) this.select(stored);
    }
    this.autoShow.add(job.id);
    // A job_done event may have come before this answer: upsertJob keeps the later state.
    this.upsertJob(job);
    this.refreshAccountSoon(); // one more job in use
  }

  /**
   * The selection to send as a job's faces or vertices parameter: its ids (the
   * stored mesh's), when it is of that kind and on the mesh the job runs on.
   */
  private selectionFor(kind: string): number[] {
    const state = this.selectionTool.state();
    if (this.runTarget || state.meshId !== this.selectedId || state.kind !== kind) return [];
    // Vertices split at attribute seams in the PLY are not the stored ones (docs/DESIGN.md).
    if (kind === 'vertices' && state.ids.length && this.selectionTool.vertexCount !== this.selectedMesh()?.report.vertices) {
      this.error('This mesh has seams (separate normal or UV indices): its vertex selection cannot be sent as stored ids.');
      return [];
    }
    return state.ids;
  }

  /** "Run on this": the next job's input is this job's output mesh. */
  setRunTarget(jobId: string, artifact: string): void {
    const job = this.jobs.get(jobId);
    if (!job) return;
    const kind = job.artifacts?.find((a) => a.name === artifact)?.kind ?? 'mesh';
    this.runTarget = { jobId, artifact, kind };
    this.algorithmsPanel.setMesh(`${artifact} of ${job.algorithm}`);
    this.renderJobs();
  }

  async cancel(id: string): Promise<void> {
    try {
      this.upsertJob(await cancelJob(id));
    } catch (e) {
      this.error(`Cannot cancel the job: ${describe(e)}`);
      void getJob(id).then((j) => this.upsertJob(j), () => {});
    }
  }

  private static readonly FINAL = new Set(['done', 'failed', 'cancelled', 'interrupted']);

  /** Merges a Job in; a finished job never goes back to queued or running (events and answers may cross). */
  private upsertJob(job: Job, render = true): void {
    const old = this.jobs.get(job.id);
    if (old && App.FINAL.has(old.state) && !App.FINAL.has(job.state)) return;
    this.jobs.set(job.id, { ...old, ...job });
    const merged = this.jobs.get(job.id)!;
    if (merged.state === 'done') {
      this.loadMetrics(merged);
      if (this.autoShow.has(merged.id)) {
        this.autoShow.delete(merged.id);
        const field = merged.artifacts?.find((a) => a.kind === 'scalar_field');
        if (field) void this.showField(merged.id, field.name);
      }
      if (this.drawWhenDone.delete(merged.id)) {
        const skeleton = merged.artifacts?.find((a) => a.kind === 'skeleton');
        if (skeleton && !this.skeletons.has(`${merged.id}/${skeleton.name}`)) void this.toggleSkeleton(merged.id, skeleton.name);
      }
    } else if (merged.state === 'failed' && this.autoShow.has(merged.id)) {
      this.autoShow.delete(merged.id);
      this.error(`${merged.algorithm} failed: ${merged.error ?? 'no reason given'}`);
    } else if (App.FINAL.has(merged.state)) {
      this.autoShow.delete(merged.id);
    }
    if (merged.state !== 'done' && App.FINAL.has(merged.state)) this.drawWhenDone.delete(merged.id);
    if (render) this.renderJobs();
  }

  private progressJob(p: JobProgress): void {
    const old = this.jobs.get(p.id);
    if (!old) {
      // A job from another client that this page has not seen yet: ask for it once.
      if (this.asking.has(p.id)) return;
      this.asking.add(p.id);
      void getJob(p.id)
        .then((j) => this.upsertJob(j), () => {})
        .finally(() => this.asking.delete(p.id));
      return;
    }
    if (App.FINAL.has(old.state)) return;
    this.jobs.set(p.id, { ...old, state: p.state, progress: p.progress, stage: p.stage });
    this.renderJobs();
  }

  private loadMetrics(job: Job): void {
    for (const a of job.artifacts ?? []) {
      if (a.kind === 'text') {
        const key = `${job.id}/${a.name}`;
        if (this.texts.has(key)) continue;
        this.texts.set(key, undefined);
        fetchArtifactBytes(job.id, a.name, 'txt').then(
          (bytes) => {
            // Not necessarily UTF-8: undecodable bytes show as U+FFFD.
            this.texts.set(key, new TextDecoder('utf-8').decode(bytes));
            this.renderJobs();
          },
          (e) => {
            this.texts.set(key, `Cannot fetch ${a.name}: ${describe(e)}`);
            this.renderJobs();
          },
        );
        continue;
      }
      if (a.kind !== 'metrics') continue;
      const key = `${job.id}/${a.name}`;
      if (this.metrics.has(key)) continue;
      this.metrics.set(key, undefined);
      fetchArtifactJson(job.id, a.name).then(
        (data) => {
          this.metrics.set(key, data);
          this.renderJobs();
        },
        (e) => {
          this.metrics.set(key, `Cannot fetch ${a.name}: ${describe(e)}`);
          this.renderJobs();
        },
      );
    }
  }

  private renderJobs(): void {
    const jobs = [...this.jobs.values()].sort((a, b) => String(a.created ?? '').localeCompare(String(b.created ?? '')));
    this.jobsPanel.render({
      jobs,
      meshName: (id) => this.meshes.find((m) => m.id === id)?.name ?? null,
      // The single field is hidden while fields are compared.
      shown: this.field && !this.compared.length ? { jobId: this.field.jobId, artifact: this.field.artifact } : null,
      compared: new Set(this.compared.map((c) => `${c.jobId}/${c.artifact}`)),
      added: this.added,
      target: this.runTarget ? `${this.runTarget.jobId}/${this.runTarget.artifact}` : null,
      metrics: this.metrics,
      texts: this.texts,
      skeletons: new Map([...this.skeletons].map(([k, v]) => [k, v.color])),
      mayChange: (owner) => this.mayChange(owner),
    });
    this.renderSkeletons();
  }

  /** The comparison table of the skeletons drawn; asks the server for each one's distance to the first. */
  private renderSkeletons(): void {
    const keys = [...this.skeletons.keys()];
    const input = (key: string) => {
      const { jobId, artifact } = splitKey(key);
      return { job: jobId, artifact };
    };
    const metricsOf = (jobId: string) => {
      const m = this.metrics.get(`${jobId}/metrics`);
      return m && typeof m === 'object' ? (m as Record<string, unknown>) : undefined;
    };
    this.skeletonsPanel.render(
      keys.map((key, i) => {
        const { jobId: job } = splitKey(key);
        let distance: { hausdorff: number; mean: number } | undefined | null = null;
        if (i > 0) {
          const pair = `${keys[0]}|${key}`;
          const distanceJob = this.distanceJobs.get(pair);
          if (distanceJob === undefined) {
            this.distanceJobs.set(pair, '');
            submitJob('skeleton_distance', { skeleton: input(keys[0]!), reference: input(key) }, {})
              .then((j) => {
                this.distanceJobs.set(pair, j.id);
                this.upsertJob(j);
              })
              .catch((e) => this.error(`Cannot measure the distance between skeletons: ${describe(e)}`));
          }
          const m = distanceJob ? metricsOf(distanceJob) : undefined;
          distance = m && typeof m.hausdorff === 'number' && typeof m.mean === 'number' ? { hausdorff: m.hausdorff, mean: m.mean } : undefined;
        }
        return {
          key,
          color: this.skeletons.get(key)!.color,
          algorithm: this.jobs.get(job)?.algorithm ?? job,
          metrics: metricsOf(job),
          distance,
        };
      }),
      this.selectedMesh() !== null,
    );
  }

  private meshPly(meshId: string): Promise<PlyMesh> {
    let p = this.plyCache.get(meshId);
    if (!p) {
      p = fetchMeshBytes(meshId, 'ply').then(parsePly);
      p.catch(() => this.plyCache.delete(meshId));
      this.plyCache.set(meshId, p);
    }
    return p;
  }

  /**
   * The job's scalar_field artifact and its mesh, with that mesh selected
   * (the selection drops what was drawn on another mesh); null, with an error
   * shown, when the job, the artifact or the mesh is gone.
   */
  private fieldSource(jobId: string, artifactName: string): FieldSource | null {
    const job = this.jobs.get(jobId);
    const artifact = job?.artifacts?.find((a) => a.name === artifactName);
    const meshId = jobMeshId(job);
    if (!job || !artifact || !meshId) return null;
    if (this.selectedId !== meshId) {
      if (!this.meshes.some((m) => m.id === meshId)) {
        this.error(`Cannot show ${artifactName} of ${job.algorithm}: its mesh no longer exists`);
        return null;
      }
      this.select(meshId);
    }
    return { job, artifact, meshId };
  }

  /**
   * Fetches a scalar_field artifact: the values as f32, the range and location
   * from the Job, the mesh in the server's vertex order (viewer/ply.ts).
   */
  private async loadField(jobId: string, artifact: ArtifactInfo, meshId: string): Promise<{ data: ScalarField; ply: PlyMesh }> {
    const [values, ply] = await Promise.all([fetchArtifactF32(jobId, artifact.name), this.meshPly(meshId), this.showing]);
    const location = artifact.location ?? (values.length === ply.faces && values.length !== ply.vertices ? 'face' : 'vertex');
    let range: [number, number] =
      artifact.range && artifact.range.length === 2 && artifact.range.every(Number.isFinite) ? artifact.range : finiteRange(values);
    if (artifact.hint === 'symmetric') {
      const m = Math.max(Math.abs(range[0]), Math.abs(range[1]));
      range = [-m, m];
    }
    return { data: { name: artifact.name, location, values, range }, ply };
  }

  /** Draws a job's scalar_field artifact on its mesh, in place of a comparison (selecting that mesh first when another one is shown). */
  async showField(jobId: string, artifactName: string): Promise<void> {
    const source = this.fieldSource(jobId, artifactName);
    if (!source) return;
    const { job, artifact, meshId } = source;
    this.leaveComparison();
    const token = ++this.fieldToken;
    try {
      const { data, ply } = await this.loadField(jobId, artifact, meshId);
      if (token !== this.fieldToken || this.selectedId !== meshId) return;
      const mapName = this.mapName ?? defaultMapFor(artifact.hint);
      const object = buildScalarSurface(ply, data, mapName);
      this.field = { jobId, artifact: artifactName, meshId, data, object, map: mapName, fullRange: data.range };
      this.hooks.lastField = null;
      this.textures.detach(); // the field's surface replaces the textured one
      this.viewer.replace(object, () => {
        if (this.viewer.object === object) this.hooks.lastField = this.fieldHook();
      });
      this.showFieldLegend();
      this.display.setField({ range: data.range, full: data.range, values: data.values });
      this.renderJobs();
    } catch (e) {
      if (token !== this.fieldToken) return;
      this.error(`Cannot show ${artifactName} of ${job.algorithm}: ${describe(e)}`);
    }
  }

  /**
   * Draws a job's skeleton artifact over its mesh (fetched as JSON), each in
   * its own colour, so that skeletons from several algorithms compare at a
   * glance (the paper's Figure 5); a second click hides it.
   */
  async toggleSkeleton(jobId: string, artifactName: string): Promise<void> {
    const key = `${jobId}/${artifactName}`;
    const drawn = this.skeletons.get(key);
    if (drawn) {
      this.viewer.removeExtra(drawn.object);
      this.skeletons.delete(key);
      this.renderJobs();
      this.viewer.redraw(() => this.reportSkeletons());
      return;
    }
    const job = this.jobs.get(jobId);
    if (!job) return;
    this.selectMeshOf(job);
    const selected = this.selectedId;
    try {
      const [json] = await Promise.all([fetchArtifactJson(jobId, artifactName), this.showing]);
      if (this.selectedId !== selected || this.skeletons.has(key)) return;
      const data = parseSkeleton(json);
      const palette = SKELETON_COLORS;
      const used = new Set([...this.skeletons.values()].map((v) => v.color));
      const color = palette.find((c) => !used.has(c)) ?? palette[this.skeletons.size % palette.length]!;
      const object = buildSkeleton(data, color);
      this.skeletons.set(key, { object, data, color, nodes: data.nodes.length / 3, edges: data.edges.length / 2 });
      this.viewer.addExtra(object, () => this.reportSkeletons());
      this.renderJobs();
    } catch (e) {
      this.error(`Cannot show ${artifactName} of ${job.algorithm}: ${describe(e)}`);
    }
  }

  /**
   * "Load skeleton file…": the file's text goes to a skeleton_file job on the
   * shown mesh (the server parses it: a bad file is refused naming its line),
   * whose skeleton is drawn when it is done, measured and compared as any.
   */
  async loadSkeletonFile(file: File): Promise<void> {
    const mesh = this.selectedMesh();
    if (!mesh) return this.error('Choose a mesh first: a skeleton file is attached to the mesh shown.');
    try {
      const job = await submitJob('skeleton_file', { mesh: mesh.id }, { name: file.name, text: await file.text() });
      this.drawWhenDone.add(job.id);
      // A job_done event may have come before this answer: upsertJob keeps the
      // later state, and a job done already is drawn now.
      this.upsertJob(job);
      const now = this.jobs.get(job.id);
      if (now?.state === 'done' && this.drawWhenDone.has(job.id)) this.upsertJob(now);
    } catch (e) {
      this.error(`Cannot load the skeleton file ${file.name}: ${describe(e)}`);
    }
  }

  private reportSkeletons(): void {
    this.hooks.skeletons = [...this.skeletons].map(([key, v]) => ({ key, color: v.color, nodes: v.nodes, edges: v.edges }));
  }

  /** "Compare": every scalar field of the job side by side (at most MAX_PANES). */
  compareJob(jobId: string): void {
    const fields = this.jobs.get(jobId)?.artifacts?.filter((a) => a.kind === 'scalar_field') ?? [];
    if (fields.length > App.MAX_PANES) this.messages.notice(`Comparing the first ${App.MAX_PANES} of ${fields.length} fields.`);
    void this.compare(fields.slice(0, App.MAX_PANES).map((a) => ({ jobId, artifact: a.name })));
  }

  /** "Add to comparison": the field joins the fields compared now (or the one shown), on the same mesh. */
  addToComparison(jobId: string, artifact: string): void {
    const now = this.compared.length ? this.compared : this.field ? [{ jobId: this.field.jobId, artifact: this.field.artifact }] : [];
    if (now.some((c) => c.jobId === jobId && c.artifact === artifact)) return;
    const meshId = jobMeshId(this.jobs.get(jobId));
    const other = now.find((c) => jobMeshId(this.jobs.get(c.jobId)) !== meshId);
    if (other) return this.error(`Cannot compare ${artifact}: it is on another mesh than ${other.artifact}; compare fields of one mesh.`);
    if (now.length >= App.MAX_PANES) return this.error(`At most ${App.MAX_PANES} fields side by side: leave the comparison first.`);
    void this.compare([...now, { jobId, artifact }]);
  }

  private static readonly MAX_PANES = 4;

  /** Shows the fields (all on one mesh) side by side in synchronized panes, each with its legend. */
  private async compare(list: Array<{ jobId: string; artifact: string }>): Promise<void> {
    const sources: FieldSource[] = [];
    for (const c of list) {
      const source = this.fieldSource(c.jobId, c.artifact);
      if (!source) return;
      sources.push(source);
    }
    const meshId = sources[0]?.meshId;
    if (!meshId || sources.some((s) => s.meshId !== meshId)) return;
    const token = ++this.compareToken;
    try {
      const loaded = await Promise.all(sources.map((s) => this.loadField(s.job.id, s.artifact, meshId)));
      if (token !== this.compareToken || this.selectedId !== meshId) return;
      this.compared = list;
      this.endSceneSideBySide();
      this.hooks.lastCompare = null;
      this.legend.hide();
      this.comparison.show(
        loaded[0]!.ply,
        loaded.map(({ data }, i) => ({ key: `${list[i]!.jobId}/${list[i]!.artifact}`, title: `${sources[i]!.job.algorithm} · ${data.name}`, data, hint: sources[i]!.artifact.hint })),
      );
      this.leaveCompare.hidden = false;
      this.renderJobs();
    } catch (e) {
      if (token !== this.compareToken) return;
      this.error(`Cannot compare the fields: ${describe(e)}`);
    }
  }

  /** The skeletons drawn, side by side: one pane each, over the plain surface, through the one camera. */
  private async compareSkeletons(): Promise<void> {
    const list = [...this.skeletons].slice(0, App.MAX_PANES);
    const meshId = this.selectedId;
    if (list.length < 2 || !meshId) return;
    const token = ++this.compareToken;
    try {
      const ply = await this.meshPly(meshId);
      if (token !== this.compareToken || this.selectedId !== meshId) return;
      this.compared = list.map(([key]) => splitKey(key));
      this.endSceneSideBySide();
      this.hooks.lastCompare = null;
      this.legend.hide();
      this.comparison.showObjects(
        list.map(([key, s]) => {
          const group = new THREE.Group();
          group.add(buildPlainSurface(ply.positions, ply.indices, SURFACE_COLOR), buildSkeleton(s.data, s.color));
          const { jobId } = splitKey(key);
          return { key, title: this.jobs.get(jobId)?.algorithm ?? jobId, object: group, color: s.color };
        }),
      );
      this.leaveCompare.hidden = false;
      this.renderJobs();
    } catch (e) {
      if (token !== this.compareToken) return;
      this.error(`Cannot show the skeletons side by side: ${describe(e)}`);
    }
  }

  /** Back to one view: the field drawn before the comparison (if any) with its legend. */
  leaveComparison(): void {
    ++this.compareToken;
    if (!this.compared.length && !this.scenePanes) return;
    this.compared = [];
    if (this.scenePanes) {
      this.scenePanes = false;
      this.renderScene();
    }
    this.hooks.lastCompare = null;
    this.comparison.clear();
    this.leaveCompare.hidden = true;
    if (this.field) this.showFieldLegend();
    this.renderJobs();
  }

  /** Selects the mesh a job ran on (when it is another one, and still stored), so that what the job made is drawn on it. */
  private selectMeshOf(job: Job): void {
    const meshId = jobMeshId(job);
    if (meshId && this.selectedId !== meshId && this.meshes.some((m) => m.id === meshId)) this.select(meshId);
  }

  /** Adds a job's mesh artifact (fetched as binary PLY) to the view, beside its input mesh. */
  async addMeshArtifact(jobId: string, artifactName: string): Promise<void> {
    const job = this.jobs.get(jobId);
    if (!job) return;
    this.selectMeshOf(job);
    const selected = this.selectedId;
    try {
      const [bytes] = await Promise.all([fetchArtifactBytes(jobId, artifactName, 'ply'), this.showing]);
      if (this.selectedId !== selected) return;
      const ply = parsePly(bytes);
      const object = buildPlainSurface(ply.positions, ply.indices);
      const key = `${jobId}/${artifactName}`;
      this.viewer.addExtra(object, () => {
        this.hooks.lastExtra = { jobId, artifact: artifactName, vertices: ply.vertices, faces: ply.faces };
      });
      this.added.add(key);
      this.renderJobs();
    } catch (e) {
      this.error(`Cannot add ${artifactName} of ${job.algorithm}: ${describe(e)}`);
    }
  }

  /**
   * Shows a job's animation artifact (.frames: chaos_animate) as points in
   * place of the mesh, with the player's slider and play button over the
   * view; the camera frames the box of every frame.
   */
  async showAnimation(jobId: string, artifactName: string): Promise<void> {
    const job = this.jobs.get(jobId);
    if (!job) return;
    const token = ++this.animationToken;
    try {
      // Over the WebSocket, as quantized deltas (protocol/API.md, get_animation).
      const [bytes] = await Promise.all([this.socket.getAnimation(jobId, artifactName), this.showing]);
      if (token !== this.animationToken) return;
      const frames = decodeFrames(bytes);
      this.leaveComparison();
      if (this.field) this.dropField();
      const positions = framePositions(frames, 0, new Float32Array(3 * frames.vertices));
      const geometry = new THREE.BufferGeometry();
      const attribute = new THREE.BufferAttribute(positions, 3);
      attribute.setUsage(THREE.DynamicDrawUsage);
      geometry.setAttribute('position', attribute);
      // The box of every frame, so that fit-to-view and culling hold for all.
      geometry.boundingBox = new THREE.Box3(new THREE.Vector3(...frames.lo), new THREE.Vector3(...frames.hi));
      geometry.boundingSphere = geometry.boundingBox.getBoundingSphere(new THREE.Sphere());
      const size = geometry.boundingSphere.radius / 150;
      const points = new THREE.Points(geometry, new THREE.PointsMaterial({ color: '#e07a1f', size, sizeAttenuation: true }));
      points.name = 'animation';
      this.hooks.lastAnimation = null;
      this.textures.detach();
      this.viewer.show(points);
      this.player.show(`${job.algorithm} · ${artifactName}`, frames.frames, (k) => {
        if (this.viewer.object !== points) return;
        framePositions(frames, k, positions);
        attribute.needsUpdate = true;
        this.viewer.redraw(() => {
          if (this.viewer.object !== points) return;
          let sum = 0;
          for (let i = 0; i < positions.length; ++i) sum += positions[i]!;
          this.hooks.lastAnimation = {
            jobId, artifact: artifactName, frame: k, frames: frames.frames, vertices: frames.vertices,
            first: [positions[0]!, positions[1]!, positions[2]!], sum,
          };
        });
      });
    } catch (e) {
      if (token !== this.animationToken) return;
      this.error(`Cannot show ${artifactName} of ${job.algorithm}: ${describe(e)}`);
    }
  }

  private fieldHook(): TestHooks['lastField'] {
    const f = this.field!;
    return { jobId: f.jobId, artifact: f.artifact, meshId: f.meshId, location: f.data.location, count: f.data.values.length, range: f.data.range, map: f.map };
  }

  private showFieldLegend(): void {
    const f = this.field!;
    this.legend.show(`${this.jobs.get(f.jobId)?.algorithm ?? ''} · ${f.artifact}`, f.data.range, f.map, f.data.values);
  }

  private setColorMap(name: string): void {
    this.mapName = name;
    const f = this.field;
    if (!f) return;
    f.map = name;
    colourGeometry(f.object.geometry, f.data, name);
    this.showFieldLegend();
    this.viewer.redraw(() => {
      if (this.field === f) this.hooks.lastField = this.fieldHook();
    });
  }

  /** Stops drawing a scalar field (the next mesh shown is plain). */
  private dropField(): void {
    ++this.fieldToken;
    this.field = null;
    this.hooks.lastField = null;
    this.legend.hide();
    this.display.setField(null);
  }

  /** Recolours the field drawn over `range` (null: its full range), without fetching it again. */
  private setFieldRange(range: [number, number] | null): void {
    const f = this.field;
    if (!f) return;
    f.data.range = range ?? f.fullRange;
    colourGeometry(f.object.geometry, f.data, f.map);
    this.showFieldLegend();
    this.display.setField({ range: f.data.range, full: f.fullRange, values: f.data.values });
    this.viewer.redraw(() => {
      if (this.field === f) this.hooks.lastField = this.fieldHook();
    });
  }

  /** "Copy link": the view (camera, mesh, display, overlays, field) in the page's hash; copied to the clipboard where the page may. */
  private copyViewLink(): void {
    const meshId = this.selectedId;
    if (!meshId) return this.error('Choose a mesh first: a view link reopens a mesh.');
    const { display, overlays } = this.display.state();
    const state: ViewState = { v: 1, mesh: meshId, camera: readCamera(this.viewer), display: { ...display }, overlays: { ...overlays } };
    // The scene, when there is more to it than the mesh as it was loaded (old readers see the mesh alone).
    const scene = this.scene.map(({ name: _n, object: _o, ...e }) => ({ ...e }));
    if (scene.length > 1 || scene.some((e) => !e.visible || e.color !== null || !isIdentity(e))) state.scene = scene;
    if (this.scenePanes) state.panes = true;
    const f = this.field;
    if (f && f.meshId === meshId) state.field = { job: f.jobId, artifact: f.artifact, map: f.map, range: f.data.range };
    // Never the token: it stays in this browser's storage (api/auth.ts).
    const url = `${location.origin}${location.pathname}${location.search}${encodeViewHash(state)}`;
    history.replaceState(null, '', url);
    this.display.showLink(url);
    this.hooks.lastLink = url;
    navigator.clipboard?.writeText(url).then(
      () => this.messages.notice('View link copied.'),
      () => this.messages.notice('View link: copy it from the Display panel.'),
    );
  }

  /** Opens the view of the page's #view= link, if any: its mesh, display, overlays and field, then its camera. */
  private async restoreView(): Promise<void> {
    let state: ViewState | null;
    try {
      state = decodeViewHash(location.hash);
    } catch (e) {
      this.hooks.viewRestored = { error: describe(e) };
      return this.error(`Cannot open the view link: ${describe(e)}`);
    }
    if (!state) return;
    if (!this.meshes.some((m) => m.id === state.mesh)) {
      const error = `the mesh ${state.mesh} of the view link no longer exists`;
      this.hooks.viewRestored = { error };
      return this.error(`Cannot open the view link: ${error}`);
    }
    let scene: SceneObjectState[] = [];
    try {
      scene = state.scene ? sanitizeScene(state.scene) : [];
    } catch (e) {
      this.hooks.viewRestored = { error: describe(e) };
      return this.error(`Cannot open the view link: ${describe(e)}`);
    }
    this.select(state.mesh);
    if (scene[0]) this.changeSceneObject(0, scene[0]);
    await this.showing;
    const missing = scene.slice(1).filter((o) => !this.meshes.some((m) => m.id === o.mesh));
    if (missing.length) this.error(`The view link's meshes ${missing.map((o) => o.mesh).join(', ')} no longer exist; the scene is shown without them.`);
    await Promise.all(scene.slice(1).filter((o) => !missing.includes(o)).map((o) => this.addToScene(o.mesh, o)));
    this.display.restore(state.display, state.overlays);
    if (state.field) {
      this.mapName = state.field.map;
      await this.showField(state.field.job, state.field.artifact);
      if (this.field) this.setFieldRange(state.field.range);
    }
    if (state.panes && this.scene.length > 1) this.showSceneSideBySide();
    applyCamera(this.viewer, state.camera);
    const mode = this.display.state().display.mode;
    this.viewer.redraw(() => (this.hooks.viewRestored = { camera: readCamera(this.viewer), mode }));
  }

  private selectedMesh(): Mesh | null {
    return this.meshes.find((m) => m.id === this.selectedId) ?? null;
  }

  /** Reloads the mesh list from the server. */
  async refresh(): Promise<void> {
    try {
      this.meshes = await listMeshes();
      if (this.selectedId && !this.meshes.some((m) => m.id === this.selectedId)) this.forget(this.selectedId);
      this.renderList();
    } catch (e) {
      this.renderList();
      this.error(`Cannot list meshes: ${describe(e)}`);
    }
  }

  /** Uploads files one after the other (a mesh with its MTL and images as one zip) and shows the last one uploaded. */
  async upload(files: File[]): Promise<void> {
    let last: Mesh | null = null;
    let uploads: Array<{ name: string; body: Blob }> = [];
    try {
      uploads = await uploadsOf(files);
    } catch (e) {
      this.error(`Upload failed: ${describe(e)}`);
    }
    for (const file of uploads) {
      this.progress.show('uploading', null, file.name);
      try {
        const mesh = await uploadMesh(file.name, file.body);
        this.upsert(mesh);
        for (const w of mesh.warnings ?? []) this.messages.notice(`${mesh.name}: ${w}`);
        last = mesh;
      } catch (e) {
        this.error(`Upload of ${file.name} failed: ${describe(e)}`);
      } finally {
        this.progress.hide();
      }
    }
    if (last) this.select(last.id);
  }

  select(id: string): void {
    const mesh = this.meshes.find((m) => m.id === id);
    if (!mesh) return;
    this.selectedId = id;
    // A plain click shows this mesh alone: the scene starts again from it (show() clears the viewer's extras).
    this.leaveComparison();
    this.scene = [{ ...defaultSceneObject(id), name: mesh.name, object: null }];
    this.pickSceneObject(0);
    this.renderScene();
    if (this.runTarget) {
      this.runTarget = null;
      this.renderJobs();
    }
    this.renderList();
    this.report.render(mesh);
    this.algorithmsPanel.setMesh(mesh.name);
    this.selectionTool.setSource(id, (meshId) => this.meshPly(meshId));
    this.showing = this.show(mesh);
  }

  async remove(id: string): Promise<void> {
    const mesh = this.meshes.find((m) => m.id === id);
    try {
      await deleteMesh(id);
      this.forget(id);
    } catch (e) {
      this.error(`Cannot delete ${mesh?.name ?? id}: ${describe(e)}`);
    }
  }

  /** Downloads the mesh over the WebSocket, decodes it in the worker and shows it. */
  private async show(mesh: Mesh): Promise<void> {
    this.load?.controller.abort();
    this.leaveComparison();
    ++this.animationToken;
    this.player.hide();
    this.hooks.lastAnimation = null;
    if (this.field || this.added.size || this.skeletons.size) {
      this.dropField();
      this.added.clear(); // show() below clears the viewer's extras
      this.skeletons.clear();
      this.hooks.lastExtra = null;
      this.hooks.skeletons = [];
      this.renderJobs();
    }
    const load = { id: mesh.id, controller: new AbortController() };
    this.load = load;
    const current = () => this.load === load;
    const timer = new LoadTimer(); // of the full mesh
    // A big mesh's preview (API.md "Big meshes") is shown while the full mesh
    // streams and decodes, then replaced without moving the camera.
    // The preview and the full mesh decode in that order in the one worker, so
    // the preview is in the viewer before the full mesh is decoded; the swap
    // waits for the preview's first frame (settled at the next frame), so the
    // preview is always drawn once, however fast the full mesh comes.
    let preview: THREE.Object3D | null = null;
    let previewDrawn: Promise<void> = Promise.resolve();
    let fullDecoded = false;
    const stage = (what: string) => (preview ? `preview shown, ${what} full mesh` : what);
    const showPreview = async (transfer: MeshTransfer) => {
      const decoded = await this.decoder.decode(transfer.payload);
      if (!current() || fullDecoded) return;
      const object = buildSurface(decoded);
      preview = object;
      previewDrawn = new Promise<void>((drawn) =>
        this.viewer.show(object, () => {
          drawn();
          if (this.viewer.object !== object) return;
          this.hooks.lastPreview = { id: mesh.id, vertices: decoded.vertices, faces: decoded.faces, camera: readCamera(this.viewer), fullCamera: null };
        }),
      );
      this.progress.show(stage('downloading'), null, mesh.name);
    };
    try {
      this.hooks.lastPreview = null;
      const loaded = await this.downloadMesh(mesh, load.controller.signal, current, timer, {
        stage,
        onPreview: (t) => {
          showPreview(t).catch((e) => console.warn('cgview: the preview could not be shown', e));
        },
      });
      if (!loaded) return;
      fullDecoded = true;
      const { decoded, bytes } = loaded;
      const object = buildSurface(decoded);
      timer.mark('geometry-built');
      this.textures.attach(object, mesh);
      await previewDrawn;
      if (!current()) return;
      const swap = preview !== null && this.viewer.object === preview;
      const onShown = () => {
        if (this.viewer.object !== object) return;
        timer.mark('first-frame');
        this.hooks.timings = null;
        this.hooks.lastLoaded = { id: mesh.id, vertices: decoded.vertices, faces: decoded.faces, bytes };
        if (swap && this.hooks.lastPreview?.id === mesh.id) this.hooks.lastPreview.fullCamera = readCamera(this.viewer);
        void timer.markGpuDone(this.viewer.renderer.getContext()).then(() => {
          if (this.viewer.object === object) this.hooks.timings = timer.finish();
        });
      };
      if (swap) this.viewer.replace(object, onShown);
      else this.viewer.show(object, onShown);
      this.progress.hide();
    } catch (e) {
      if (isAbort(e) || !current()) return;
      this.progress.hide();
      this.error(`Cannot show ${mesh.name}: ${describe(e)}`);
    } finally {
      if (current()) this.load = null;
    }
  }

  /**
   * Downloads a mesh over the WebSocket (with the progress bar while
   * `current()`) and decodes it in the worker; null when no longer current.
   * With `preview`, a big mesh's decimated preview is asked for first and
   * handed to `preview.onPreview`; `preview.stage` words the full mesh's
   * stages (once the preview is shown). `timer` times the full mesh only.
   */
  private async downloadMesh(
    mesh: Mesh,
    signal: AbortSignal,
    current: () => boolean,
    timer: LoadTimer,
    preview?: { onPreview: (transfer: MeshTransfer) => void; stage: (what: string) => string },
  ): Promise<{ decoded: Awaited<ReturnType<DracoDecoder['decode']>>; bytes: number } | null> {
    const stage = preview?.stage ?? ((what: string) => what);
    let inPreview = false;
    this.progress.show('downloading', 0, mesh.name);
    const transfer = await this.socket.getMesh(mesh.id, {
      signal,
      onSent: () => timer.mark('request'),
      onBegin: (begin) => {
        inPreview = begin.level === 'preview';
        if (!inPreview) timer.mark('first-byte');
      },
      onProgress: (received, total) => {
        if (!inPreview) {
          if (received > 0) timer.mark('first-chunk');
          if (received >= total) timer.mark('last-chunk');
        }
        if (current()) this.progress.show(inPreview ? 'downloading preview of' : stage('downloading'), total > 0 ? received / total : 0, mesh.name);
      },
      ...(preview && {
        onPreview: (t: MeshTransfer) => {
          inPreview = false;
          preview.onPreview(t);
        },
      }),
    });
    if (!current()) return null;
    this.progress.show(stage('decoding'), null, mesh.name);
    const bytes = transfer.payload.byteLength; // before the worker takes the buffer
    timer.mark('decode-start');
    const decoded = await this.decoder.decode(transfer.payload);
    if (!current()) return null;
    timer.mark('decode-end');
    timer.setWorkerTiming(decoded.timing);
    return { decoded, bytes };
  }

  // The scene: several meshes at once.

  /**
   * "+" in the mesh list: draws the mesh beside the scene's objects, in the
   * next colour and the display mode of the others (with nothing shown, it
   * is shown as a click would). `state` (a view link's) gives its visibility,
   * colour and transform. Resolves once it is drawn (or has failed).
   */
  async addToScene(id: string, state?: SceneObjectState): Promise<void> {
    const mesh = this.meshes.find((m) => m.id === id);
    if (!mesh) return;
    if (!this.scene.length) {
      this.select(id);
      return;
    }
    if (this.scene.length >= MAX_SCENE_OBJECTS) return this.error(`A scene holds at most ${MAX_SCENE_OBJECTS} objects.`);
    const entry: SceneEntry = { ...(state ?? defaultSceneObject(id, sceneColor(this.scene.length - 1))), mesh: id, name: mesh.name, object: null };
    this.scene.push(entry);
    this.renderScene();
    const inScene = () => this.scene.includes(entry);
    try {
      await this.showing; // the first object's show() clears the viewer's extras
      if (!inScene()) return;
      const controller = new AbortController();
      const loaded = await this.downloadMesh(mesh, controller.signal, inScene, new LoadTimer());
      this.progress.hide();
      if (!loaded || !inScene()) return;
      const object = buildSurface(loaded.decoded);
      object.name = `scene:${mesh.name}`;
      entry.object = object;
      applySceneTransform(object, entry);
      this.display.applyTo(object);
      if (this.scene[this.picked] === entry) this.display.setOverlayObject(object);
      await new Promise<void>((resolve) => this.viewer.addExtra(object, resolve));
      if (this.scenePanes) this.showSceneSideBySide();
    } catch (e) {
      this.progress.hide();
      if (!inScene()) return;
      this.scene.splice(this.scene.indexOf(entry), 1);
      this.renderScene();
      this.error(`Cannot add ${mesh.name} to the scene: ${describe(e)}`);
    }
  }

  /** The drawn object of scene entry `e` (the first: whatever the viewer shows for the selected mesh). */
  private sceneObject(index: number): THREE.Object3D | null {
    return index === 0 ? this.viewer.object : (this.scene[index]?.object ?? null);
  }

  private sceneEntryOf(object: THREE.Object3D): SceneEntry | null {
    const i = this.scene.findIndex((_, k) => this.sceneObject(k) === object);
    return i >= 0 ? this.scene[i]! : null;
  }

  /** A new shown object (the selected mesh, its field, an animation) takes the first scene object's place and transform. */
  private shownChanged(object: THREE.Object3D | null): void {
    const first = this.scene[0];
    if (object && first && first.mesh === this.selectedId) applySceneTransform(object, first);
  }

  private changeSceneObject(index: number, patch: Partial<SceneObjectState>): void {
    const entry = this.scene[index];
    if (!entry) return;
    Object.assign(entry, patch);
    const object = this.sceneObject(index);
    if (object) {
      applySceneTransform(object, entry);
      if (patch.color !== undefined) this.display.applyTo(object);
      if (index === this.picked) this.display.refreshOverlays();
    }
    this.viewer.requestRender();
  }

  private removeSceneObject(index: number): void {
    const entry = this.scene[index];
    if (!entry || index === 0) return;
    this.scene.splice(index, 1);
    if (index === this.picked) this.pickSceneObject(0);
    else if (index < this.picked) --this.picked;
    const wasPanes = this.scenePanes;
    if (wasPanes) this.leaveComparison();
    if (entry.object) this.viewer.removeExtra(entry.object);
    if (wasPanes && this.scene.length >= 2) this.showSceneSideBySide();
    this.renderScene();
  }

  /** The scene's objects side by side, one per pane, all through the one camera; framed together. */
  private showSceneSideBySide(): void {
    const items = this.scene.flatMap((e, i) => {
      const object = this.sceneObject(i);
      return object ? [{ key: `scene:${i}`, title: e.name, object, color: e.color ?? this.display.state().display.color }] : [];
    });
    if (items.length < 2) return this.error('Side by side needs two objects in the scene: add one with “+” in the mesh list.');
    ++this.compareToken;
    this.compared = [];
    this.hooks.lastCompare = null;
    this.legend.hide();
    this.comparison.showObjects(items, false);
    this.scenePanes = true;
    this.leaveCompare.hidden = false;
    this.viewer.fitAll();
    this.renderScene();
  }

  /** Forgets that the scene is side by side (a comparison of fields takes the panes). */
  private endSceneSideBySide(): void {
    if (!this.scenePanes) return;
    this.scenePanes = false;
    this.renderScene();
  }

  /** Chooses scene object `index` for the overlays (the first: the shown object, whatever it is). */
  private pickSceneObject(index: number): void {
    if (!this.scene[index]) index = 0;
    this.picked = index;
    this.display.setOverlayObject(index === 0 ? null : this.sceneObject(index));
    this.renderScene();
  }

  private renderScene(): void {
    this.scenePanel.render(this.scene, this.scenePanes, this.display.state().display.color, this.picked);
    if (this.meshes.length) this.renderList();
  }

  private sceneReport(): TestHooks['scene'] {
    // Drawn per pane with the pane's aspect (viewer.resize), or over the canvas.
    const objects = this.scene.map((e, i) => {
      const object = this.sceneObject(i);
      const pane = object ? this.viewer.paneOf(object) : -1;
      const { name, object: _, ...state } = e;
      return { ...state, position: [...e.position] as SceneObjectState['position'], rotation: [...e.rotation] as SceneObjectState['rotation'], name, loaded: !!object, pane, box: object ? projectedBox(object, this.viewer.camera) : null };
    });
    return { panes: this.scenePanes ? objects.filter((o) => o.pane >= 0).length : 0, picked: this.picked, objects };
  }

  private upsert(mesh: Mesh): void {
    this.plyCache.delete(mesh.id);
    const i = this.meshes.findIndex((m) => m.id === mesh.id);
    if (i >= 0) this.meshes[i] = mesh;
    else this.meshes.push(mesh);
    this.renderList();
    if (mesh.id === this.selectedId) this.report.render(mesh);
  }

  /** Drops a mesh that no longer exists on the server; clears the view if it was shown. */
  private forget(id: string): void {
    this.meshes = this.meshes.filter((m) => m.id !== id);
    for (let i = this.scene.length - 1; i > 0; --i) if (this.scene[i]!.mesh === id) this.removeSceneObject(i);
    this.plyCache.delete(id);
    if (this.selectedId === id) {
      this.selectedId = null;
      this.algorithmsPanel.setMesh(null);
      this.selectionTool.setSource(null, (meshId) => this.meshPly(meshId));
      this.leaveComparison();
      if (this.field) this.dropField();
      if (this.load?.id === id) {
        this.load.controller.abort();
        this.load = null;
        this.progress.hide();
      }
      this.viewer.clearAll();
      this.textures.detach();
      this.added.clear();
      this.skeletons.clear();
      this.hooks.skeletons = [];
      this.hooks.lastExtra = null;
      this.hooks.lastLoaded = null;
      this.hooks.timings = null;
      this.report.render(null);
      this.scene = [];
      this.scenePanes = false;
      this.renderScene();
    }
    this.renderList();
  }

  private renderList(): void {
    this.list.render(this.meshes, this.selectedId, new Set(this.scene.map((e) => e.mesh)));
    this.algorithmsPanel.setMeshes(this.meshes.map((m) => ({ id: m.id, name: m.name })));
    if (this.jobs.size) this.renderJobs(); // mesh names in the job panel
  }

  private error(text: string): void {
    this.hooks.lastError = text;
    this.messages.error(text);
  }
}
