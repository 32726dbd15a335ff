// The renderer for one kind of quantity: a triangle surface, smooth-shaded.
// Builds a three.js mesh from a decoded payload.
import * as THREE from 'three';
import { markFileNormals } from './crease.ts';
import type { DecodedColors, DecodedMesh } from './decoded_mesh.ts';

/** The default surface colour: an orange that tests can find in screenshots. */
export const SURFACE_COLOR = '#e07a1f';

/**
 * Mesh files store colours in sRGB; three.js expects vertex colours in linear
 * sRGB. Returns float RGB(A) in 0..1, the colour channels converted.
 */
function linearColors(colors: DecodedColors): THREE.BufferAttribute {
  const { array, itemSize, normalized } = colors;
  const scale = !normalized ? 1 : array instanceof Uint8Array ? 1 / 255 : array instanceof Uint16Array ? 1 / 65535 : 1;
  const out = new Float32Array(array.length);
  const c = new THREE.Color();
  for (let i = 0; i < array.length; i += itemSize) {
    // setRGB with a colour space converts to the working (linear) space.
    c.setRGB(array[i]! * scale, array[i + 1]! * scale, array[i + 2]! * scale, THREE.SRGBColorSpace);
    out[i] = c.r;
    out[i + 1] = c.g;
    out[i + 2] = c.b;
    if (itemSize === 4) out[i + 3] = array[i + 3]! * scale;
  }
  return new THREE.BufferAttribute(out, itemSize);
}

export function buildSurface(decoded: DecodedMesh): THREE.Mesh {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(decoded.positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(decoded.indices, 1));
  // Drawn per material only with an array of materials (viewer/textures.ts); one material draws them all.
  for (const g of decoded.groups ?? []) geometry.addGroup(g.start, g.count, g.material);
  if (decoded.normals) {
    geometry.setAttribute('normal', new THREE.BufferAttribute(decoded.normals, 3));
    markFileNormals(geometry); // kept by the crease angle (viewer/crease.ts)
  } else {
    geometry.computeVertexNormals();
  }
  const colors = decoded.colors;
  if (colors) geometry.setAttribute('color', linearColors(colors));
  if (decoded.uvs) geometry.setAttribute('uv', new THREE.BufferAttribute(decoded.uvs, 2));
  geometry.computeBoundingBox();
  geometry.computeBoundingSphere();

  const material = new THREE.MeshStandardMaterial({
    color: colors ? 0xffffff : SURFACE_COLOR,
    vertexColors: colors !== null,
    roughness: 0.6,
    metalness: 0.0,
    // Open meshes (boundary loops) show their inside too.
    side: THREE.DoubleSide,
  });
  const mesh = new THREE.Mesh(geometry, material);
  mesh.name = 'surface';
  return mesh;
}

/** The colour of meshes that jobs made, shown beside the input mesh. */
export const ARTIFACT_COLOR = '#6fa8dc';

/** A plain smooth-shaded surface from positions and triangle indices (a job's mesh artifact). */
export function buildPlainSurface(positions: Float32Array, indices: Uint32Array, color: string = ARTIFACT_COLOR): THREE.Mesh {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(indices, 1));
  geometry.computeVertexNormals();
  geometry.computeBoundingBox();
  geometry.computeBoundingSphere();
  const material = new THREE.MeshStandardMaterial({ color, roughness: 0.6, metalness: 0.0, side: THREE.DoubleSide });
  const mesh = new THREE.Mesh(geometry, material);
  mesh.name = 'artifact';
  return mesh;
}
