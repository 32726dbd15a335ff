// The up axis: scans and CAD parts often come with +Z up, and drawn as they
// are they lie on their back. "Z up" turns such a mesh's objects so that +Z
// points up on screen. The choice is the mesh's, kept in this browser's
// storage by mesh id; until one is made, the mesh's file format gives it
// (defaultUpAxis, the one place of that rule).
// The turn goes over the object's own transform (the Scene panel's) as a
// parent's would, so that the object's moves are in the mesh's own axes and
// keep the turn, and what measures the object's world box (fit to view, the
// overlays) sees it as drawn. The mesh's data are never changed: picks,
// selections and what goes back to the server stay in the file's coordinates.
import * as THREE from 'three';

/** Which of the mesh's axes points up on screen. */
export type UpAxis = 'y' | 'z';

const UP_KEY = 'cgview.up-axis.';

/**
 * The up axis a file of `format` (the server's Mesh.format: "stl", "obj",
 * "glb"...) is drawn with until the user chooses: Z for STL, whose writers
 * (CAD tools, slicers: 3D printing builds along +Z) put Z up, though the
 * format says nothing; Y for everything else: glTF by its specification, and
 * OBJ, PLY and OFF, which say nothing either and come Y up from most tools
 * that write them (Blender's OBJ export, the Stanford scans). A mesh a job
 * made is stored in another format, so it starts Y up.
 */
export function defaultUpAxis(format: string | null): UpAxis {
  return format?.toLowerCase() === 'stl' ? 'z' : 'y';
}

/** defaultUpAxis in words, for the control's title. */
export const UP_AXIS_RULE = 'Z for STL files (CAD tools write them Z up), Y for the other formats (glTF by its specification)';

/** The mesh's up axis as this browser keeps it, `fallback` unless chosen. */
export function storedUpAxis(meshId: string, fallback: UpAxis = 'y'): UpAxis {
  try {
    const kept = localStorage.getItem(UP_KEY + meshId);
    return kept === 'z' || kept === 'y' ? kept : fallback;
  } catch {
    return fallback; // storage disabled
  }
}

/** Keeps `axis` for the mesh (forgotten when it is `fallback`, the one the mesh has unless chosen). */
export function storeUpAxis(meshId: string, axis: UpAxis, fallback: UpAxis = 'y'): void {
  try {
    if (axis === fallback) localStorage.removeItem(UP_KEY + meshId);
    else localStorage.setItem(UP_KEY + meshId, axis);
  } catch {
    // Storage disabled: the choice lasts as long as the page.
  }
}

/** -90° about X: takes +Z to +Y (up on screen) and -Y towards the default camera, a Z-up scan's front. */
const Z_UP = new THREE.Matrix4().makeRotationX(-Math.PI / 2);
const upOf = new WeakMap<THREE.Object3D, UpAxis>();

/**
 * Draws `object` with `axis` up: the turn is applied to the local matrix
 * each time three composes it from the position, rotation and scale, so that
 * applySceneTransform and three's own updates keep it. Returns whether
 * anything changed.
 */
export function setObjectUp(object: THREE.Object3D, axis: UpAxis): boolean {
  const had = upOf.get(object);
  if ((had ?? 'y') === axis) return false;
  if (had === undefined) {
    const compose = object.updateMatrix.bind(object);
    object.updateMatrix = () => {
      compose();
      if (upOf.get(object) === 'z') object.matrix.premultiply(Z_UP);
    };
  }
  upOf.set(object, axis);
  object.updateMatrixWorld(true);
  return true;
}
