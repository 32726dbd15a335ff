// Unit tests of the display's pure parts: boundary and non-manifold edges
// (src/viewer/mesh_edges.ts), the field's percentile range
// (src/viewer/histogram.ts), the view link's encoding
// (src/viewer/view_state.ts) and the check of texture coordinates that
// chooses no checkerboard (src/viewer/uv_check.ts).  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { classifyEdges } = await importTs('viewer/mesh_edges.ts');
const { percentileRange } = await importTs('viewer/histogram.ts');
const { decodeViewHash, encodeViewHash } = await importTs('viewer/view_state.ts');
const { uvProblem } = await importTs('viewer/uv_check.ts');

const count = (pairs) => pairs.length / 2;

test('a closed tetrahedron has no boundary and no non-manifold edge', () => {
  const positions = [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1];
  const index = [0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3];
  const e = classifyEdges(positions, index);
  assert.equal(count(e.boundary), 0);
  assert.equal(count(e.nonManifold), 0);
});

test('an open square of two triangles has its four sides as boundary', () => {
  const positions = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0];
  const e = classifyEdges(positions, [0, 1, 2, 0, 2, 3]);
  assert.equal(count(e.boundary), 4);
  assert.equal(count(e.nonManifold), 0);
  const edges = new Set();
  for (let i = 0; i < e.boundary.length; i += 2) edges.add([e.boundary[i], e.boundary[i + 1]].sort().join('-'));
  assert.deepEqual([...edges].sort(), ['0-1', '0-3', '1-2', '2-3']);
});

test('three triangles on one edge make it non-manifold (and their six other sides boundary)', () => {
  const positions = [0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1];
  const e = classifyEdges(positions, [0, 1, 2, 1, 0, 3, 0, 1, 4]);
  assert.equal(count(e.nonManifold), 1);
  assert.deepEqual([...e.nonManifold].sort(), [0, 1]);
  assert.equal(count(e.boundary), 6);
});

test('vertices split at equal positions (unindexed corners) are welded', () => {
  // The open square again, as six unindexed corners.
  const p = [
    [0, 0, 0],
    [1, 0, 0],
    [1, 1, 0],
    [0, 0, 0],
    [1, 1, 0],
    [0, 1, 0],
  ].flat();
  const e = classifyEdges(p, null);
  assert.equal(count(e.boundary), 4);
  assert.equal(count(e.nonManifold), 0);
});

test('percentile range clips the tails and skips non-finite values', () => {
  const values = new Float32Array(101);
  for (let i = 0; i <= 100; ++i) values[i] = i;
  assert.deepEqual(percentileRange(values, 1, 99), [1, 99]);
  assert.deepEqual(percentileRange(values, 0, 100), [0, 100]);
  assert.deepEqual(percentileRange(new Float32Array([NaN, 5, Infinity]), 1, 99), [5, 5]);
  assert.deepEqual(percentileRange(new Float32Array([NaN]), 1, 99), [0, 0]);
});

test('a view link round-trips, and bad links say what is wrong', () => {
  const state = {
    v: 1,
    mesh: 'm-1',
    camera: { position: [1, 2, 3], target: [0, 0.5, 0], up: [0, 1, 0], fov: 40 },
    display: { mode: 'toon', color: '#ff0000' },
    overlays: { bbox: true },
    field: { job: 'j', artifact: 'sdf', map: 'magma', range: [-1, 2.5] },
  };
  const hash = encodeViewHash(state);
  assert.match(hash, /^#view=[A-Za-z0-9_-]+$/, 'base64url, no padding');
  assert.deepEqual(decodeViewHash(hash), state);
  assert.equal(decodeViewHash(''), null);
  assert.equal(decodeViewHash('#other=1'), null);
  assert.throws(() => decodeViewHash('#view=%%%'), /base64url JSON/);
  const bad = (s) => encodeViewHash(s);
  assert.throws(() => decodeViewHash(bad({ ...state, v: 2 })), /version 2/);
  assert.throws(() => decodeViewHash(bad({ ...state, mesh: '' })), /names no mesh/);
  assert.throws(() => decodeViewHash(bad({ ...state, camera: { ...state.camera, up: [0, 1] } })), /camera/);
  assert.throws(() => decodeViewHash(bad({ ...state, camera: { ...state.camera, fov: 0 } })), /fov/);
  assert.throws(() => decodeViewHash(bad({ ...state, field: { ...state.field, range: [0] } })), /field/);
  const clipped = { ...state, camera: { ...state.camera, near: 0.1, far: 20 } };
  assert.deepEqual(decodeViewHash(bad(clipped)), clipped);
  assert.throws(() => decodeViewHash(bad({ ...state, camera: { ...state.camera, near: 2, far: 1 } })), /near and far/);
});

test('texture coordinates that cannot show a texture are told apart from those that can', () => {
  const quad = [0, 1, 2, 0, 2, 3];
  assert.equal(uvProblem([0, 0, 1, 0, 1, 1, 0, 1], quad), null, 'a unit square');
  // One face with an area among flat ones is enough; tiny UVs too (the test is scale-free).
  assert.equal(uvProblem([0, 0, 1e-6, 0, 1e-6, 1e-6, 0, 0], quad), null, 'a tiny square');
  assert.match(uvProblem([0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5], quad), /all the same point/);
  assert.match(uvProblem([0, 0, 0, 0, 0, 0, 0, 0], quad), /all the same point/);
  assert.match(uvProblem([0, 0, 0.1, 0.2, 0.3, 0.6, 0.7, 1.4], quad), /no area/, 'all on a line');
  assert.match(uvProblem([0.2, 0.2, 0.2, 0.2, 0.9, 0.9, 0.3, 0.3], quad), /no area/, 'corners that coincide');
  assert.match(uvProblem([NaN, 0, 1, 0, 1, 1, NaN, 1], quad), /not numbers/);
  // Faces with a corner not a number are left out: the other one decides.
  assert.equal(uvProblem([0, 0, 1, 0, 1, 1, NaN, 1], quad), null);
  // No index: the vertices three by three.
  assert.equal(uvProblem([0, 0, 1, 0, 0, 1], null), null);
  assert.match(uvProblem([0, 0, 1, 1, 2, 2], null), /no area/);
});
