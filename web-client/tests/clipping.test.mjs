// Unit tests of the near and far planes that follow the camera
// (src/viewer/clipping.ts). `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { boxDepths, clipPlanes } = await importTs('viewer/clipping.ts');

const unit = (v) => {
  const n = Math.hypot(...v);
  return v.map((x) => x / n);
};
const close = (a, b) => Math.abs(a - b) < 1e-9 * Math.max(1, Math.abs(b));

test('depths of a box: along the view, not the distance to its nearest point', () => {
  const d = boxDepths([0, 0, 5], [0, 0, -1], [-1, -1, -1], [1, 1, 1]);
  assert.ok(close(d.nearest, 4) && close(d.farthest, 6), JSON.stringify(d));
  // Seen from off its corner, the nearest corner is closer along the view than the view's axis suggests.
  const eye = [3, 1.9, 5.5];
  const forward = unit(eye.map((x) => -x));
  const corners = [-1, 1].flatMap((x) => [-1, 1].flatMap((y) => [-1, 1].map((z) => [2 * x, 0.5 * y, 0.5 * z])));
  const depths = corners.map((c) => c.reduce((s, ck, k) => s + (ck - eye[k]) * forward[k], 0));
  const got = boxDepths(eye, forward, [-2, -0.5, -0.5], [2, 0.5, 0.5]);
  assert.ok(close(got.nearest, Math.min(...depths)) && close(got.farthest, Math.max(...depths)), JSON.stringify({ got, depths }));
});

/** Every corner of the box lies between the planes. */
function encloses(eye, forward, lo, hi, { near, far }) {
  const { nearest, farthest } = boxDepths(eye, forward, lo, hi);
  return near > 0 && near < nearest && far > farthest;
}

for (const scale of [1e-3, 1, 1e4, 1e6]) {
  test(`a box ${scale} across: the planes enclose it from any distance and direction`, () => {
    const lo = [-scale, -scale / 4, -scale / 4];
    const hi = [scale, scale / 4, scale / 4];
    for (const dir of [
      [0, 0, 1],
      [0.55, 0.35, 1],
      [1, 1, 1],
      [-1, 0.2, 0],
    ]) {
      const back = unit(dir);
      for (const distance of [3, 6, 50, 1000, 1e5].map((f) => f * scale)) {
        const eye = back.map((x) => x * distance);
        const forward = back.map((x) => -x);
        const p = clipPlanes(eye, forward, lo, hi, distance);
        assert.ok(encloses(eye, forward, lo, hi, p), `${scale} box from ${distance} along ${dir}: ${JSON.stringify(p)}`);
        assert.ok(p.far / p.near < 1e7, `${JSON.stringify(p)}`);
      }
    }
  });
}

test('zoomed into the box, the near plane is a hundredth of the way to the orbit centre', () => {
  const { near, far } = clipPlanes([0, 0, 0.5], [0, 0, -1], [-1, -1, -1], [1, 1, 1], 0.5);
  assert.ok(close(near, 0.005), `near ${near}`);
  assert.ok(far > 1.5, `far ${far}`);
  // Just outside it, a thousandth away from its face, the face stays beyond the near plane.
  const p = clipPlanes([0, 0, 1.001], [0, 0, -1], [-1, -1, -1], [1, 1, 1], 1.001);
  assert.ok(p.near < 0.001, `near ${p.near}`);
});

test('the planes stay ordered for flat and point-like boxes, and with the box behind the camera', () => {
  for (const [lo, hi] of [
    [
      [-1, -1, 0],
      [1, 1, 0],
    ],
    [
      [0.2, 0.2, 0.2],
      [0.2, 0.2, 0.2],
    ],
  ]) {
    const p = clipPlanes([0, 0, 3], [0, 0, -1], lo, hi, 3);
    assert.ok(encloses([0, 0, 3], [0, 0, -1], lo, hi, p), JSON.stringify({ lo, hi, p }));
  }
  const behind = clipPlanes([0, 0, 3], [0, 0, 1], [-1, -1, -1], [1, 1, 1], 3);
  assert.ok(behind.near > 0 && behind.far > behind.near, JSON.stringify(behind));
});
