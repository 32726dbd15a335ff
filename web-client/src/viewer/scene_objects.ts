// The scene's objects in three.js terms: a SceneObjectState's visibility and
// transform put on an object, and where an object lands on the screen (its
// world bounding box projected through the camera), which the test hook
// reports.
import * as THREE from 'three';
import type { SceneObjectState } from './scene_state.ts';

/** Puts the visibility and the transform of `s` on `object` (rotations in degrees, XYZ order). */
export function applySceneTransform(object: THREE.Object3D, s: SceneObjectState): void {
  object.visible = s.visible;
  object.position.fromArray(s.position);
  const [x, y, z] = s.rotation.map((d) => THREE.MathUtils.degToRad(d));
  object.rotation.set(x!, y!, z!, 'XYZ');
  object.scale.setScalar(s.scale);
  object.updateMatrixWorld(true);
}

/**
 * The box on screen of `object`'s world bounding box, in normalized device
 * coordinates of the viewport it is drawn in ([-1, 1] across it, y up):
 * [xmin, ymin, xmax, ymax]; null when the box is empty or behind the camera.
 */
export function projectedBox(object: THREE.Object3D, camera: THREE.Camera): [number, number, number, number] | null {
  const box = new THREE.Box3().setFromObject(object);
  if (box.isEmpty()) return null;
  const out: [number, number, number, number] = [Infinity, Infinity, -Infinity, -Infinity];
  const p = new THREE.Vector3();
  const view = new THREE.Vector3();
  for (let i = 0; i < 8; ++i) {
    p.set(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z);
    view.copy(p).applyMatrix4(camera.matrixWorldInverse);
    if (view.z >= 0) return null;
    p.project(camera);
    out[0] = Math.min(out[0], p.x);
    out[1] = Math.min(out[1], p.y);
    out[2] = Math.max(out[2], p.x);
    out[3] = Math.max(out[3], p.y);
  }
  return out;
}
