// A Web Worker that decodes Draco bitstreams with draco3d's WASM decoder, so
// that decoding a large mesh never blocks the page. In: {id, payload}; out:
// {id, ok, mesh | error}, the mesh's arrays transferred back.
import createDecoderModule from 'draco3d/draco_decoder_nodejs.js';
import type { DracoAttribute, DracoDecoder, DracoDecoderModule, DracoMesh } from 'draco3d/draco_decoder_nodejs.js';
import wasmUrl from 'draco3d/draco_decoder.wasm?url';
import type { DecodeRequest, DecodeResponse, DecodedColors, DecodedMesh, MaterialGroup } from './decoded_mesh.ts';

interface WorkerScope {
  onmessage: ((ev: MessageEvent<DecodeRequest>) => void) | null;
  postMessage(message: DecodeResponse, transfer: Transferable[]): void;
}
const scope = self as unknown as WorkerScope;

let modulePromise: Promise<DracoDecoderModule> | null = null;

function loadModule(): Promise<DracoDecoderModule> {
  if (!modulePromise) {
    modulePromise = fetch(wasmUrl)
      .then((r) => {
        if (!r.ok) throw new Error(`cannot load the Draco decoder (${wasmUrl}: HTTP ${r.status})`);
        return r.arrayBuffer();
      })
      .then(
        (wasmBinary) =>
          new Promise<DracoDecoderModule>((resolve) => {
            // The emscripten module is promise-like; resolve from the callback
            // with a wrapper-free value rather than chaining on it.
            void createDecoderModule({
              wasmBinary,
              locateFile: () => wasmUrl,
              onModuleLoaded: (m) => resolve(m),
            });
          }),
      );
    modulePromise.catch(() => {
      modulePromise = null; // let a later request try again
    });
  }
  return modulePromise;
}

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
  mesh: DracoMesh,
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

function readFloat32(draco: DracoDecoderModule, decoder: DracoDecoder, mesh: DracoMesh, attr: DracoAttribute): Float32Array {
  return readAttribute(draco, decoder, mesh, attr, draco.DT_FLOAT32, Float32Array, 'an attribute as float32');
}

function readColors(draco: DracoDecoderModule, decoder: DracoDecoder, mesh: DracoMesh, attr: DracoAttribute): DecodedColors {
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
  mesh: DracoMesh,
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

function decode(draco: DracoDecoderModule, payload: ArrayBuffer): Omit<DecodedMesh, 'timing'> {
  const data = new Int8Array(payload);
  const decoder = new draco.Decoder();
  const mesh = new draco.Mesh();
  try {
    if (decoder.GetEncodedGeometryType(data) !== draco.TRIANGULAR_MESH) {
      throw new Error('Draco: the payload is not a triangle mesh');
    }
    const status = decoder.DecodeArrayToMesh(data, data.byteLength, mesh);
    if (!status.ok() || mesh.ptr === 0) throw new Error(`Draco: ${status.error_msg()}`);

    const positionId = decoder.GetAttributeId(mesh, draco.POSITION);
    if (positionId < 0) throw new Error('Draco: the mesh has no positions');
    const positionAttr = decoder.GetAttribute(mesh, positionId);
    if (positionAttr.num_components() !== 3) throw new Error('Draco: positions are not 3D');
    const positions = readFloat32(draco, decoder, mesh, positionAttr);

    const faces = mesh.num_faces();
    const indexBytes = faces * 3 * 4;
    const ptr = draco._malloc(indexBytes);
    let indices: Uint32Array;
    try {
      decoder.GetTrianglesUInt32Array(mesh, indexBytes, ptr);
      indices = new Uint32Array(draco.HEAPF32.buffer, ptr, faces * 3).slice();
    } finally {
      draco._free(ptr);
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
    const materialId = decoder.GetAttributeIdByName(mesh, 'material');
    if (materialId >= 0) {
      const attr = decoder.GetAttribute(mesh, materialId);
      if (attr.num_components() === 1) ({ indices, groups, faceSource } = groupByMaterial(draco, decoder, mesh, attr, indices));
    }
    return { positions, indices, normals, colors, uvs, groups, faceSource, vertices: mesh.num_points(), faces };
  } finally {
    draco.destroy(mesh);
    draco.destroy(decoder);
  }
}

scope.onmessage = (ev) => {
  const { id, payload } = ev.data;
  const received = performance.now();
  loadModule()
    .then((draco) => {
      const start = performance.now();
      const decoded = decode(draco, payload);
      const end = performance.now();
      performance.clearMeasures('cgview:worker-decode'); // keep the latest only
      performance.measure('cgview:worker-decode', { start, end });
      const mesh: DecodedMesh = { ...decoded, timing: { initMs: start - received, decodeMs: end - start } };
      const transfer: Transferable[] = [mesh.positions.buffer, mesh.indices.buffer];
      if (mesh.normals) transfer.push(mesh.normals.buffer);
      if (mesh.colors) transfer.push(mesh.colors.array.buffer);
      if (mesh.uvs) transfer.push(mesh.uvs.buffer);
      if (mesh.faceSource) transfer.push(mesh.faceSource.buffer);
      scope.postMessage({ id, ok: true, mesh }, transfer);
    })
    .catch((e: unknown) => {
      scope.postMessage({ id, ok: false, error: e instanceof Error ? e.message : String(e) }, []);
    });
};
