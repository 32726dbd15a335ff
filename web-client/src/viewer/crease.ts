// Smooth shading that keeps a part's edges: normals averaged only over the
// faces that meet at less than a crease angle (three's toCreasedNormals), so
// that a CAD part's 90° edges stay sharp while a scan's surface stays smooth
// (MeshLab's and Blender's crease / auto-smooth angle). 180° draws the
// surface as built (normals averaged across every edge); a file's own
// normals are always kept.
//
// Split normals need split vertices, and toCreasedNormals gives a geometry of
// three corners per face. The surface's own geometry stays as it is, since
// everything else reads it by its vertices: fields colour it per vertex, the
// overlays count its edges, the selection and the up axis go by it. The
// split geometry is drawn by a twin: a child of the surface with the same
// faces in the same order (so a ray's faceIndex is the surface's), drawn in
// the surface's own material (a getter: a texture or a colour the texture
// panel or the scene puts on the surface shows at once), while the surface
// itself moves to a layer no camera draws (rays still go down to the twin).
// The twin's geometry follows the surface's as it is read (a getter too, so
// before three uploads it): a field recoloured is copied per corner, new
// positions or faces make the normals again.
import * as THREE from 'three';
import { toCreasedNormals } from 'three/addons/utils/BufferGeometryUtils.js';

/** Surfaces of more faces are drawn as built: three corners per face would cost too much memory. */
export const CREASE_MAX_FACES = 1_000_000;

/** The layer of a surface that its twin draws: the camera draws layer 0 only. */
const TWIN_DRAWS_IT = 1;

interface Twin {
  object: THREE.Mesh;
  drawn: THREE.BufferGeometry;
  degrees: number;
  /** The surface's geometry the drawn one was made from, and the versions of its attributes then. */
  source: THREE.BufferGeometry;
  seen: Map<string, { attribute: THREE.BufferAttribute | THREE.InterleavedBufferAttribute; version: number }>;
}

const twins = new WeakMap<THREE.Mesh, Twin>();

/** Marks a surface's geometry whose normals came with the file (never replaced by computed ones). */
export function markFileNormals(geometry: THREE.BufferGeometry): void {
  geometry.userData.fileNormals = true;
}

/** Why the crease angle does not apply to `mesh`, or null when it does. */
export function creaseRefusal(mesh: THREE.Mesh): string | null {
  if (mesh.geometry.userData.fileNormals) return "This mesh's file gives its own normals, which are kept: the crease angle applies to computed normals";
  if (faceCount(mesh.geometry) > CREASE_MAX_FACES)
    return `Over ${CREASE_MAX_FACES.toLocaleString('en')} faces the surface is smooth across every edge (split normals would cost too much memory)`;
  return null;
}

function faceCount(geometry: THREE.BufferGeometry): number {
  return (geometry.index ? geometry.index.count : geometry.getAttribute('position').count) / 3;
}

/** The crease angle `mesh` is drawn with (null: as built). */
export function creaseOf(mesh: THREE.Mesh): number | null {
  return twins.get(mesh)?.degrees ?? null;
}

/**
 * Draws `mesh` smooth-shaded with its normals split where faces meet at more
 * than `degrees`; null or 180 and more: as built.
 */
export function setCrease(mesh: THREE.Mesh, degrees: number | null): void {
  const want = degrees !== null && degrees < 180 && creaseRefusal(mesh) === null ? degrees : null;
  const had = twins.get(mesh);
  if (had && had.degrees === want) return;
  if (had) {
    mesh.remove(had.object);
    had.drawn.dispose();
    twins.delete(mesh);
    mesh.layers.set(0);
  }
  if (want === null) return;
  const twin: Twin = { object: new THREE.Mesh(), drawn: new THREE.BufferGeometry(), degrees: want, source: mesh.geometry, seen: new Map() };
  build(twin, mesh.geometry);
  const object = twin.object;
  object.name = 'crease';
  object.userData.crease = true;
  Object.defineProperty(object, 'material', { get: () => mesh.material, set: () => {} });
  Object.defineProperty(object, 'geometry', {
    get: () => {
      follow(twin, mesh.geometry);
      return twin.drawn;
    },
    set: () => {},
  });
  mesh.add(object);
  mesh.layers.set(TWIN_DRAWS_IT);
  twins.set(mesh, twin);
}

