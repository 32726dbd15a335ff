// Whether a mesh's texture coordinates can show a texture at all: UVs that are
// not numbers, all one point, or with no area (every face's three on a line)
// draw one texel over the whole face, and the checkerboard chosen for a mesh
// with UVs would show as a broken surface. Pure (no three.js), so that node's
// unit tests load it.

/**
 * What is wrong with `uvs` (u, v per vertex) for the faces `indices` (three
 * vertex ids per face; null: the vertices three by three), as a sentence for
 * the texture panel; null when at least one face spans an area in UV space.
 * A face with a coordinate that is not a finite number is left out; a face
 * counts as having no area when its UV triangle is flat to 1e-6 (the sine
 * of its angle at a corner), whatever its size.
 */
export function uvProblem(uvs: ArrayLike<number>, indices: ArrayLike<number> | null): string | null {
  const corners = indices ? indices.length : uvs.length / 2;
  const at = (k: number) => (indices ? indices[k]! : k);
  let faces = 0;
  let first: [number, number] | null = null;
  let onePoint = true;
  for (let k = 0; k + 2 < corners; k += 3) {
    const a = at(k);
    const b = at(k + 1);
    const c = at(k + 2);
    const u0 = uvs[2 * a]!;
    const v0 = uvs[2 * a + 1]!;
    const u1 = uvs[2 * b]!;
    const v1 = uvs[2 * b + 1]!;
    const u2 = uvs[2 * c]!;
    const v2 = uvs[2 * c + 1]!;
    if (![u0, v0, u1, v1, u2, v2].every(Number.isFinite)) continue;
    ++faces;
    first ??= [u0, v0];
    if (onePoint && (u0 !== first[0] || v0 !== first[1] || u1 !== first[0] || v1 !== first[1] || u2 !== first[0] || v2 !== first[1])) onePoint = false;
    const e1u = u1 - u0;
    const e1v = v1 - v0;
    const e2u = u2 - u0;
    const e2v = v2 - v0;
    const cross = Math.abs(e1u * e2v - e1v * e2u);
    if (cross > 1e-6 * Math.hypot(e1u, e1v) * Math.hypot(e2u, e2v)) return null;
  }
  if (faces === 0) return 'The texture coordinates are not numbers: nothing to show.';
  if (onePoint) return 'The texture coordinates are all the same point: nothing to show.';
  return "The texture coordinates have no area (each face's lie on a line): nothing to show.";
}
