// The view link: what the viewer shows (camera, mesh, display mode and
// material, overlays, the scalar field with its colour map and range, the
// scene's objects with their transforms and whether they are side by side) as
// base64url JSON in the page's hash, `#view=...`, so that opening the link
// shows the same view. Pure (no DOM, no three.js), so that node's unit tests
// load it. Never holds the auth token: a link is something users share.

export const VIEW_HASH_KEY = 'view';

type Vec3 = [number, number, number];

export interface ViewState {
  /** Format version. */
  v: 1;
  /** The shown mesh's id. */
  mesh: string;
  camera: { position: Vec3; target: Vec3; up: Vec3; fov: number; near?: number; far?: number };
  /** Display settings (viewer/display_modes.ts), kept as given; the reader checks them. */
  display?: Record<string, unknown>;
  /** Overlay settings (viewer/overlays.ts), kept as given. */
  overlays?: Record<string, unknown>;
  /** The scalar field drawn, with its colour map and range. */
  field?: { job: string; artifact: string; map: string; range: [number, number] };
  /**
   * The scene's objects (viewer/scene_state.ts), the first one `mesh`'s,
   * each kept as given (the reader checks them); absent: `mesh` alone, as in
   * links made before scenes.
   */
  scene?: Array<Record<string, unknown>>;
  /** The scene's objects side by side, one per pane. */
  panes?: boolean;
}

function toBase64Url(text: string): string {
  let binary = '';
  for (const byte of new TextEncoder().encode(text)) binary += String.fromCharCode(byte);
  return btoa(binary).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
}

function fromBase64Url(b64: string): string {
  const std = b64.replace(/-/g, '+').replace(/_/g, '/');
  const binary = atob(std + '='.repeat((4 - (std.length % 4)) % 4));
  return new TextDecoder().decode(Uint8Array.from(binary, (c) => c.charCodeAt(0)));
}

/** The hash (with its '#') that encodes `state`. */
export function encodeViewHash(state: ViewState): string {
  return `#${VIEW_HASH_KEY}=${toBase64Url(JSON.stringify(state))}`;
}

function isVec3(v: unknown): v is Vec3 {
  return Array.isArray(v) && v.length === 3 && v.every((x) => typeof x === 'number' && Number.isFinite(x));
}

function isObject(v: unknown): v is Record<string, unknown> {
  return typeof v === 'object' && v !== null && !Array.isArray(v);
}

/**
 * The view in a page hash; null when the hash has no view. Throws a sentence
 * saying what is wrong with a view that does not decode or check.
 */