/** Makes the drawn geometry of `source`: every attribute per corner, the normals split at the crease. */
function build(twin: Twin, source: THREE.BufferGeometry): void {
  twin.drawn.dispose();
  const drawn = source.index ? source.toNonIndexed() : source.clone();
  drawn.setAttribute('normal', creasedNormals(source, twin.degrees));
  if (!source.boundingBox) source.computeBoundingBox();
  if (!source.boundingSphere) source.computeBoundingSphere();
  drawn.boundingBox = source.boundingBox!.clone();
  drawn.boundingSphere = source.boundingSphere!.clone();
  twin.drawn = drawn;
  twin.source = source;
  twin.seen = versions(source);
}

function versions(source: THREE.BufferGeometry): Twin['seen'] {
  const seen: Twin['seen'] = new Map();
  for (const [name, attribute] of Object.entries(source.attributes)) {
    seen.set(name, { attribute, version: (attribute as THREE.BufferAttribute).version ?? 0 });
  }
  if (source.index) seen.set('index', { attribute: source.index, version: source.index.version });
  return seen;
}

/** Brings the drawn geometry up to the surface's: a new geometry, positions or faces are made again; another attribute changed is copied per corner. */
function follow(twin: Twin, source: THREE.BufferGeometry): void {
  const now = versions(source);
  const changed = [...now].filter(([name, v]) => twin.seen.get(name)?.attribute !== v.attribute || twin.seen.get(name)?.version !== v.version).map(([name]) => name);
  const gone = [...twin.seen.keys()].filter((name) => !now.has(name));
  if (source === twin.source && changed.length === 0 && gone.length === 0) return;
  if (source !== twin.source || changed.includes('position') || changed.includes('index') || gone.includes('position')) {
    build(twin, source);
    return;
  }
  for (const name of gone) if (name !== 'normal') twin.drawn.deleteAttribute(name);
  for (const name of changed) {
    if (name === 'normal') continue; // the drawn geometry's own
    twin.drawn.setAttribute(name, perCorner(source.getAttribute(name), source.index));
  }
  twin.seen = now;
}

/** `attribute` of an indexed geometry with one item per corner (`index` null: as it is). */
function perCorner(attribute: THREE.BufferAttribute | THREE.InterleavedBufferAttribute, index: THREE.BufferAttribute | null): THREE.BufferAttribute {
  const n = index ? index.count : attribute.count;
  const size = attribute.itemSize;
  const array = new (attribute.array.constructor as new (n: number) => THREE.TypedArray)(n * size);
  for (let k = 0; k < n; ++k) {
    const v = index ? index.getX(k) : k;
    for (let c = 0; c < size; ++c) array[k * size + c] = attribute.getComponent(v, c);
  }
  return new THREE.BufferAttribute(array, size, attribute.normalized);
}

/**
 * The normals of `source`'s corners, split at `degrees`. toCreasedNormals
 * takes corners closer than 0.01 (in the mesh's units) for one vertex, too
 * coarse for a part measured in metres; so it is given the positions centred
 * and scaled to a box of 10^4, where 0.01 is a millionth of the mesh.
 */
function creasedNormals(source: THREE.BufferGeometry, degrees: number): THREE.BufferAttribute {
  const position = source.getAttribute('position');
  if (!source.boundingBox) source.computeBoundingBox();
  const box = source.boundingBox!;
  const center = box.getCenter(new THREE.Vector3());
  const size = box.getSize(new THREE.Vector3());
  const scale = 1e4 / (Math.max(size.x, size.y, size.z) || 1);
  const scaled = new Float32Array(position.count * 3);
  for (let i = 0; i < position.count; ++i) {
    scaled[3 * i] = (position.getX(i) - center.x) * scale;
    scaled[3 * i + 1] = (position.getY(i) - center.y) * scale;
    scaled[3 * i + 2] = (position.getZ(i) - center.z) * scale;
  }
  const probe = new THREE.BufferGeometry();
  probe.setAttribute('position', new THREE.BufferAttribute(scaled, 3));
  if (source.index) probe.setIndex(source.index);
  const creased = toCreasedNormals(probe, (degrees * Math.PI) / 180);
  return creased.getAttribute('normal') as THREE.BufferAttribute;
}
