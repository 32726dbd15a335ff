// The camera as plain numbers (for the view link) and back.
import type { Viewer } from './viewer.ts';
import type { ViewState } from './view_state.ts';

export function readCamera(viewer: Viewer): ViewState['camera'] {
  const c = viewer.camera;
  return {
    position: c.position.toArray() as [number, number, number],
    target: viewer.controls.target.toArray() as [number, number, number],
    up: c.up.toArray() as [number, number, number],
    fov: c.fov,
    near: c.near,
    far: c.far,
  };
}

/** Puts the camera where `camera` says (near and far, when given; otherwise those of the fit to the shown object stay). */
export function applyCamera(viewer: Viewer, camera: ViewState['camera']): void {
  const c = viewer.camera;
  c.position.fromArray(camera.position);
  c.up.fromArray(camera.up).normalize();
  c.fov = camera.fov;
  if (camera.near !== undefined && camera.far !== undefined) {
    c.near = camera.near;
    c.far = camera.far;
  }
  c.updateProjectionMatrix();
  viewer.controls.target.fromArray(camera.target);
  viewer.controls.update();
  viewer.requestRender();
}
