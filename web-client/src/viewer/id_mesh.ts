// The id buffer's mesh: what the selection tool draws off screen to read
// which face shows at each pixel.
import * as THREE from 'three';
import type { PlyMesh } from './ply.ts';

/** Each face in its own colour, id + 1 in 24 bits (0: nothing drawn): a triangle soup. */
export function idMesh(ply: PlyMesh): THREE.Mesh {
  const faces = ply.faces;
  const positions = new Float32Array(9 * faces);
  const colors = new Uint8Array(9 * faces);
  for (let f = 0; f < faces; ++f) {
    const id = f + 1;
    for (let c = 0; c < 3; ++c) {
      const v = ply.indices[3 * f + c]!;
      positions.set(ply.positions.subarray(3 * v, 3 * v + 3), 9 * f + 3 * c);
      colors[9 * f + 3 * c] = id & 255;
      colors[9 * f + 3 * c + 1] = (id >> 8) & 255;
      colors[9 * f + 3 * c + 2] = (id >> 16) & 255;
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colors, 3, true));
  // Exact colours: no lighting, no tone mapping; render targets get no colour-space conversion.
  const material = new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.DoubleSide, toneMapped: false });
  return new THREE.Mesh(geometry, material);
}
