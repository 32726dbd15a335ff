// The renderer for one kind of quantity: a vector field on a triangle
// surface (one 3D vector per vertex or per face), whatever algorithm made it,
// drawn as line segments (one THREE.LineSegments, one BufferGeometry):
//
// - hint "direction" (unit vectors whose sign means nothing: principal
//   directions): a segment centred on the point, as long both ways;
// - hint "arrow" (length and sign mean something: a gradient, a flow): a
//   segment from the point along the vector, scaled by its length over the
//   field's longest.
//
// The point is the vertex, or the face's centroid, of the mesh in the
// server's stored order (viewer/stored_order.ts or viewer/ply.ts), the order
// the field is in. A vector with a NaN (no value) is skipped, and counted.
//
// Length: a fraction of the mesh's mean edge length, not of its bounding
// box. The vectors sit one per vertex (face), so they are about an edge apart
// whatever the mesh's size or resolution: a share of the edge keeps the
// segments of neighbours from running into one another on a dense mesh and
// still visible on a coarse one, where a share of the box would make a dense
// mesh a solid hatch and a coarse one dots.
//
// Depth: the segments lie in the tangent plane, so half of each would dip
// into a concave surface and flicker with it. Each point is drawn a little
// towards the camera (along its view ray, so it stays where it is on
// screen), which works whichever way the faces are turned, where lifting
// along the normal would bury the lines of a mesh oriented inwards.
import * as THREE from 'three';
import type { PlyMesh } from './ply.ts';

export type VectorHint = 'arrow' | 'direction';

export interface VectorField {
  /** The artifact's name. */
  name: string;
  location: 'vertex' | 'face';
  hint: VectorHint;
  /** x, y, z per vertex (face), in the stored order. */
  values: Float32Array;
  /** The longest finite vector's length: an arrow of it is drawn at the full length. */
  maxLength: number;
}

/**
 * Colours for the fields drawn together: near-black first (it reads on the
 * orange surface and on the light middle of a diverging colour map, as a
 * curvature is drawn in), then near-white (a vertex's two principal
 * directions cross as dark and light), then blue, green, purple.
 */
export const VECTOR_COLORS: readonly string[] = ['#101418', '#f2f2f2', '#2f6fff', '#19a85a', '#a23ee0'];

/** A segment's full length at scale 1, as a share of the mean edge length: vertices are about an edge apart, face centroids about 0.6 of one. */
const SHARE = { vertex: 0.8, face: 0.45 } as const;

/** How far each point is drawn towards the camera, as a share of the mean edge length (see Depth above). */
const TOWARDS = 0.12;

/** The mean length of the triangles' edges (an edge of two triangles counts twice); 0 without faces. */
export function meanEdgeLength(mesh: PlyMesh): number {
  const p = mesh.positions;
  const ix = mesh.indices;
  let sum = 0;
  for (let t = 0; t + 2 < ix.length; t += 3) {
    for (let k = 0; k < 3; ++k) {
      const a = 3 * ix[t + k]!;
      const b = 3 * ix[t + ((k + 1) % 3)]!;
      sum += Math.hypot(p[a]! - p[b]!, p[a + 1]! - p[b + 1]!, p[a + 2]! - p[b + 2]!);
    }
  }
  return ix.length ? sum / ix.length : 0;
}

/** The longest finite vector's length (0 when there is none). */
export function longest(values: Float32Array): number {
  let max = 0;
  for (let i = 0; i + 2 < values.length; i += 3) {
    const l = Math.hypot(values[i]!, values[i + 1]!, values[i + 2]!);
    if (Number.isFinite(l) && l > max) max = l;
  }
  return max;
}

/** Checks that the field has one vector per vertex (face) of the mesh; throws a sentence otherwise. */
export function checkVectorsMatch(field: VectorField, mesh: PlyMesh): void {
  const expected = field.location === 'face' ? mesh.faces : mesh.vertices;
  const count = field.values.length / 3;
  if (count !== expected) {
    throw new Error(`the field "${field.name}" has ${count} vectors, the mesh has ${expected} ${field.location === 'face' ? 'faces' : 'vertices'}`);
  }
}

/**
 * Where each vector sits: its vertex, or its face's centroid; NaN for a
 * vertex no face uses (the streamed mesh does not have it, so it has no place).
 */
