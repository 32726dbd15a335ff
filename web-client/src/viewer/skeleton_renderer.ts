// The renderer for one kind of quantity: a curve skeleton, drawn over the
// mesh in one colour, as lines a few pixels wide (three's LineSegments2: a
// 1-pixel line is lost among a wireframe's) with a sphere at every node,
// bigger at its ends and branch nodes.
//
// X-ray (the default, as the EGL renderer draws it): the skeleton shows
// through the surface, since a curve skeleton lies inside its mesh. The
// depth buffer is cleared just before the skeletons are drawn (by an empty
// object drawn first), so that they still hide each other and their own far
// side as solid things do, rather than being drawn with no depth test at
// all. Off: they are drawn as any object, hidden where the surface is in
// front (a wireframe or points display shows where they run inside).
import * as THREE from 'three';
import { LineMaterial } from 'three/addons/lines/LineMaterial.js';
import { LineSegments2 } from 'three/addons/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/addons/lines/LineSegmentsGeometry.js';
import { nodeDegrees, type SkeletonData } from '../api/skeleton.ts';

/** Colours for skeletons drawn together: tab10 without its orange, the mesh's own colour. */
export const SKELETON_COLORS: readonly string[] = ['#1f77b4', '#2ca02c', '#d62728', '#9467bd', '#17becf', '#e377c2', '#8c564b', '#bcbd22'];

/** Width of the skeleton's lines in CSS pixels. */
export const SKELETON_LINE_PX = 3;

/** Draw order: the depth clear, then the lines, then the nodes (after the surfaces, which keep order 0). */
const ORDER = { clear: 9, lines: 10, nodes: 11 };

/** Sphere radius of a node between two edges, as a share of the skeleton's diagonal (ends and branch nodes: 1.6 times it). */
const NODE_SIZE = 0.006;

/** The parts of a skeleton whose materials x-ray changes, and the object that clears the depth before them. */
interface SkeletonParts {
  materials: THREE.Material[];
  clear: THREE.Object3D;
}

export function buildSkeleton(s: SkeletonData, color: THREE.ColorRepresentation, xray = true): THREE.Group {
  const group = new THREE.Group();
  group.name = 'skeleton';
  const nodeCount = s.nodes.length / 3;
  const node = (n: number) => new THREE.Vector3(s.nodes[n * 3]!, s.nodes[n * 3 + 1]!, s.nodes[n * 3 + 2]!);

  const positions = new Float32Array(s.edges.length * 3);
  for (let k = 0; k < s.edges.length; ++k) positions.set(s.nodes.subarray(s.edges[k]! * 3, s.edges[k]! * 3 + 3), k * 3);
  const lineMaterial = new LineMaterial({ color, linewidth: SKELETON_LINE_PX, worldUnits: false });
  const materials: THREE.Material[] = [lineMaterial];
  if (positions.length) {
    const lines = new LineSegmentsGeometry().setPositions(positions);
    const segments = new LineSegments2(lines, lineMaterial);
    segments.renderOrder = ORDER.lines;
    group.add(segments);
  }

  if (nodeCount) {
    const box = new THREE.Box3().setFromArray(s.nodes);
    const diagonal = box.getSize(new THREE.Vector3()).length();
    let edgeLength = 0;
    for (let k = 0; k < s.edges.length; k += 2) edgeLength += node(s.edges[k]!).distanceTo(node(s.edges[k + 1]!));
    const meanEdge = s.edges.length ? edgeLength / (s.edges.length / 2) : diagonal;
    // Small enough that the spheres of a dense skeleton do not run into one another.
    const radius = Math.max(Math.min(NODE_SIZE * diagonal, 0.3 * meanEdge), 1e-9);
    const sphere = new THREE.IcosahedronGeometry(radius, 2);
    const nodeMaterial = new THREE.MeshStandardMaterial({ color, roughness: 0.5 });
    materials.push(nodeMaterial);
    const spheres = new THREE.InstancedMesh(sphere, nodeMaterial, nodeCount);
    const degree = nodeDegrees(s);
    const m = new THREE.Matrix4();
    for (let n = 0; n < nodeCount; ++n) {
      const scale = degree[n] === 2 ? 1 : 1.6;
      spheres.setMatrixAt(n, m.makeScale(scale, scale, scale).setPosition(node(n)));
    }
    spheres.instanceMatrix.needsUpdate = true;
    spheres.renderOrder = ORDER.nodes;
    group.add(spheres);
  }

  const clear = depthClear(nodeCount ? node(0) : new THREE.Vector3());
  group.add(clear);
  group.userData.skeleton = { materials, clear } satisfies SkeletonParts;
  setSkeletonXray(group, xray);
  return group;
}

/** Shows the skeleton through the surface (x-ray) or hidden behind it as any object. */
export function setSkeletonXray(group: THREE.Object3D, on: boolean): void {
  const parts = group.userData.skeleton as SkeletonParts | undefined;
  if (!parts) return;
  parts.clear.visible = on;
  for (const m of parts.materials) {
    // Transparent objects are drawn after every opaque one, whatever their order: the surfaces come first.
    if (m.transparent !== on) {
      m.transparent = on;
      m.needsUpdate = true;
    }
  }
}

/**
 * An object that draws nothing and clears the depth buffer when its turn
 * comes (before the skeletons' lines and nodes, after the surfaces). Its one
 * degenerate triangle sits at `at`, a node of the skeleton, so that it adds
 * nothing to the box the camera frames.
 */
function depthClear(at: THREE.Vector3): THREE.Mesh {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute([...at.toArray(), ...at.toArray(), ...at.toArray()], 3));
  const material = new THREE.MeshBasicMaterial({ colorWrite: false, depthWrite: false, depthTest: false, transparent: true });
  const mesh = new THREE.Mesh(geometry, material);
  mesh.name = 'skeleton:x-ray';
  mesh.frustumCulled = false;
  mesh.renderOrder = ORDER.clear;
  mesh.raycast = () => {};
  mesh.onBeforeRender = (renderer) => renderer.clearDepth();
  return mesh;
}
