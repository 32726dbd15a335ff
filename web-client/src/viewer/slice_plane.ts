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
  const plane = new THREE.Mesh(new THREE.PlaneGeometry(w, h), material);
  const outline = new THREE.LineSegments(
    new THREE.EdgesGeometry(new THREE.PlaneGeometry(w, h)),
    new THREE.LineBasicMaterial({ color: 0x8fb8ff }),
  );
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
