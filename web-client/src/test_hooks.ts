// What the tests read: window.__cgview. Controllers and kinds write the parts
// they own (see each field); nothing in the page reads them back.
import type { CameraState } from './viewer/navigation.ts';
import type { DisplayReport } from './controllers/display.ts';
import type { SceneObjectState } from './viewer/scene_state.ts';
import type { ViewState } from './viewer/view_state.ts';
import type { OrbitTimes } from './viewer/frame_timer.ts';
import type { LoadTimings } from './viewer/timings.ts';
import type { TextureState } from './viewer/textures.ts';
import type { LectureRole, ReplayClock } from './state/app_state.ts';

/** What tests read (window.__cgview). */
export interface TestHooks {
  /** True once the page is set up and the first mesh list has been asked for. */
  ready: boolean;
  /**
   * The mesh in the viewer, set after the first frame showing it has rendered;
   * bytes: the Draco payload received for it; points: it was a point cloud,
   * drawn as points (how: `display.cloud`).
   */
  lastLoaded: { id: string; vertices: number; faces: number; bytes: number; points?: boolean } | null;
  /**
   * The durations of the load of lastLoaded (see viewer/timings.ts): null
   * when lastLoaded changes, set once the GPU has finished its first frame.
   */
  timings: LoadTimings | null;
  /** Frames rendered so far. */
  frames: number;
  /** "Undo" offers not yet ended (controllers/undo.ts): what they hold back (a DELETE) is not sent yet. */
  pendingUndo: number;
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
  /**
   * The vector fields drawn over the mesh, set after the first frame with
   * each change (a new length too): what is drawn (a LineSegments of
   * `points` points, two a vector drawn), vectors without a value, and the
   * segments' full length in mesh units.
   */
  vectors: Array<{
    key: string;
    color: string;
    location: string;
    hint: string;
    type: string;
    points: number;
    drawn: number;
    missing: number;
    length: number;
    scale: number;
  }>;
  /**
   * Jobs' points drawn over the mesh (kinds/points.ts), set after the first
   * frame with each change (a new point size too): key, colour, and as
   * drawn the points, their size in pixels, whether the file's colours and
   * normals are used.
   */
  points: Array<{ key: string; color: string; points: number; size: number; colors: boolean; normals: boolean }>;
  /** The selection (ids of the stored mesh), set after the frame that draws it. */
  selection?: { meshId: string | null; ready: boolean; kind: string; count: number; ids: number[]; area: number | null };
  /** The camera now: position, view direction, up, orbit centre, navigation mode. */
  camera?: () => CameraState;
  /** The camera's near and far planes as the last frame drew with them. */
  clipping?: () => { near: number; far: number };
  /** The camera's view for the selection: canvas size in CSS pixels, projection × view (column-major). */
  selectionView?: () => { width: number; height: number; viewProjection: number[] };
  /** The display mode, material and overlays of the shown object, set after the first frame with each change (controllers/display.ts). */
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
  /**
   * The live lecture this page takes part in (controllers/lecture.ts): its
   * role, room and join code, whether the view follows, who follows and
   * raised a hand (the presenter's), the hand shown to all, the presenter's
   * code, a replay's clock, and whether a follower's view is still being
   * shown (meshes loading, the camera gliding).
   */
  lecture?: () => {
    role: LectureRole;
    room: string | null;
    code: string | null;
    attached: boolean;
    followers: number;
    hands: string[];
    shownHand: string | null;
    presenterCode: string | null;
    replay: ReplayClock | null;
    busy: boolean;
  };
  /** Sends a room_set over this page's WebSocket (a follower's attempt to write): the refusal's code, or null when taken. */
  lectureWrite?: (part: string, value: unknown) => Promise<string | null>;
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

declare global {
  interface Window {
    __cgview: TestHooks;
  }
}

/** The hooks as the page starts, installed as window.__cgview; `orbit` times frames orbiting the shown object. */
export function installTestHooks(orbit: TestHooks['orbit']): TestHooks {
  const hooks: TestHooks = {
    ready: false,
    lastLoaded: null,
    timings: null,
    frames: 0,
    pendingUndo: 0,
    lastError: null,
    lastField: null,
    lastVoxels: null,
    lastCompare: null,
    algorithmsApi: null,
    lastExtra: null,
    lastAnimation: null,
    skeletons: [],
    vectors: [],
    points: [],
    display: null,
    lastLink: null,
    viewRestored: null,
    lastScreenshot: null,
    texture: null,
    lastPreview: null,
    orbit,
    scene: { panes: 0, picked: 0, objects: [] },
  };
  window.__cgview = hooks;
  return hooks;
}