export function decodeViewHash(hash: string): ViewState | null {
  const params = new URLSearchParams(hash.replace(/^#/, ''));
  const b64 = params.get(VIEW_HASH_KEY);
  if (b64 === null) return null;
  let raw: unknown;
  try {
    raw = JSON.parse(fromBase64Url(b64));
  } catch {
    throw new Error('the view link is not base64url JSON');
  }
  return checkViewState(raw);
}

/** `cam` checked as a view's camera; throws a sentence saying what is wrong. */
export function checkCamera(cam: unknown): ViewState['camera'] {
  if (!isObject(cam) || !isVec3(cam.position) || !isVec3(cam.target) || !isVec3(cam.up)) {
    throw new Error("the view link's camera needs position, target and up as three numbers each");
  }
  if (typeof cam.fov !== 'number' || !(cam.fov > 0 && cam.fov < 180)) throw new Error("the view link's camera fov is not between 0 and 180");
  const camera: ViewState['camera'] = { position: cam.position, target: cam.target, up: cam.up, fov: cam.fov };
  // The clipping planes: links made before they followed the camera carry them; checked, then not used.
  if (cam.near !== undefined || cam.far !== undefined) {
    const { near, far } = cam;
    if (typeof near !== 'number' || typeof far !== 'number' || !(near > 0) || !(far > near) || !Number.isFinite(far)) {
      throw new Error("the view link's camera near and far must be numbers with 0 < near < far");
    }
    camera.near = near;
    camera.far = far;
  }
  return camera;
}

/** `raw` checked as a view (from a link, or a lecture's parts); throws a sentence saying what is wrong. */
export function checkViewState(raw: unknown): ViewState {
  if (!isObject(raw)) throw new Error('the view link is not a JSON object');
  if (raw.v !== 1) throw new Error(`the view link has version ${JSON.stringify(raw.v)}, not 1`);
  if (typeof raw.mesh !== 'string' || !raw.mesh) throw new Error('the view link names no mesh');
  const state: ViewState = { v: 1, mesh: raw.mesh, camera: checkCamera(raw.camera) };
  if (raw.display !== undefined) {
    if (!isObject(raw.display)) throw new Error("the view link's display is not an object");
    state.display = raw.display;
  }
  if (raw.overlays !== undefined) {
    if (!isObject(raw.overlays)) throw new Error("the view link's overlays is not an object");
    state.overlays = raw.overlays;
  }
  if (raw.field !== undefined) {
    const f = raw.field;
    if (
      !isObject(f) ||
      typeof f.job !== 'string' ||
      typeof f.artifact !== 'string' ||
      typeof f.map !== 'string' ||
      !Array.isArray(f.range) ||
      f.range.length !== 2 ||
      !f.range.every((x) => typeof x === 'number' && Number.isFinite(x))
    ) {
      throw new Error("the view link's field needs job, artifact, map and a range of two numbers");
    }
    state.field = { job: f.job, artifact: f.artifact, map: f.map, range: [f.range[0], f.range[1]] };
  }
  if (raw.scene !== undefined) {
    const scene = raw.scene;
    if (!Array.isArray(scene) || !scene.every((o) => isObject(o) && typeof o.mesh === 'string' && o.mesh !== '')) {
      throw new Error("the view link's scene must be a list of objects that each name a mesh");
    }
    if (scene.length === 0 || (scene[0] as Record<string, unknown>).mesh !== raw.mesh) throw new Error("the view link's scene must begin with its mesh");
    state.scene = scene as Array<Record<string, unknown>>;
  }
  if (raw.panes !== undefined) {
    if (typeof raw.panes !== 'boolean') throw new Error("the view link's panes is not true or false");
    state.panes = raw.panes;
  }
  return state;
}

// ---- the whole view, and a lecture's parts ---------------------------------

/**
 * The whole view: the view state and what a link's hash holds beside it
 * (controllers/view_links.ts): the shown mesh's up axis, the fields compared
 * side by side and the skeletons, vector fields and voxel grids shown, each
 * as a `JOB/ARTIFACT` key.
 */
export interface FullView {
  state: ViewState;
  up: 'y' | 'z';
  compare: string[];
  show: string[];
}

/**
 * The parts of a live lecture that carry the view (protocol/API.md, "Live
 * lectures"): the camera its own, as it changes most (the server passes it
 * on at most 30 times a second), and the rest by what changes together.
 */
export const VIEW_PARTS = ['camera', 'meshes', 'display', 'overlays', 'field', 'skeletons'] as const;
export type ViewPart = (typeof VIEW_PARTS)[number];

/** A job's artifact as a part names it: under `job`, which the server reads to let the followers read it too. */
interface JobArtifact {
  job: string;
  artifact: string;
}

function toRef(key: string): JobArtifact {
  const i = key.indexOf('/');
  return { job: key.slice(0, i), artifact: key.slice(i + 1) };
}

function toKeys(refs: unknown, what: string): string[] {
  if (refs === undefined || refs === null) return [];
  if (!Array.isArray(refs) || !refs.every((r) => isObject(r) && typeof r.job === 'string' && typeof r.artifact === 'string')) {
    throw new Error(`the lecture's ${what} must be a list of {job, artifact}`);
  }
  return refs.map((r: JobArtifact) => `${r.job}/${r.artifact}`);
}

/** The view as a lecture's parts. */
export function viewParts(view: FullView): Record<ViewPart, unknown> {
  const { state } = view;
  const meshes: Record<string, unknown> = { mesh: state.mesh, up: view.up, compare: view.compare.map(toRef) };
  if (state.scene) meshes.scene = state.scene;
  if (state.panes) meshes.panes = true;
  // A job's output mesh in the scene stands as `job:JOB/ARTIFACT`: its job named, for the followers to read it.
  const jobs = (state.scene ?? []).map((o) => String(o.mesh)).filter((m) => m.startsWith('job:') && m.includes('/'));
  if (jobs.length) meshes.jobs = jobs.map((m) => m.slice(4, m.indexOf('/')));
  return {
    camera: state.camera,
    meshes,
    display: state.display ?? null,
    overlays: state.overlays ?? null,
    field: state.field ?? null,
    skeletons: view.show.map(toRef),
  };
}

/**
 * The view a lecture's parts hold, checked as a link's is; null before they
 * hold a mesh and a camera. Throws a sentence saying what is wrong.
 */
export function viewFromParts(parts: Readonly<Record<string, unknown>>): FullView | null {
  const m = parts.meshes;
  if (!isObject(m) || !isObject(parts.camera)) return null;
  const state = checkViewState({
    v: 1,
    mesh: m.mesh,
    camera: parts.camera,
    display: parts.display ?? undefined,
    overlays: parts.overlays ?? undefined,
    field: parts.field ?? undefined,
    scene: m.scene,
    panes: m.panes,
  });
  return { state, up: m.up === 'z' ? 'z' : 'y', compare: toKeys(m.compare, 'comparison'), show: toKeys(parts.skeletons, 'skeletons') };
}
