// The camera as plain numbers (for the view link) and back. The near and far
// planes are not part of it: they follow the camera (viewer.ts), so that the
// same camera over the same objects draws the same picture with its own.
import type { Viewer } from './viewer.ts';
import type { ViewState } from './view_state.ts';

export function readCamera(viewer: Viewer): ViewState['camera'] {
  const c = viewer.camera;
  return {
    position: c.position.toArray() as [number, number, number],
    target: viewer.controls.target.toArray() as [number, number, number],
    up: c.up.toArray() as [number, number, number],
    fov: c.fov,
  };
}

/** Puts the camera where `camera` says, and keeps it there (the near and far of a link made before they followed the camera are not needed). */
export function applyCamera(viewer: Viewer, camera: ViewState['camera']): void {
  // What is left of a drag's glide (the orbit's damping) would carry the camera on from here: one
  // update without damping spends it first (the viewer's settleControls), then the camera is set.
  const { controls } = viewer;
  const damping = controls.enableDamping;
  controls.enableDamping = false;
  controls.update();
  controls.enableDamping = damping;
  const c = viewer.camera;
  c.position.fromArray(camera.position);
  c.up.fromArray(camera.up).normalize();
  c.fov = camera.fov;
  c.updateProjectionMatrix();
  viewer.controls.target.fromArray(camera.target);
  viewer.controls.update();
  viewer.requestRender();
}
