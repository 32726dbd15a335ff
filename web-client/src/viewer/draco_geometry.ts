// What a Draco bitstream holds, as the viewer draws it (DecodedMesh): a
// triangle mesh (TRIANGULAR_MESH) or a point cloud (POINT_CLOUD: an uploaded
// cloud, a job's points), with positions and, where the stream has them,
// normals, colours, UVs and material ids. Pure: given draco3d's decoder
// module, so the worker (draco_worker.ts) and node's unit tests run the same
// code.
import type { DracoAttribute, DracoDecoder, DracoDecoderModule, DracoMesh, DracoPointCloud } from 'draco3d/draco_decoder_nodejs.js';
import type { DecodedColors, DecodedMesh, MaterialGroup } from './decoded_mesh.ts';

/** The typed arrays an attribute is read into. */
type AttributeArray = Float32Array | Uint32Array | Uint16Array | Uint8Array;
interface AttributeArrayType<T extends AttributeArray> {
  new (buffer: ArrayBufferLike, byteOffset: number, length: number): T;
  readonly BYTES_PER_ELEMENT: number;
}

/** An attribute's values for every point, as `dracoType` (one of draco.DT_*) into an array of `Type`. */
function readAttribute<T extends AttributeArray>(
  draco: DracoDecoderModule,
  decoder: DracoDecoder,
  mesh: DracoPointCloud,
  attr: DracoAttribute,
  dracoType: number,
  Type: AttributeArrayType<T>,
  what: string,
): T {
  const n = mesh.num_points() * attr.num_components();
  const bytes = n * Type.BYTES_PER_ELEMENT;
  const ptr = draco._malloc(bytes);
  try {
    if (!decoder.GetAttributeDataArrayForAllPoints(mesh, attr, dracoType, bytes, ptr)) {
      throw new Error(`Draco: cannot read ${what}`);
    }
    return new Type(draco.HEAPF32.buffer, ptr, n).slice() as T;
  } finally {
    draco._free(ptr);
  }
}

function readFloat32(draco: DracoDecoderModule, decoder: DracoDecoder, mesh: DracoPointCloud, attr: DracoAttribute): Float32Array {
  return readAttribute(draco, decoder, mesh, attr, draco.DT_FLOAT32, Float32Array, 'an attribute as float32');
}

function readColors(draco: DracoDecoderModule, decoder: DracoDecoder, mesh: DracoPointCloud, attr: DracoAttribute): DecodedColors {
  const itemSize = attr.num_components();
  const type = attr.data_type();
  if (type === draco.DT_UINT8 || type === draco.DT_UINT16) {
    const array =
      type === draco.DT_UINT16
        ? readAttribute(draco, decoder, mesh, attr, type, Uint16Array, 'the colours')
        : readAttribute(draco, decoder, mesh, attr, type, Uint8Array, 'the colours');
    return { array, itemSize, normalized: true };
  }
  return { array: readFloat32(draco, decoder, mesh, attr), itemSize, normalized: false };
}

/**
 * The faces sorted by material (a counting sort, stable within a material)
 * and their runs, from the per-point material ids: a face's material is its
 * first corner's (the server splits vertices at material boundaries).
 */
function groupByMaterial(
  draco: DracoDecoderModule,
  decoder: DracoDecoder,
  mesh: DracoPointCloud,
  attr: DracoAttribute,
  indices: Uint32Array,
): { indices: Uint32Array; groups: MaterialGroup[]; faceSource: Uint32Array } {
  const ids = readAttribute(draco, decoder, mesh, attr, draco.DT_UINT32, Uint32Array, 'the material ids');
  const faces = indices.length / 3;
  let materials = 0;
  for (let f = 0; f < faces; ++f) materials = Math.max(materials, ids[indices[3 * f]] + 1);
  const next = new Uint32Array(materials + 1);
  for (let f = 0; f < faces; ++f) ++next[ids[indices[3 * f]] + 1];
  for (let m = 0; m < materials; ++m) next[m + 1] += next[m];
  const groups: MaterialGroup[] = [];
  for (let m = 0; m < materials; ++m) {
    if (next[m + 1] > next[m]) groups.push({ start: 3 * next[m], count: 3 * (next[m + 1] - next[m]), material: m });
  }
  const sorted = new Uint32Array(indices.length);
  const faceSource = new Uint32Array(faces);
  for (let f = 0; f < faces; ++f) {
    const k = next[ids[indices[3 * f]]]++;
    faceSource[k] = f;
    sorted[3 * k] = indices[3 * f];
    sorted[3 * k + 1] = indices[3 * f + 1];
    sorted[3 * k + 2] = indices[3 * f + 2];
  }
  return { indices: sorted, groups, faceSource };
}

