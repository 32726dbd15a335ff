// The camera's near and far planes, from where the camera is and the box of
// what is drawn, worked out again before every frame (viewer/framing.ts).
// Planes set once when a mesh is framed cut into it as soon as the camera
// moves closer (the near plane stays where it was) or further (the far one
// does); planes that follow the camera keep the whole box between them at
// any distance, for a 1-unit mesh as for a 10,000-unit one, and the depth
// buffer's precision is spent on what is in front of the camera.
// Pure (no three.js), so that node's unit tests load it.

export type Vec3 = readonly [number, number, number];

/** Share of the box's diagonal kept free in front of and behind the box: what is drawn a little outside it (toon outlines, normals, labels). */
const PAD = 0.02;
/** Inside the box, the near plane at this share of the distance to the orbit centre (or of the box's size, if smaller). */
const CLOSE = 0.01;
/** The near plane never closer than this share of the far one (a depth buffer's precision runs out beyond). */
const MIN_RATIO = 1e-6;

/**
 * The depths of the box [min, max] seen from `eye` looking along the unit
 * vector `forward`: the least and the greatest distance of its points along
 * `forward` (the planes are at such depths, not at distances from the eye).
 * A linear function over a box is extreme at its corners.
 */
export function boxDepths(eye: Vec3, forward: Vec3, min: Vec3, max: Vec3): { nearest: number; farthest: number } {
  let nearest = 0;
  let farthest = 0;
  for (let k = 0; k < 3; ++k) {
    const a = (min[k]! - eye[k]!) * forward[k]!;
    const b = (max[k]! - eye[k]!) * forward[k]!;
    nearest += Math.min(a, b);
    farthest += Math.max(a, b);
  }
  return { nearest, farthest };
}

/**
 * Near and far planes for a camera at `eye` looking along the unit vector
 * `forward` at what lies in the box [min, max], `focus` away from the point
 * it turns about (the orbit centre). With the whole box in front, the near
 * plane lies just before the box's nearest depth (nothing drawn is closer);
 * with the camera in it (zoomed into a mesh) or past its near side, at a
 * hundredth of the distance to the orbit centre, so that what one zooms
 * towards stays beyond it. The far plane lies just past the box's farthest
 * depth.
 */
export function clipPlanes(eye: Vec3, forward: Vec3, min: Vec3, max: Vec3, focus: number): { near: number; far: number } {
  const { nearest, farthest } = boxDepths(eye, forward, min, max);
  const diagonal = Math.hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]);
  // A point (or a flat box seen edge-on) still has a scale: the distance to it.
  const size = Math.max(diagonal, Math.abs(farthest) * 1e-3, 1e-12);
  const pad = PAD * size;
  const close = CLOSE * Math.min(Number.isFinite(focus) && focus > 0 ? focus : size, size);
  const front = nearest > 0 ? Math.max(nearest - pad, Math.min(close, nearest / 2)) : close;
  // The box behind the camera (nothing to see): any far plane beyond the near one will do.
  const far = Math.max(farthest + pad, front * 2);
  const near = Math.max(front, far * MIN_RATIO);
  return { near, far };
}
