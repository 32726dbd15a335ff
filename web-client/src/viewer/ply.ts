// A reader for the binary little-endian PLY that the server writes
// (GET /meshes/{id}/download?format=ply): vertex x y z (any numeric type,
// other vertex properties skipped) and triangle faces as a list property.
// PLY keeps the server's vertex and face order, which the Draco stream
// (Edgebreaker) does not: it is how the viewer gets that order for a mesh it
// has not streamed (a job's output mesh); a streamed mesh gets it from its
// stored ids instead (viewer/stored_order.ts).

export interface PlyMesh {
  positions: Float32Array;
  indices: Uint32Array;
  vertices: number;
  faces: number;
}

const SIZES: Record<string, number> = {
  char: 1,
  int8: 1,
  uchar: 1,
  uint8: 1,
  short: 2,
  int16: 2,
  ushort: 2,
  uint16: 2,
  int: 4,
  int32: 4,
  uint: 4,
  uint32: 4,
  float: 4,
  float32: 4,
  double: 8,
  float64: 8,
};

function reader(type: string): (v: DataView, at: number) => number {
  switch (type) {
    case 'char':
    case 'int8':
      return (v, at) => v.getInt8(at);
    case 'uchar':
    case 'uint8':
      return (v, at) => v.getUint8(at);
    case 'short':
    case 'int16':
      return (v, at) => v.getInt16(at, true);
    case 'ushort':
    case 'uint16':
      return (v, at) => v.getUint16(at, true);
    case 'int':
    case 'int32':
      return (v, at) => v.getInt32(at, true);
    case 'uint':
    case 'uint32':
      return (v, at) => v.getUint32(at, true);
    case 'float':
    case 'float32':
      return (v, at) => v.getFloat32(at, true);
    case 'double':
    case 'float64':
      return (v, at) => v.getFloat64(at, true);
    default:
      throw new Error(`PLY: unknown property type "${type}"`);
  }
}

interface Property {
  name: string;
  type: string;
  /** For list properties: the count's type. */
  countType?: string;
}

interface Element {
  name: string;
  count: number;
  properties: Property[];
}

export function parsePly(buffer: ArrayBuffer): PlyMesh {
  const bytes = new Uint8Array(buffer);
  // The header is ASCII and ends with "end_header\n".
  const probe = new TextDecoder('latin1').decode(bytes.subarray(0, Math.min(bytes.length, 65536)));
  const end = probe.indexOf('end_header');
  if (!probe.startsWith('ply') || end < 0) throw new Error('PLY: no header');
  const bodyStart = probe.indexOf('\n', end) + 1;
  const lines = probe.slice(0, end).split(/\r?\n/);
  const elements: Element[] = [];
  let format = '';
  for (const line of lines) {
    const w = line.trim().split(/\s+/);
    if (w[0] === 'format') format = w[1] ?? '';
    else if (w[0] === 'element') elements.push({ name: w[1]!, count: Number(w[2]), properties: [] });
    else if (w[0] === 'property' && elements.length) {
      const props = elements[elements.length - 1]!.properties;
      if (w[1] === 'list') props.push({ name: w[4]!, type: w[3]!, countType: w[2]! });
      else props.push({ name: w[2]!, type: w[1]! });
    }
  }
  if (format !== 'binary_little_endian') throw new Error(`PLY: format "${format}" is not read here`);

  const view = new DataView(buffer);
  let at = bodyStart;
  let positions = new Float32Array(0);
  let indices = new Uint32Array(0);
  for (const element of elements) {
    if (element.name === 'vertex') {
      positions = new Float32Array(element.count * 3);
      const props = element.properties.map((p) => ({ ...p, read: reader(p.type), axis: ['x', 'y', 'z'].indexOf(p.name) }));
      if (props.some((p) => p.countType)) throw new Error('PLY: list properties on vertices are not read here');
      for (let i = 0; i < element.count; ++i) {
        for (const p of props) {
          if (p.axis >= 0) positions[i * 3 + p.axis] = p.read(view, at);
          at += SIZES[p.type]!;
        }
      }
    } else if (element.name === 'face') {
      const tris: number[] = [];
      const props = element.properties.map((p) => ({
        ...p,
        read: reader(p.type),
        readCount: p.countType ? reader(p.countType) : null,
      }));
      for (let i = 0; i < element.count; ++i) {
        for (const p of props) {
          if (p.readCount) {
            const n = p.readCount(view, at);
            at += SIZES[p.countType!]!;
            const size = SIZES[p.type]!;
            if (p.name === 'vertex_indices' || p.name === 'vertex_index') {
              // A fan for polygons (the server writes triangles only).
              const first = p.read(view, at);
              for (let k = 1; k + 1 < n; ++k) tris.push(first, p.read(view, at + k * size), p.read(view, at + (k + 1) * size));
            }
            at += n * size;
          } else {
            at += SIZES[p.type]!;
          }
        }
      }
      indices = Uint32Array.from(tris);
    } else {
      // An element we do not use: skip it (fixed-size properties only).
      for (const p of element.properties) {
        if (p.countType) throw new Error(`PLY: cannot skip list element "${element.name}"`);
      }
      at += element.count * element.properties.reduce((s, p) => s + SIZES[p.type]!, 0);
    }
  }
  return { positions, indices, vertices: positions.length / 3, faces: indices.length / 3 };
}
