// The up axis: scans often come with +Z up, and drawn as they are they lie on
// their back. "Z up" turns such a mesh's objects so that +Z points up on
// screen; the choice is the mesh's, kept in this browser's storage by mesh id.
// The turn goes over the object's own transform (the Scene panel's) as a
// parent's would, so that the object's moves are in the mesh's own axes and
// keep the turn, and what measures the object's world box (fit to view, the
// overlays) sees it as drawn.
import * as THREE from 'three';

/** Which of the mesh's axes points up on screen. */
export type UpAxis = 'y' | 'z';

const UP_KEY = 'cgview.up-axis.';

/** The mesh's up axis as this browser keeps it (Y unless chosen). */
export function storedUpAxis(meshId: string): UpAxis {
  try {
    return localStorage.getItem(UP_KEY + meshId) === 'z' ? 'z' : 'y';
  } catch {
    return 'y'; // storage disabled
  }
}

export function storeUpAxis(meshId: string, axis: UpAxis): void {
  try {
    if (axis === 'z') localStorage.setItem(UP_KEY + meshId, 'z');
    else localStorage.removeItem(UP_KEY + meshId);
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