/**
 * Decodes a Draco bitstream: a triangle mesh, or a point cloud (no faces:
 * `points` true, `indices` empty). Throws with what is wrong with it.
 */
export function decodeDraco(draco: DracoDecoderModule, payload: ArrayBuffer): Omit<DecodedMesh, 'timing'> {
  const data = new Int8Array(payload);
  const decoder = new draco.Decoder();
  const type = decoder.GetEncodedGeometryType(data);
  const points = type === draco.POINT_CLOUD;
  if (!points && type !== draco.TRIANGULAR_MESH) {
    draco.destroy(decoder);
    throw new Error('Draco: the payload is neither a triangle mesh nor a point cloud');
  }
  const mesh = points ? new draco.PointCloud() : new draco.Mesh();
  try {
    const status = points ? decoder.DecodeArrayToPointCloud(data, data.byteLength, mesh) : decoder.DecodeArrayToMesh(data, data.byteLength, mesh as DracoMesh);
    if (!status.ok() || mesh.ptr === 0) throw new Error(`Draco: ${status.error_msg()}`);

    const positionId = decoder.GetAttributeId(mesh, draco.POSITION);
    if (positionId < 0) throw new Error(`Draco: the ${points ? 'point cloud' : 'mesh'} has no positions`);
    const positionAttr = decoder.GetAttribute(mesh, positionId);
    if (positionAttr.num_components() !== 3) throw new Error('Draco: positions are not 3D');
    const positions = readFloat32(draco, decoder, mesh, positionAttr);

    const faces = points ? 0 : (mesh as DracoMesh).num_faces();
    let indices: Uint32Array = new Uint32Array(0);
    if (!points) {
      const indexBytes = faces * 3 * 4;
      const ptr = draco._malloc(indexBytes);
      try {
        decoder.GetTrianglesUInt32Array(mesh as DracoMesh, indexBytes, ptr);
        indices = new Uint32Array(draco.HEAPF32.buffer, ptr, faces * 3).slice();
      } finally {
        draco._free(ptr);
      }
    }

    let normals: Float32Array | null = null;
    const normalId = decoder.GetAttributeId(mesh, draco.NORMAL);
    if (normalId >= 0) {
      const attr = decoder.GetAttribute(mesh, normalId);
      if (attr.num_components() === 3) normals = readFloat32(draco, decoder, mesh, attr);
    }
    let colors: DecodedColors | null = null;
    const colorId = decoder.GetAttributeId(mesh, draco.COLOR);
    if (colorId >= 0) {
      const attr = decoder.GetAttribute(mesh, colorId);
      if (attr.num_components() === 3 || attr.num_components() === 4) colors = readColors(draco, decoder, mesh, attr);
    }
    let uvs: Float32Array | null = null;
    const uvId = decoder.GetAttributeId(mesh, draco.TEX_COORD);
    if (uvId >= 0) {
      const attr = decoder.GetAttribute(mesh, uvId);
      if (attr.num_components() === 2) uvs = readFloat32(draco, decoder, mesh, attr);
    }
    let groups: MaterialGroup[] | null = null;
    let faceSource: Uint32Array | null = null;
    const materialId = points ? -1 : decoder.GetAttributeIdByName(mesh, 'material');
    if (materialId >= 0) {
      const attr = decoder.GetAttribute(mesh, materialId);
      if (attr.num_components() === 1) ({ indices, groups, faceSource } = groupByMaterial(draco, decoder, mesh, attr, indices));
    }
    return { positions, indices, normals, colors, uvs, groups, faceSource, vertices: mesh.num_points(), faces, points };
  } finally {
    draco.destroy(mesh);
    draco.destroy(decoder);
  }
}
