// Brings a stored mesh into the viewer: streamed over the WebSocket (a big
// mesh's decimated preview first), decoded in the worker, drawn, timed; and
// the mesh in the server's vertex and face order, which fields and
// selections are in: made from the streamed mesh and its stored order
// (viewer/stored_order.ts), or, for a mesh not streamed here, its binary PLY.
// A point cloud (a mesh with no faces, streamed as a Draco point cloud) is
// drawn as points (viewer/points_renderer.ts) in the Display panel's size.
import type * as THREE from 'three';
import { fetchMeshBytes, fetchStoredOrder } from '../api/rest.ts';
import type { Mesh } from '../api/types.ts';
import type { MeshTransfer } from '../api/ws.ts';
import { readCamera } from '../viewer/camera_state.ts';
import type { DracoDecoder } from '../viewer/draco_decoder.ts';
import { parsePly, type PlyMesh } from '../viewer/ply.ts';
import { buildPoints } from '../viewer/points_renderer.ts';
import { storedMesh, unpackStoredOrder } from '../viewer/stored_order.ts';
import { buildSurface } from '../viewer/surface_renderer.ts';
import { LoadTimer } from '../viewer/timings.ts';
import { describe, isAbort, type AppContext } from './context.ts';

export type DecodedMesh = Awaited<ReturnType<DracoDecoder['decode']>>;

export class MeshLoader {
  private readonly ctx: AppContext;
  private readonly decoder: DracoDecoder;
  private load: { id: string; controller: AbortController } | null = null;
  private readonly plyCache = new Map<string, Promise<PlyMesh>>();
  /** The last meshes streamed in full, by id: what their stored order is made from. */
  private readonly streamed = new Map<string, DecodedMesh>();
  /** The latest show(): what is drawn on the mesh waits for it. */
  showing: Promise<void> = Promise.resolve();

  constructor(ctx: AppContext, decoder: DracoDecoder) {
    this.ctx = ctx;
    this.decoder = decoder;
  }

  /** The mesh in the server's vertex and face order (made once): from the streamed mesh where it was streamed here. */
  ply(meshId: string): Promise<PlyMesh> {
    let p = this.plyCache.get(meshId);
    if (!p) {
      p = (async () => {
        if (this.load?.id === meshId) await this.showing; // being streamed: wait for it
        const decoded = this.streamed.get(meshId);
        if (decoded) {
          try {
            const order = await unpackStoredOrder(await fetchStoredOrder(meshId));
            const vertices = this.ctx.store.get().meshes.find((m) => m.id === meshId)?.report.vertices ?? 0;
            return storedMesh(decoded, order, vertices);
          } catch (e) {
            // The server could not map its stream (API.md, stored_order): the mesh once more, as stored.
            console.warn(`cgview: no stored order for ${meshId} (${describe(e)}): fetching it as PLY`);
          }
        }
        return parsePly(await fetchMeshBytes(meshId, 'ply'));
      })();
      p.catch(() => this.plyCache.delete(meshId));
      this.plyCache.set(meshId, p);
    }
    return p;
  }

  forgetPly(meshId: string): void {
    this.plyCache.delete(meshId);
  }

  /** Stops the load of that mesh, if it is in progress. */
  abort(meshId: string): void {
    if (this.load?.id !== meshId) return;
    this.load.controller.abort();
    this.load = null;
    this.ctx.progress.hide();
  }

  /** Decodes a Draco stream in the worker (a job's points, fetched as drc). */
  decode(payload: Uint8Array): Promise<DecodedMesh> {
    return this.decoder.decode(payload);
  }

  /** What shows a decoded stream: its surface, or its points for a point cloud. */
  private build(decoded: DecodedMesh): THREE.Object3D {
    return decoded.points ? buildPoints(decoded, this.ctx.store.get().display.settings) : buildSurface(decoded);
  }

  /** Shows the mesh in place of what is shown; `showing` settles once it is drawn (or has failed). */
  show(mesh: Mesh): void {
    this.showing = this.showMesh(mesh);
  }

