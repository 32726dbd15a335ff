// Unit test of src/viewer/selection.ts: grow and shrink by one ring, box and
// lasso regions, projection, areas, on small meshes whose answers are
// counted by hand.  `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const S = await importTs('viewer/selection.ts');

/** An n × n grid of unit squares in z = 0, two triangles each: square (i, j) has faces 2(j n + i) and +1. */
function grid(n) {
  const positions = [];
  for (let j = 0; j <= n; ++j) for (let i = 0; i <= n; ++i) positions.push(i, j, 0);
  const indices = [];
  const v = (i, j) => j * (n + 1) + i;
  for (let j = 0; j < n; ++j) for (let i = 0; i < n; ++i) indices.push(v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j), v(i + 1, j + 1), v(i, j + 1));
  return { positions: new Float32Array(positions), indices: new Uint32Array(indices), vertices: (n + 1) ** 2, faces: 2 * n * n };
}

test('grow adds the faces sharing a vertex, shrink takes them back', () => {
  const g = grid(5);
  // The centre square (2, 2): faces 24 and 25.
  const centre = [24, 25];
  const grown = S.growShrink('faces', centre, g.indices, g.vertices, true);
  // Its four corners touch the 3 x 3 block of squares around it, less the
  // triangle of the two off-diagonal corner squares that misses the corner
  // (the diagonals run from (i, j) to (i + 1, j + 1)): 18 - 2 faces.
  assert.equal(grown.length, 16);
  assert.ok(!grown.includes(16) && grown.includes(17)); // square (3, 1)
  assert.ok(grown.includes(32) && !grown.includes(33)); // square (1, 3)
  assert.ok(grown.includes(12) && grown.includes(13) && grown.includes(36) && grown.includes(37)); // squares (1, 1), (3, 3)
  assert.deepEqual(S.growShrink('faces', grown, g.indices, g.vertices, false), centre);
  // Shrinking a single square empties it; growing nothing grows nothing.
  assert.deepEqual(S.growShrink('faces', centre, g.indices, g.vertices, false), []);
  assert.deepEqual(S.growShrink('faces', [], g.indices, g.vertices, true), []);
  // Shrink erodes from unselected faces only: the whole mesh stays whole.
  const all = S.invert([], g.faces);
  assert.equal(S.growShrink('faces', all, g.indices, g.vertices, false).length, 50);
});

test('vertices grow and shrink along the triangle edges', () => {
  const g = grid(2); // 3 x 3 vertices; 4 is the centre
  const ring = S.growShrink('vertices', [4], g.indices, g.vertices, true);
  // The diagonal of each square runs from (i, j) to (i + 1, j + 1): 4 has 6 neighbours.
  assert.deepEqual(ring, [0, 1, 3, 4, 5, 7, 8]);
  // Shrinking keeps the vertices whose neighbours are all selected: the
  // centre, and the two corners on the diagonal (their 3 neighbours are in).
  assert.deepEqual(S.growShrink('vertices', ring, g.indices, g.vertices, false), [0, 4, 8]);
});

test('combine, invert, normalize', () => {
  assert.deepEqual(S.combine([1, 2], [3, 2], 'add'), [1, 2, 3]);
  assert.deepEqual(S.combine([1, 2, 3], [2], 'subtract'), [1, 3]);
  assert.deepEqual(S.combine([1, 2, 3], [5, 4], 'replace'), [4, 5]);
  assert.deepEqual(S.invert([0, 2], 4), [1, 3]);
  assert.deepEqual(S.normalize([3, 3, -1, 9, 1.5, 0], 5), [0, 3]);
});

test('points project through a view-projection matrix and fall in boxes and lassos', () => {
  // An orthographic-like matrix: x, y in -1..1 map to the 100 x 100 view, y down.
  const m = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0.1, 0, 0, 0, 0, 1];
  const p = S.projectPoints([0, 0, 0, 1, 1, 0, -0.5, 0.5, 0, 0, 0, 50], m, 100, 100);
  assert.deepEqual([...p.subarray(0, 6)], [50, 50, 100, 0, 25, 25]);
  assert.ok(Number.isNaN(p[6])); // beyond the far plane
  assert.deepEqual(S.pointsInRegion(p, { rect: [20, 20, 60, 60] }), [0, 2]);
  // A triangle lasso around (25, 25) only.
  assert.deepEqual(S.pointsInRegion(p, { polygon: [10, 10, 45, 10, 10, 45] }), [2]);
  assert.deepEqual(
    S.pointsInRegion(p, { rect: [0, 0, 100, 100] }, (i) => i !== 1),
    [0, 2],
  );
  assert.equal(S.insidePolygon(5, 5, [0, 0, 10, 0, 10, 10, 0, 10]), true);
  assert.equal(S.insidePolygon(15, 5, [0, 0, 10, 0, 10, 10, 0, 10]), false);
});

test('centroids, areas and the vertices of faces', () => {
  const g = grid(2);
  const c = S.faceCentroids(g.positions, g.indices);
  assert.deepEqual(
    [...c.subarray(0, 3)].map((x) => +x.toFixed(5)),
    [0.66667, 0.33333, 0],
  );
  assert.equal(S.facesArea(g.positions, g.indices, [0, 1, 7]), 1.5);
  assert.deepEqual(S.verticesOfFaces(g.indices, [0, 1]), [0, 1, 3, 4]);
});
