// Boundary and non-manifold edges of a triangle mesh, for the viewer's edge
// overlay. Pure (no DOM, no three.js), so that node's unit tests load it.
//
// Vertices are welded by exact position first: the Draco stream and a
// per-face field's unindexed geometry both split vertices that the mesh
// shares (attribute seams, one copy per corner), which would make every
// split edge look like a boundary.

export interface EdgeClasses {
  /** Vertex pairs (into the original vertex order), two per edge: edges used by one triangle. */
  boundary: Uint32Array;
  /** Vertex pairs of edges used by more than two triangles. */
  nonManifold: Uint32Array;
}

/**
 * Classifies the edges of the triangles `index` (three vertex indices per
 * triangle; null: consecutive triples, an unindexed geometry) over
 * `positions` (xyz per vertex). Degenerate triangles (a repeated welded
 * vertex) are skipped.
 */
export function classifyEdges(positions: ArrayLike<number>, index: ArrayLike<number> | null): EdgeClasses {
  const vertexCount = Math.floor(positions.length / 3);
  // Weld: canonical vertex of each vertex, by exact position.
  const canonical = new Uint32Array(vertexCount);
  const seen = new Map<string, number>();
  for (let v = 0; v < vertexCount; ++v) {
    const key = `${positions[3 * v]},${positions[3 * v + 1]},${positions[3 * v + 2]}`;
    const first = seen.get(key);
    if (first === undefined) {
      seen.set(key, v);
      canonical[v] = v;
    } else {
      canonical[v] = first;
    }
  }
  const corners = index ? index.length : vertexCount;
  const at = (i: number) => canonical[index ? index[i]! : i]!;
  // Edge key: lo * n + hi (below 2^53 for any mesh that fits in memory).
  const uses = new Map<number, number>();
  for (let t = 0; t + 2 < corners; t += 3) {
    const a = at(t);
    const b = at(t + 1);
    const c = at(t + 2);
    if (a === b || b === c || c === a) continue;
    for (const [u, v] of [
      [a, b],
      [b, c],
      [c, a],
    ] as const) {
      const key = u < v ? u * vertexCount + v : v * vertexCount + u;
      uses.set(key, (uses.get(key) ?? 0) + 1);
    }
  }
  const boundary: number[] = [];
  const nonManifold: number[] = [];
  for (const [key, n] of uses) {
    if (n === 2) continue;
    const lo = Math.floor(key / vertexCount);
    const hi = key - lo * vertexCount;
    (n === 1 ? boundary : nonManifold).push(lo, hi);
  }
  return { boundary: Uint32Array.from(boundary), nonManifold: Uint32Array.from(nonManifold) };
}
