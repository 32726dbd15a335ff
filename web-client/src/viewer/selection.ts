// Selections of faces or vertices of a triangle mesh, as pure functions on
// plain arrays (no three.js, no DOM: tests/selection.test.mjs runs them in
// node). Ids are the stored mesh's own: the arrays come from the mesh in the
// server's order (viewer/ply.ts), never from the Draco stream, whose
// Edgebreaker coder reorders faces and vertices.
//
// A selection is a sorted array of unique ids. Grow and shrink go by one
// ring: grow adds every face that shares a vertex with a selected face
// (MeshLab's "dilate"); shrink removes every selected face that shares a
// vertex with an unselected one ("erode"). Vertices go the same way through
// the edges of the triangles.

export type SelectionKind = 'faces' | 'vertices';
export type Combine = 'replace' | 'add' | 'subtract';

/** Compressed adjacency: the neighbours of i are items[offsets[i] .. offsets[i + 1]). */
export interface Adjacency {
  offsets: Uint32Array;
  items: Uint32Array;
}

/** The faces around each vertex (indices: three vertex ids per face). */
export function vertexFaces(indices: ArrayLike<number>, vertices: number): Adjacency {
  const offsets = new Uint32Array(vertices + 1);
  for (let i = 0; i < indices.length; ++i) ++offsets[indices[i]! + 1]!;
  for (let v = 0; v < vertices; ++v) offsets[v + 1]! += offsets[v]!;
  const items = new Uint32Array(indices.length);
  const fill = offsets.slice(0, vertices);
  for (let i = 0; i < indices.length; ++i) items[fill[indices[i]!]!++] = Math.floor(i / 3);
  return { offsets, items };
}

/** The vertices joined to each vertex by a triangle edge (each once). */
export function vertexNeighbours(indices: ArrayLike<number>, vertices: number): Adjacency {
  const around = vertexFaces(indices, vertices);
  const offsets = new Uint32Array(vertices + 1);
  const lists: number[][] = [];
  for (let v = 0; v < vertices; ++v) {
    const set = new Set<number>();
    for (let k = around.offsets[v]!; k < around.offsets[v + 1]!; ++k) {
      const f = around.items[k]!;
      for (let c = 0; c < 3; ++c) if (indices[3 * f + c] !== v) set.add(indices[3 * f + c]!);
    }
    lists.push([...set].sort((a, b) => a - b));
    offsets[v + 1] = offsets[v]! + set.size;
  }
  const items = new Uint32Array(offsets[vertices]!);
  lists.forEach((l, v) => items.set(l, offsets[v]!));
  return { offsets, items };
}

function sortedIds(set: Iterable<number>): number[] {
  return [...new Set(set)].sort((a, b) => a - b);
}

/** Sorted, unique, with `count` items at most considered (ids ≥ count dropped). */
export function normalize(ids: Iterable<number>, count: number): number[] {
  return sortedIds([...ids].filter((i) => Number.isInteger(i) && i >= 0 && i < count));
}

/** `current` combined with `hit` (replace: hit alone). */
export function combine(current: readonly number[], hit: Iterable<number>, how: Combine): number[] {
  if (how === 'replace') return sortedIds(hit);
  const set = new Set(current);
  for (const i of hit) how === 'add' ? set.add(i) : set.delete(i);
  return sortedIds(set);
}

/** Every id of 0..count-1 not in the selection. */
export function invert(selection: readonly number[], count: number): number[] {
  const set = new Set(selection);
  const out: number[] = [];
  for (let i = 0; i < count; ++i) if (!set.has(i)) out.push(i);
  return out;
}

/**
 * One ring more (grow) or less (shrink). Faces: neighbours share a vertex.
 * Vertices: neighbours share an edge. `vertices` is the mesh's vertex count.
 */
export function growShrink(kind: SelectionKind, selection: readonly number[], indices: ArrayLike<number>, vertices: number, grow: boolean): number[] {
  const selected = new Set(selection);
  const out = new Set(grow ? selection : []);
  if (kind === 'faces') {
    const around = vertexFaces(indices, vertices);
    // A vertex touches the selection (grow) or the rest of the mesh (shrink).
    const faces = indices.length / 3;
    const touches = new Uint8Array(vertices);
    for (let f = 0; f < faces; ++f) {
      if (selected.has(f) !== grow) continue;
      for (let c = 0; c < 3; ++c) touches[indices[3 * f + c]!] = 1;
    }
    if (grow) {
      for (let v = 0; v < vertices; ++v) {
        if (!touches[v]) continue;
        for (let k = around.offsets[v]!; k < around.offsets[v + 1]!; ++k) out.add(around.items[k]!);
      }
    } else {
      for (const f of selection) {
        let inner = true;
        for (let c = 0; c < 3; ++c) if (touches[indices[3 * f + c]!]) inner = false;
        if (inner) out.add(f);
      }
    }
  } else {
    const next = vertexNeighbours(indices, vertices);
    for (const v of selection) {
      let inner = true;
      for (let k = next.offsets[v]!; k < next.offsets[v + 1]!; ++k) {
        const w = next.items[k]!;
        if (grow) out.add(w);
        else if (!selected.has(w)) inner = false;
      }
      if (!grow && inner) out.add(v);
    }
  }
  return sortedIds(out);
}

