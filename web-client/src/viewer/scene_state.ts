// The scene: several stored meshes shown at once, each with its visibility,
// colour and transform (translation, rotation in degrees about x, y and z in
// that order, uniform scale). Pure (no DOM, no three.js), so that node's unit
// tests load it: the view link keeps these as given and the reader checks
// them here.

export type Vec3 = [number, number, number];

export interface SceneObjectState {
  /** The stored mesh's id. */
  mesh: string;
  visible: boolean;
  /** sRGB hex colour of the surface; null: the Display panel's material colour. */
  color: string | null;
  position: Vec3;
  /** Degrees about x, y, z (applied in that order). */
  rotation: Vec3;
  scale: number;
}

/** Colours given to objects added to the scene, in turn (the first object keeps the material's colour). */
export const SCENE_COLORS = ['#3f8fe0', '#4cc36a', '#d94cc8', '#e0d23f', '#40d0d0', '#a070ff'] as const;

/** At most this many objects in a scene (a link with more is cut to it). */
export const MAX_SCENE_OBJECTS = 16;

/** Translations and scales beyond these are typos, not scenes. */
const MAX_OFFSET = 1e6;
const SCALE_RANGE: [number, number] = [1e-3, 1e3];

export function defaultSceneObject(mesh: string, color: string | null = null): SceneObjectState {
  return { mesh, visible: true, color, position: [0, 0, 0], rotation: [0, 0, 0], scale: 1 };
}

/** The colour for the `n`-th object added beside the first. */
export function sceneColor(n: number): string {
  return SCENE_COLORS[((n % SCENE_COLORS.length) + SCENE_COLORS.length) % SCENE_COLORS.length]!;
}

const clamp = (v: number, lo: number, hi: number) => Math.min(hi, Math.max(lo, v));
const finite = (v: unknown): v is number => typeof v === 'number' && Number.isFinite(v);

function vec3(v: unknown, lo: number, hi: number, d: Vec3): Vec3 {
  return Array.isArray(v) && v.length === 3 && v.every(finite) ? (v.map((x: number) => clamp(x, lo, hi)) as Vec3) : [...d];
}

/** One object from untrusted JSON (a view link); null when it names no mesh. What is invalid falls back to the default. */
export function sanitizeSceneObject(raw: unknown): SceneObjectState | null {
  if (typeof raw !== 'object' || raw === null || Array.isArray(raw)) return null;
  const r = raw as Record<string, unknown>;
  if (typeof r.mesh !== 'string' || !r.mesh) return null;
  const s = defaultSceneObject(r.mesh);
  if (typeof r.visible === 'boolean') s.visible = r.visible;
  if (typeof r.color === 'string' && /^#[0-9a-fA-F]{6}$/.test(r.color)) s.color = r.color.toLowerCase();
  s.position = vec3(r.position, -MAX_OFFSET, MAX_OFFSET, s.position);
  s.rotation = vec3(r.rotation, -360, 360, s.rotation);
  if (finite(r.scale) && r.scale > 0) s.scale = clamp(r.scale, ...SCALE_RANGE);
  return s;
}

/**
 * The objects of a view link's scene: throws a sentence when it is not a
 * list of objects that each name a mesh; cut to MAX_SCENE_OBJECTS.
 */
export function sanitizeScene(raw: unknown): SceneObjectState[] {
  if (!Array.isArray(raw)) throw new Error("the view link's scene is not a list");
  const objects = raw.slice(0, MAX_SCENE_OBJECTS).map(sanitizeSceneObject);
  if (objects.some((o) => o === null)) throw new Error("every object of the view link's scene needs a mesh id");
  return objects as SceneObjectState[];
}

/** Whether a transform is the identity (nothing to apply or to keep in a link). */
export function isIdentity(s: Pick<SceneObjectState, 'position' | 'rotation' | 'scale'>): boolean {
  return s.scale === 1 && s.position.every((x) => x === 0) && s.rotation.every((x) => x === 0);
}
