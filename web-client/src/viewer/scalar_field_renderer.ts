// The renderer for one kind of quantity: a scalar field on a triangle
// surface (one float per vertex or per face), whatever algorithm made it.
//
// Vertex order: the Draco stream that the viewer shows is Edgebreaker-encoded
// and does not keep the server's vertex or face order, while scalar fields are
// indexed in the server's order. So the coloured surface is built from the
// mesh in the stored order (a PlyMesh): made from the streamed mesh and its
// stored ids (viewer/stored_order.ts), or read from a binary PLY (viewer/ply.ts)
// for a mesh not streamed here.
//
// Per-vertex fields: an indexed geometry with a colour per vertex, smooth
// shaded, colours interpolated across faces. Per-face fields: the geometry is
// made non-indexed (three corners per triangle, smooth normals kept) and each
// triangle's corners get its face's colour, so faces are flat-coloured and
// show the data exactly, without averaging.
import * as THREE from 'three';
import { colorMap, sample } from './colormaps.ts';
import type { PlyMesh } from './ply.ts';

export interface ScalarField {
  /** The artifact's name (legend title). */
  name: string;
  location: 'vertex' | 'face';
  values: Float32Array;
  /** The range the colours span: the Job's artifact range, or the values' own. */
  range: [number, number];
}

/** The smallest and largest finite value; [0, 0] when there is none. */
export function finiteRange(values: Float32Array): [number, number] {
  let lo = Infinity;
  let hi = -Infinity;
  for (const v of values) {
    if (!Number.isFinite(v)) continue;
    if (v < lo) lo = v;
    if (v > hi) hi = v;
  }
  return lo <= hi ? [lo, hi] : [0, 0];
}

/** Checks that the field has one value per vertex (face) of the mesh; throws a sentence otherwise. */
export function checkMatches(field: ScalarField, mesh: PlyMesh): void {
  const expected = field.location === 'face' ? mesh.faces : mesh.vertices;
  if (field.values.length !== expected) {
    throw new Error(`the field "${field.name}" has ${field.values.length} values, the mesh has ${expected} ${field.location === 'face' ? 'faces' : 'vertices'}`);
  }
}

/** Writes linear-sRGB vertex colours for `field` on `map` into the geometry's colour attribute. */
export function colourGeometry(geometry: THREE.BufferGeometry, field: ScalarField, mapName: string): void {
  const map = colorMap(mapName);
  const [lo, hi] = field.range;
  const count = geometry.getAttribute('position').count;
  let attr = geometry.getAttribute('color') as THREE.BufferAttribute | undefined;
  if (!attr || attr.count !== count) {
    attr = new THREE.BufferAttribute(new Float32Array(count * 3), 3);
    geometry.setAttribute('color', attr);
  }
  const out = attr.array as Float32Array;
  const rgb: [number, number, number] = [0, 0, 0];
  const c = new THREE.Color();
  const perCorner = field.location === 'face' ? 3 : 1;
  for (let i = 0; i < field.values.length; ++i) {
    sample(map, field.values[i]!, lo, hi, rgb);
    c.setRGB(rgb[0], rgb[1], rgb[2], THREE.SRGBColorSpace); // to the working (linear) space
    for (let k = 0; k < perCorner; ++k) {
      const j = (i * perCorner + k) * 3;
      out[j] = c.r;
      out[j + 1] = c.g;
      out[j + 2] = c.b;
    }
  }
  attr.needsUpdate = true;
}

/** A surface coloured by `field`. `mesh` must be in the server's order (checkMatches first). */
export function buildScalarSurface(mesh: PlyMesh, field: ScalarField, mapName: string): THREE.Mesh {
  checkMatches(field, mesh);
  let geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(mesh.positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(mesh.indices, 1));
  geometry.computeVertexNormals();
  if (field.location === 'face') {
    const flat = geometry.toNonIndexed(); // corners in face order: triangle f is corners 3f..3f+2
    geometry.dispose();
    geometry = flat;
  }
  colourGeometry(geometry, field, mapName);
  geometry.computeBoundingBox();
  geometry.computeBoundingSphere();
  const material = new THREE.MeshStandardMaterial({
    color: 0xffffff,
    vertexColors: true,
    roughness: 0.7,
    metalness: 0.0,
    side: THREE.DoubleSide,
  });
  const object = new THREE.Mesh(geometry, material);
  object.name = `scalar:${field.name}`;
  return object;
}
