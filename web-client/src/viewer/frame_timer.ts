// Frame times while orbiting (bench/frame_bench.mjs, window.__cgview.orbit):
// the camera turns about the orbit target's vertical axis by one step per
// frame; each frame is rendered with renderer.render() and waited for with a
// 1-pixel readPixels (Chromium's gl.finish() is only a flush), so a frame's
// time is what the GPU (or SwiftShader) takes to draw it.  The camera is put
// back afterwards.
import * as THREE from 'three';
import type { Viewer } from './viewer.ts';

export interface OrbitTimes {
  frames: number;
  /** Triangles drawn per frame (renderer.info), to say which object was measured. */
  triangles: number;
  medianMs: number;
  p95Ms: number;
  meanMs: number;
  maxMs: number;
}

const quantile = (sorted: number[], q: number): number => sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))]!;

export function orbitFrameTimes(viewer: Viewer, frames = 100): OrbitTimes {
  const { renderer, scene, camera, controls } = viewer;
  const gl = renderer.getContext();
  const pixel = new Uint8Array(4);
  const start = camera.position.clone();
  const step = new THREE.Quaternion().setFromAxisAngle(new THREE.Vector3(0, 1, 0), (2 * Math.PI) / Math.max(1, frames));
  const offset = new THREE.Vector3();
  const times: number[] = [];
  let triangles = 0;
  for (let i = 0; i < frames; ++i) {
    const t0 = performance.now();
    offset.copy(camera.position).sub(controls.target).applyQuaternion(step);
    camera.position.copy(controls.target).add(offset);
    camera.lookAt(controls.target);
    renderer.render(scene, camera);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    times.push(performance.now() - t0);
    triangles = renderer.info.render.triangles;
  }
  camera.position.copy(start);
  camera.lookAt(controls.target);
  viewer.requestRender();
  const sorted = [...times].sort((a, b) => a - b);
  return {
    frames,
    triangles,
    medianMs: quantile(sorted, 0.5),
    p95Ms: quantile(sorted, 0.95),
    meanMs: times.reduce((a, b) => a + b, 0) / Math.max(1, times.length),
    maxMs: sorted[sorted.length - 1] ?? 0,
  };
}
