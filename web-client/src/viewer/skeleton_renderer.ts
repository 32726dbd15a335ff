// The renderer for one kind of quantity: a curve skeleton, drawn over the
// mesh (not hidden by it, as the EGL renderer draws it), as line segments in
// one colour with its ends and branch nodes as dots.
import * as THREE from 'three';
import { nodeDegrees, type SkeletonData } from '../api/skeleton.ts';

/** Colours for skeletons drawn together: tab10 without its orange, the mesh's own colour. */
export const SKELETON_COLORS: readonly string[] = ['#1f77b4', '#2ca02c', '#d62728', '#9467bd', '#17becf', '#e377c2', '#8c564b', '#bcbd22'];

export function buildSkeleton(s: SkeletonData, color: THREE.ColorRepresentation): THREE.Group {
  const group = new THREE.Group();
  const positions = new Float32Array(s.edges.length * 3);
  for (let k = 0; k < s.edges.length; ++k) positions.set(s.nodes.subarray(s.edges[k]! * 3, s.edges[k]! * 3 + 3), k * 3);
  const lines = new THREE.BufferGeometry();
  lines.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  const lineMaterial = new THREE.LineBasicMaterial({ color, depthTest: false, transparent: true });
  const segments = new THREE.LineSegments(lines, lineMaterial);
  segments.renderOrder = 10;
  group.add(segments);

  const degree = nodeDegrees(s);
  const marked: number[] = [];
  degree.forEach((d, n) => {
    if (d !== 2) marked.push(s.nodes[n * 3]!, s.nodes[n * 3 + 1]!, s.nodes[n * 3 + 2]!);
  });
  const dots = new THREE.BufferGeometry();
  dots.setAttribute('position', new THREE.Float32BufferAttribute(marked, 3));
  const dotMaterial = new THREE.PointsMaterial({ color, size: 6, sizeAttenuation: false, depthTest: false, transparent: true });
  const points = new THREE.Points(dots, dotMaterial);
  points.renderOrder = 11;
  group.add(points);
  return group;
}
