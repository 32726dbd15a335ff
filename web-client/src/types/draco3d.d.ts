// The parts of draco3d's emscripten decoder module that the worker uses.
// draco3d ships no TypeScript declarations.
declare module 'draco3d/draco_decoder_nodejs.js' {
  export interface DracoStatus {
    ok(): boolean;
    error_msg(): string;
  }
  export interface DracoAttribute {
    num_components(): number;
    data_type(): number;
    normalized(): boolean;
  }
  /** A point cloud (a Draco POINT_CLOUD): points and their attributes, no faces. */
  export interface DracoPointCloud {
    ptr: number;
    num_points(): number;
  }
  export interface DracoMesh extends DracoPointCloud {
    num_faces(): number;
  }
  export interface DracoDecoder {
    GetEncodedGeometryType(array: Int8Array): number;
    DecodeArrayToMesh(array: Int8Array, byteLength: number, mesh: DracoMesh): DracoStatus;
    DecodeArrayToPointCloud(array: Int8Array, byteLength: number, cloud: DracoPointCloud): DracoStatus;
    GetAttributeId(mesh: DracoPointCloud, type: number): number;
    /** The attribute whose metadata entry "name" is `name`, or -1. */
    GetAttributeIdByName(mesh: DracoPointCloud, name: string): number;
    GetAttribute(mesh: DracoPointCloud, id: number): DracoAttribute;
    GetAttributeDataArrayForAllPoints(mesh: DracoPointCloud, attribute: DracoAttribute, dataType: number, byteLength: number, ptr: number): boolean;
    GetTrianglesUInt32Array(mesh: DracoMesh, byteLength: number, ptr: number): boolean;
  }
  export interface DracoDecoderModule {
    Decoder: new () => DracoDecoder;
    Mesh: new () => DracoMesh;
    PointCloud: new () => DracoPointCloud;
    destroy(object: unknown): void;
    _malloc(bytes: number): number;
    _free(ptr: number): void;
    HEAPF32: Float32Array;
    TRIANGULAR_MESH: number;
    POINT_CLOUD: number;
    POSITION: number;
    NORMAL: number;
    COLOR: number;
    TEX_COORD: number;
    DT_INT8: number;
    DT_UINT8: number;
    DT_INT16: number;
    DT_UINT16: number;
    DT_INT32: number;
    DT_UINT32: number;
    DT_FLOAT32: number;
  }
  export interface DracoDecoderModuleOptions {
    wasmBinary?: ArrayBuffer;
    locateFile?: (path: string, prefix: string) => string;
    onModuleLoaded?: (module: DracoDecoderModule) => void;
  }
  const createDecoderModule: (options?: DracoDecoderModuleOptions) => Promise<DracoDecoderModule>;
  export default createDecoderModule;
}
