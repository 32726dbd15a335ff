// Voxels in 3D: a grid read from its NRRD artifact (the format the worker
// stores, protocol/API.md), and the voxels above a threshold drawn as
// cubes, one instance each. Only the voxels on the boundary of the kept set
// (a 6-neighbour not kept, or the grid's edge) are drawn: the inside ones
// cannot be seen, and a 128³ solid keeps millions.
import * as THREE from 'three';

export interface VoxelVolume {
  dims: [number, number, number];
  /** The centre of voxel (0, 0, 0). */
  origin: [number, number, number];
  size: number;
  values: Uint8Array | Float32Array;
}

/** Parses the NRRD the server writes (raw, little-endian uint8 or float, axis-aligned); throws on others. */
export function parseNrrd(buffer: ArrayBuffer): VoxelVolume {
  const bytes = new Uint8Array(buffer);
  let end = -1;
  for (let i = 0; i + 1 < bytes.length && i < 65536; ++i) {
    if (bytes[i] === 10 && bytes[i + 1] === 10) {
      end = i;
      break;
    }
  }
  if (end < 0) throw new Error('not a NRRD file: no end of header');
  const header = new TextDecoder().decode(bytes.subarray(0, end));
  if (!header.startsWith('NRRD')) throw new Error('not a NRRD file');
  const field = (name: string): string => {
    const m = new RegExp(`^${name}:\\s*(.*)$`, 'm').exec(header);
    if (!m) throw new Error(`NRRD header has no "${name}"`);
    return m[1]!.trim();
  };
  const sizes = field('sizes').split(/\s+/).map(Number);
  if (sizes.length !== 3 || !sizes.every((n) => Number.isInteger(n) && n > 0)) throw new Error(`bad NRRD sizes: ${field('sizes')}`);
  const type = field('type');
  if (field('encoding') !== 'raw') throw new Error('only raw NRRD is read');
  const numbers = (text: string) => (text.match(/-?[0-9.eE+-]+/g) ?? []).map(Number);
  const origin = numbers(field('space origin'));
  const size = numbers(field('space directions'))[0] ?? 1;
  const count = sizes[0]! * sizes[1]! * sizes[2]!;
  const start = end + 2;
  let values: Uint8Array | Float32Array;
  if (type === 'uint8' || type === 'unsigned char') {
    values = bytes.slice(start, start + count);
  } else if (type === 'float') {
    values = new Float32Array(bytes.slice(start, start + 4 * count).buffer);
  } else {
    throw new Error(`NRRD type ${type} is not read`);
  }
  if (values.length !== count) throw new Error(`NRRD payload holds ${values.length} of ${count} values`);
  return { dims: sizes as [number, number, number], origin: origin as [number, number, number], size, values };
}

/** The smallest and largest value. */
export function valueRange(v: VoxelVolume): [number, number] {
  let lo = Infinity;
  let hi = -Infinity;
  for (const x of v.values) {
    if (x < lo) lo = x;
    if (x > hi) hi = x;
  }
  return lo <= hi ? [lo, hi] : [0, 0];
}

/**
 * The kept voxels (value above `cut`, and not 0) on the boundary of the kept
 * set, as instanced cubes coloured by value; `count` is how many are drawn,
 * `kept` how many are above the threshold in all.
 */
export function buildVoxels(v: VoxelVolume, cut: number): { object: THREE.InstancedMesh; count: number; kept: number } {
  const [nx, ny, nz] = v.dims;
  const keep = (i: number, j: number, k: number) => {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return false;
    const x = v.values[i + nx * (j + ny * k)]!;
    return x !== 0 && x > cut;
  };
  const cells: number[] = [];
  let kept = 0;
  for (let k = 0; k < nz; ++k)
    for (let j = 0; j < ny; ++j)
      for (let i = 0; i < nx; ++i) {
        if (!keep(i, j, k)) continue;
        ++kept;
        if (keep(i - 1, j, k) && keep(i + 1, j, k) && keep(i, j - 1, k) && keep(i, j + 1, k) && keep(i, j, k - 1) && keep(i, j, k + 1)) continue;
        cells.push(i, j, k);
      }
  const count = cells.length / 3;
  const geometry = new THREE.BoxGeometry(v.size * 0.96, v.size * 0.96, v.size * 0.96);
  const material = new THREE.MeshStandardMaterial({ color: 0xffffff, roughness: 0.7, metalness: 0.0 });
  const object = new THREE.InstancedMesh(geometry, material, Math.max(1, count));
  object.count = count;
  const [lo, hi] = valueRange(v);
  const span = hi > lo ? hi - lo : 1;
  const m = new THREE.Matrix4();
  const colour = new THREE.Color();
  for (let n = 0; n < count; ++n) {
    const i = cells[3 * n]!;
    const j = cells[3 * n + 1]!;
    const k = cells[3 * n + 2]!;
    m.makeTranslation(v.origin[0] + i * v.size, v.origin[1] + j * v.size, v.origin[2] + k * v.size);
    object.setMatrixAt(n, m);
    const t = (v.values[i + nx * (j + ny * k)]! - lo) / span;
    colour.setRGB((80 + 175 * t) / 255, (160 + 60 * t) / 255, 230 / 255, THREE.SRGBColorSpace);
    object.setColorAt(n, colour);
  }
  object.instanceMatrix.needsUpdate = true;
  if (object.instanceColor) object.instanceColor.needsUpdate = true;
  return { object, count, kept };
}
