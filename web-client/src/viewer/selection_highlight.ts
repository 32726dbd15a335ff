// The selection drawn over the surface: the selected faces in a
// translucent colour pulled towards the camera, or the selected vertices as
// points drawn over everything.
import * as THREE from 'three';
import type { PlyMesh } from './ply.ts';
import type { SelectionKind } from './selection.ts';

const HIGHLIGHT = '#ff2d75';

/** The highlight of `ids` (faces or vertices of `ply`, in the stored order), in the mesh's own coordinates. */
export function highlight(ply: PlyMesh, kind: SelectionKind, ids: readonly number[]): THREE.Object3D {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(ply.positions, 3));
  let object: THREE.Object3D;
  if (kind === 'faces') {
    const index = new Uint32Array(3 * ids.length);
    ids.forEach((f, k) => index.set(ply.indices.subarray(3 * f, 3 * f + 3), 3 * k));
    geometry.setIndex(new THREE.BufferAttribute(index, 1));
    // Drawn over the surface: pulled towards the camera in depth.
    const material = new THREE.MeshBasicMaterial({
      color: HIGHLIGHT,
      side: THREE.DoubleSide,
      transparent: true,
      opacity: 0.75,
      polygonOffset: true,
      polygonOffsetFactor: -2,
      polygonOffsetUnits: -2,
    });
    object = new THREE.Mesh(geometry, material);
  } else {
    geometry.setIndex(new THREE.BufferAttribute(new Uint32Array(ids), 1));
    object = new THREE.Points(geometry, new THREE.PointsMaterial({ color: HIGHLIGHT, size: 7, sizeAttenuation: false, depthTest: false }));
  }
  return object;
}
