// Where the camera stands: framing a box (fit to view) and the near and far
// planes that follow the camera before every frame (viewer/clipping.ts says
// how they are chosen).
import * as THREE from 'three';
import type { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { clipPlanes } from './clipping.ts';

/** Frames `box`'s bounding sphere, looking from the front-right-above; the orbit's distances follow its size. */
export function frameBox(camera: THREE.PerspectiveCamera, controls: OrbitControls, box: THREE.Box3): void {
  if (box.isEmpty()) return;
  const sphere = box.getBoundingSphere(new THREE.Sphere());
  const radius = Math.max(sphere.radius, 1e-6);

  // Distance at which the sphere fits both the vertical and horizontal field of view.
  const vFov = THREE.MathUtils.degToRad(camera.fov);
  const hFov = 2 * Math.atan(Math.tan(vFov / 2) * camera.aspect);
  const distance = (radius / Math.sin(Math.min(vFov, hFov) / 2)) * 1.05;

  const direction = new THREE.Vector3(0.55, 0.35, 1).normalize();
  camera.position.copy(sphere.center).addScaledVector(direction, distance);
  controls.target.copy(sphere.center);
  // Close enough to fill the view with a thousandth of the object (the near
  // plane follows), far enough to see it as a dot.
  controls.minDistance = radius * 1e-3;
  controls.maxDistance = radius * 100;
  controls.update();
}

/** Puts the near and far planes around `box` (what is drawn) as seen from where the camera is now; `focus`: the orbit centre. */
export function followBox(camera: THREE.PerspectiveCamera, focus: THREE.Vector3, box: THREE.Box3): void {
  if (box.isEmpty()) return;
  const forward = camera.getWorldDirection(new THREE.Vector3()).toArray();
  const { near, far } = clipPlanes(camera.position.toArray(), forward, box.min.toArray(), box.max.toArray(), camera.position.distanceTo(focus));
  if (near === camera.near && far === camera.far) return;
  camera.near = near;
  camera.far = far;
  camera.updateProjectionMatrix();
}