function origins(mesh: PlyMesh, location: 'vertex' | 'face'): Float32Array {
  const p = mesh.positions;
  const ix = mesh.indices;
  if (location === 'face') {
    const out = new Float32Array(3 * mesh.faces);
    for (let f = 0; f < mesh.faces; ++f) {
      for (let c = 0; c < 3; ++c) out[3 * f + c] = (p[3 * ix[3 * f]! + c]! + p[3 * ix[3 * f + 1]! + c]! + p[3 * ix[3 * f + 2]! + c]!) / 3;
    }
    return out;
  }
  const used = new Uint8Array(mesh.vertices);
  for (const v of ix) used[v] = 1;
  const out = new Float32Array(p.subarray(0, 3 * mesh.vertices));
  for (let v = 0; v < mesh.vertices; ++v) if (!used[v]) out[3 * v] = NaN;
  return out;
}

/** What a drawn field says of itself: vectors drawn, vectors without a value, the full length at scale 1 (mesh units). */
export interface VectorStats {
  drawn: number;
  missing: number;
  length: number;
}

/**
 * A vector field drawn over its mesh: one LineSegments, two points per
 * vector drawn. `setScale` changes the segments' length in place.
 */
export class VectorGlyphs {
  readonly object: THREE.LineSegments;
  readonly stats: VectorStats;
  private readonly field: VectorField;
  private readonly at: Float32Array;
  /** The mean edge length: what the lengths are shares of. */
  private readonly edge: number;
  private readonly towards: { value: number };
  private scale: number;

  constructor(mesh: PlyMesh, field: VectorField, color: THREE.ColorRepresentation, scale = 1) {
    checkVectorsMatch(field, mesh);
    this.field = field;
    this.at = origins(mesh, field.location);
    const edge = meanEdgeLength(mesh);
    this.edge = edge;
    this.scale = scale;
    let drawn = 0;
    let missing = 0;
    const v = field.values;
    for (let i = 0; i < v.length; i += 3) {
      if (!(Number.isFinite(v[i]!) && Number.isFinite(v[i + 1]!) && Number.isFinite(v[i + 2]!))) ++missing;
      else if (Number.isFinite(this.at[i]!)) ++drawn;
    }
    this.stats = { drawn, missing, length: SHARE[field.location] * edge };
    this.towards = { value: TOWARDS * edge * Math.max(1, scale) };
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(6 * drawn), 3));
    const material = new THREE.LineBasicMaterial({ color, toneMapped: false });
    const towards = this.towards;
    material.onBeforeCompile = (shader) => {
      shader.uniforms.towards = towards;
      shader.vertexShader = shader.vertexShader.replace('void main() {', 'uniform float towards;\nvoid main() {').replace(
        '#include <project_vertex>',
        `#include <project_vertex>
        mvPosition.xyz -= (isPerspectiveMatrix(projectionMatrix) ? normalize(mvPosition.xyz) : vec3(0.0, 0.0, -1.0)) * towards;
        gl_Position = projectionMatrix * mvPosition;`,
      );
    };
    this.object = new THREE.LineSegments(geometry, material);
    this.object.name = `vectors:${field.name}`;
    this.object.renderOrder = 5; // over the surfaces, as the overlays' lines
    this.write();
  }

  /** The segments' length, as a multiple of the default. */
  setScale(scale: number): void {
    this.scale = scale;
    this.towards.value = TOWARDS * this.edge * Math.max(1, scale);
    this.write();
  }

  private write(): void {
    const attr = this.object.geometry.getAttribute('position') as THREE.BufferAttribute;
    const out = attr.array as Float32Array;
    const { values: v, hint, maxLength } = this.field;
    const full = this.stats.length * this.scale;
    // A direction: half its length each way; an arrow: from the point, its share of the longest.
    const along = hint === 'direction' ? full / 2 : maxLength > 0 ? full / maxLength : 0;
    const back = hint === 'direction' ? along : 0;
    let j = 0;
    for (let i = 0; i < v.length; i += 3) {
      const x = v[i]!;
      const y = v[i + 1]!;
      const z = v[i + 2]!;
      if (!(Number.isFinite(x) && Number.isFinite(y) && Number.isFinite(z) && Number.isFinite(this.at[i]!))) continue;
      // A direction is drawn at one length whatever its vector's (unit, but not trusted to be).
      const n = hint === 'direction' ? Math.hypot(x, y, z) || 1 : 1;
      const ax = this.at[i]!;
      const ay = this.at[i + 1]!;
      const az = this.at[i + 2]!;
      const b = back / n;
      const f = along / n;
      out[j] = ax - b * x;
      out[j + 1] = ay - b * y;
      out[j + 2] = az - b * z;
      out[j + 3] = ax + f * x;
      out[j + 4] = ay + f * y;
      out[j + 5] = az + f * z;
      j += 6;
    }
    attr.needsUpdate = true;
    this.object.geometry.computeBoundingBox();
    this.object.geometry.computeBoundingSphere();
  }
}