/** Whether (x, y) is inside the polygon (even-odd rule); polygon: x0, y0, x1, y1, ... */
export function insidePolygon(x: number, y: number, polygon: ArrayLike<number>): boolean {
  let inside = false;
  const n = polygon.length / 2;
  for (let i = 0, j = n - 1; i < n; j = i++) {
    const xi = polygon[2 * i]!,
      yi = polygon[2 * i + 1]!,
      xj = polygon[2 * j]!,
      yj = polygon[2 * j + 1]!;
    if (yi > y !== yj > y && x < ((xj - xi) * (y - yi)) / (yj - yi) + xi) inside = !inside;
  }
  return inside;
}

/** The centroid of each face: xyz per face. */
export function faceCentroids(positions: ArrayLike<number>, indices: ArrayLike<number>): Float32Array {
  const faces = indices.length / 3;
  const out = new Float32Array(3 * faces);
  for (let f = 0; f < faces; ++f)
    for (let c = 0; c < 3; ++c) {
      const v = indices[3 * f + c]!;
      for (let a = 0; a < 3; ++a) out[3 * f + a]! += positions[3 * v + a]! / 3;
    }
  return out;
}

/**
 * Projects points (xyz each) to pixels of a width × height view with the
 * column-major 4×4 matrix `viewProjection` (projection × view): x, y per
 * point, y down from the top; NaN for points behind the camera or outside the
 * depth range.
 */
export function projectPoints(points: ArrayLike<number>, viewProjection: ArrayLike<number>, width: number, height: number): Float32Array {
  const m = viewProjection;
  const n = points.length / 3;
  const out = new Float32Array(2 * n);
  for (let i = 0; i < n; ++i) {
    const x = points[3 * i]!,
      y = points[3 * i + 1]!,
      z = points[3 * i + 2]!;
    const w = m[3]! * x + m[7]! * y + m[11]! * z + m[15]!;
    const cz = (m[2]! * x + m[6]! * y + m[10]! * z + m[14]!) / w;
    if (!(w > 0) || cz < -1 || cz > 1) {
      out[2 * i] = out[2 * i + 1] = NaN;
      continue;
    }
    const cx = (m[0]! * x + m[4]! * y + m[8]! * z + m[12]!) / w;
    const cy = (m[1]! * x + m[5]! * y + m[9]! * z + m[13]!) / w;
    out[2 * i] = ((cx + 1) / 2) * width;
    out[2 * i + 1] = ((1 - cy) / 2) * height;
  }
  return out;
}

/** A region of the view in pixels: a rectangle (x0 ≤ x1, y0 ≤ y1) or a lasso polygon. */
export type Region = { rect: [number, number, number, number] } | { polygon: number[] };

export function regionBounds(region: Region): [number, number, number, number] {
  if ('rect' in region) return region.rect;
  const p = region.polygon;
  let x0 = Infinity,
    y0 = Infinity,
    x1 = -Infinity,
    y1 = -Infinity;
  for (let i = 0; i < p.length; i += 2) {
    x0 = Math.min(x0, p[i]!);
    x1 = Math.max(x1, p[i]!);
    y0 = Math.min(y0, p[i + 1]!);
    y1 = Math.max(y1, p[i + 1]!);
  }
  return [x0, y0, x1, y1];
}

/** The ids of the projected points (x, y each, from projectPoints) inside the region, kept where `keep(id)`. */
export function pointsInRegion(projected: ArrayLike<number>, region: Region, keep: (id: number) => boolean = () => true): number[] {
  const [x0, y0, x1, y1] = regionBounds(region);
  const out: number[] = [];
  const n = projected.length / 2;
  for (let i = 0; i < n; ++i) {
    const x = projected[2 * i]!,
      y = projected[2 * i + 1]!;
    if (!(x >= x0 && x <= x1 && y >= y0 && y <= y1)) continue;
    if ('polygon' in region && !insidePolygon(x, y, region.polygon)) continue;
    if (keep(i)) out.push(i);
  }
  return out;
}

/** The total area of the faces listed. */
export function facesArea(positions: ArrayLike<number>, indices: ArrayLike<number>, faces: readonly number[]): number {
  let sum = 0;
  for (const f of faces) {
    const a = indices[3 * f]!,
      b = indices[3 * f + 1]!,
      c = indices[3 * f + 2]!;
    const ux = positions[3 * b]! - positions[3 * a]!,
      uy = positions[3 * b + 1]! - positions[3 * a + 1]!,
      uz = positions[3 * b + 2]! - positions[3 * a + 2]!;
    const vx = positions[3 * c]! - positions[3 * a]!,
      vy = positions[3 * c + 1]! - positions[3 * a + 1]!,
      vz = positions[3 * c + 2]! - positions[3 * a + 2]!;
    const cx = uy * vz - uz * vy,
      cy = uz * vx - ux * vz,
      cz = ux * vy - uy * vx;
    sum += Math.sqrt(cx * cx + cy * cy + cz * cz) / 2;
  }
  return sum;
}

/** The vertices of the faces listed (sorted, unique). */
export function verticesOfFaces(indices: ArrayLike<number>, faces: readonly number[]): number[] {
  const out = new Set<number>();
  for (const f of faces) for (let c = 0; c < 3; ++c) out.add(indices[3 * f + c]!);
  return sortedIds(out);
}
