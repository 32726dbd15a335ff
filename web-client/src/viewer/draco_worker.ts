// A Web Worker that decodes Draco bitstreams with draco3d's WASM decoder, so
// that decoding a large mesh never blocks the page. In: {id, payload}; out:
// {id, ok, mesh | error}, the mesh's arrays transferred back. What a stream
// decodes to is draco_geometry.ts's (node's unit tests run it too).
import createDecoderModule from 'draco3d/draco_decoder_nodejs.js';
import type { DracoDecoderModule } from 'draco3d/draco_decoder_nodejs.js';
import wasmUrl from 'draco3d/draco_decoder.wasm?url';
import type { DecodeRequest, DecodeResponse, DecodedMesh } from './decoded_mesh.ts';
import { decodeDraco } from './draco_geometry.ts';

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

scope.onmessage = (ev) => {
  const { id, payload } = ev.data;
  const received = performance.now();
  loadModule()
    .then((draco) => {
      const start = performance.now();
      const decoded = decodeDraco(draco, payload);
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