  /** Downloads the mesh over the WebSocket, decodes it in the worker and shows it. */
  private async showMesh(mesh: Mesh): Promise<void> {
    const { hooks, viewer, progress } = this.ctx;
    this.load?.controller.abort();
    const load = { id: mesh.id, controller: new AbortController() };
    this.load = load;
    const current = () => this.load === load;
    const timer = new LoadTimer(); // of the full mesh
    // A big mesh's preview (API.md "Big meshes") is shown while the full mesh
    // streams and decodes, then replaced without moving the camera.
    // The preview and the full mesh decode in that order in the one worker, so
    // the preview is in the viewer before the full mesh is decoded; the swap
    // waits for the preview's first frame (settled at the next frame), so the
    // preview is always drawn once, however fast the full mesh comes.
    let preview: THREE.Object3D | null = null;
    let previewDrawn: Promise<void> = Promise.resolve();
    let fullDecoded = false;
    const stage = (what: string) => (preview ? `preview shown, ${what} full mesh` : what);
    const showPreview = async (transfer: MeshTransfer) => {
      const decoded = await this.decoder.decode(transfer.payload);
      if (!current() || fullDecoded) return;
      const object = this.build(decoded);
      preview = object;
      previewDrawn = new Promise<void>((drawn) =>
        viewer.show(object, () => {
          drawn();
          if (viewer.object !== object) return;
          hooks.lastPreview = { id: mesh.id, vertices: decoded.vertices, faces: decoded.faces, camera: readCamera(viewer), fullCamera: null };
        }),
      );
      progress.show(stage('downloading'), null, mesh.name);
    };
    try {
      hooks.lastPreview = null;
      const loaded = await this.downloadMesh(mesh, load.controller.signal, current, timer, {
        stage,
        onPreview: (t) => {
          showPreview(t).catch((e) => console.warn('cgview: the preview could not be shown', e));
        },
      });
      if (!loaded) return;
      fullDecoded = true;
      const { decoded, bytes } = loaded;
      const object = this.build(decoded);
      timer.mark('geometry-built');
      if (decoded.points)
        this.ctx.textures.detach(); // a cloud has no texture: the last mesh's panel goes
      else this.ctx.textures.attach(object as THREE.Mesh, mesh);
      await previewDrawn;
      if (!current()) return;
      const swap = preview !== null && viewer.object === preview;
      const onShown = () => {
        if (viewer.object !== object) return;
        timer.mark('first-frame');
        hooks.timings = null;
        hooks.lastLoaded = { id: mesh.id, vertices: decoded.vertices, faces: decoded.faces, bytes, points: decoded.points };
        if (swap && hooks.lastPreview?.id === mesh.id) hooks.lastPreview.fullCamera = readCamera(viewer);
        void timer.markGpuDone(viewer.renderer.getContext()).then(() => {
          if (viewer.object === object) hooks.timings = timer.finish();
        });
      };
      if (swap) viewer.replace(object, onShown);
      else viewer.show(object, onShown);
      progress.hide();
    } catch (e) {
      if (isAbort(e) || !current()) return;
      progress.hide();
      this.ctx.error(`Cannot show ${mesh.name}: ${describe(e)}`);
    } finally {
      if (current()) this.load = null;
    }
  }

  /**
   * Downloads a mesh over the WebSocket (with the progress bar while
   * `current()`) and decodes it in the worker; null when no longer current.
   * With `preview`, a big mesh's decimated preview is asked for first and
   * handed to `preview.onPreview`; `preview.stage` words the full mesh's
   * stages (once the preview is shown). `timer` times the full mesh only.
   */
  async downloadMesh(
    mesh: Mesh,
    signal: AbortSignal,
    current: () => boolean,
    timer: LoadTimer,
    preview?: { onPreview: (transfer: MeshTransfer) => void; stage: (what: string) => string },
  ): Promise<{ decoded: DecodedMesh; bytes: number } | null> {
    const { progress } = this.ctx;
    const stage = preview?.stage ?? ((what: string) => what);
    let inPreview = false;
    progress.show('downloading', 0, mesh.name);
    const transfer = await this.ctx.socket.getMesh(mesh.id, {
      signal,
      onSent: () => timer.mark('request'),
      onBegin: (begin) => {
        inPreview = begin.level === 'preview';
        if (!inPreview) timer.mark('first-byte');
      },
      onProgress: (received, total) => {
        if (!inPreview) {
          if (received > 0) timer.mark('first-chunk');
          if (received >= total) timer.mark('last-chunk');
        }
        if (current()) progress.show(inPreview ? 'downloading preview of' : stage('downloading'), total > 0 ? received / total : 0, mesh.name);
      },
      ...(preview && {
        onPreview: (t: MeshTransfer) => {
          inPreview = false;
          preview.onPreview(t);
        },
      }),
    });
    if (!current()) return null;
    progress.show(stage('decoding'), null, mesh.name);
    const bytes = transfer.payload.byteLength; // before the worker takes the buffer
    timer.mark('decode-start');
    const decoded = await this.decoder.decode(transfer.payload);
    if (!current()) return null;
    timer.mark('decode-end');
    timer.setWorkerTiming(decoded.timing);
    this.streamed.delete(mesh.id);
    this.streamed.set(mesh.id, decoded);
    while (this.streamed.size > 2) this.streamed.delete(this.streamed.keys().next().value as string);
    return { decoded, bytes };
  }
}
