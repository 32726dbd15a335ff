// A voxel slice in the 3D view: a plane at the slice's place in the world,
// textured with the 2D slice (each texel one voxel, nearest filtering), with
// an outline of the grid's section, so that it reads as a cut through the mesh.
import * as THREE from 'three';
import type { VoxelSlice } from '../api/voxel_slice.ts';

export function buildSlicePlane(canvas: HTMLCanvasElement, slice: VoxelSlice): THREE.Object3D {
  const s = slice.voxelSize;
  const w = slice.width * s;
  const h = slice.height * s;
  const texture = new THREE.CanvasTexture(canvas);
  texture.magFilter = THREE.NearestFilter;
  texture.minFilter = THREE.NearestFilter;
  texture.colorSpace = THREE.SRGBColorSpace;
  const material = new THREE.MeshBasicMaterial({ map: texture, transparent: true, side: THREE.DoubleSide, depthWrite: false });
  // disposeObject() frees geometries and materials, not textures: the overlay
  // is replaced at every slider step, so its texture goes with its material.
  material.addEventListener('dispose', () => texture.dispose());
  const plane = new THREE.Mesh(new THREE.PlaneGeometry(w, h), material);
  const outline = new THREE.LineSegments(new THREE.EdgesGeometry(new THREE.PlaneGeometry(w, h)), new THREE.LineBasicMaterial({ color: 0x8fb8ff }));
  const group = new THREE.Group();
  group.add(plane, outline);
  // The plane's local (x, y) are the slice's (width, height) axes; its centre
  // sits half a voxel into the slice along the cut axis.
  const [cx, cy, cz] = slice.corner;
  if (slice.axis === 'z') {
    group.position.set(cx + w / 2, cy + h / 2, cz + s / 2);
  } else if (slice.axis === 'x') {
    // width along y, height along z: rotate the plane's x to y and y to z.
    group.setRotationFromMatrix(new THREE.Matrix4().makeBasis(new THREE.Vector3(0, 1, 0), new THREE.Vector3(0, 0, 1), new THREE.Vector3(1, 0, 0)));
    group.position.set(cx + s / 2, cy + w / 2, cz + h / 2);
  } else {
    // y slice: width along x, height along z.
    group.setRotationFromMatrix(new THREE.Matrix4().makeBasis(new THREE.Vector3(1, 0, 0), new THREE.Vector3(0, 0, 1), new THREE.Vector3(0, -1, 0)));
    group.position.set(cx + w / 2, cy + s / 2, cz + h / 2);
  }
  return group;
}

/** The section at a slice: keeps what lies below the far side of the slice's
 * voxel layer along its axis (the slice plane itself stays visible). */
export function sliceClipPlane(slice: VoxelSlice): THREE.Plane {
  const a = slice.axis === 'x' ? 0 : slice.axis === 'y' ? 1 : 2;
  const normal = new THREE.Vector3();
  normal.setComponent(a, -1);
  return new THREE.Plane(normal, slice.corner[a]! + slice.voxelSize);
}
