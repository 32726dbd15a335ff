// The one place that owns the view state: the list of meshes, the chosen
// mesh, the load in progress and what the viewer shows. Panels render from
// it and call its actions; nothing else changes it.
import { ApiError, deleteMesh, listMeshes, uploadMesh } from './api/rest.ts';
import type { Mesh } from './api/types.ts';
import { CgviewSocket, ServerError } from './api/ws.ts';
import { MeshListPanel } from './panels/mesh_list.ts';
import { MessagesPanel } from './panels/messages.ts';
import { ProgressPanel } from './panels/progress.ts';
import { ReportPanel } from './panels/report.ts';
import { UploadControl } from './panels/upload.ts';
import { byId } from './panels/dom.ts';
import { DracoDecoder } from './viewer/draco_decoder.ts';
import { buildSurface } from './viewer/surface_renderer.ts';
import { LoadTimer, type LoadTimings } from './viewer/timings.ts';
import { Viewer } from './viewer/viewer.ts';

/** What tests read (window.__cgview). */
export interface TestHooks {
  /** True once the page is set up and the first mesh list has been asked for. */
  ready: boolean;
  /**
   * The mesh in the viewer, set after the first frame showing it has rendered;
   * bytes: the Draco payload received for it.
   */
  lastLoaded: { id: string; vertices: number; faces: number; bytes: number } | null;
  /**
   * The durations of the load of lastLoaded (see viewer/timings.ts): null
   * when lastLoaded changes, set once the GPU has finished its first frame.
   */
  timings: LoadTimings | null;
  /** Frames rendered so far. */
  frames: number;
  /** The last error message shown in the page, or null. */
  lastError: string | null;
}

declare global {
  interface Window {
    __cgview: TestHooks;
  }
}

function describe(e: unknown): string {
  if (e instanceof ApiError || e instanceof ServerError) return e.detail || e.message;
  if (e instanceof Error) return e.message;
  return String(e);
}

function isAbort(e: unknown): boolean {
  return e instanceof DOMException && e.name === 'AbortError';
}

export class App {
  private meshes: Mesh[] = [];
  private selectedId: string | null = null;
  private load: { id: string; controller: AbortController } | null = null;

  private readonly hooks: TestHooks = { ready: false, lastLoaded: null, timings: null, frames: 0, lastError: null };
  private readonly socket = new CgviewSocket();
  private readonly decoder = new DracoDecoder();
  private readonly viewer: Viewer;
  private readonly list: MeshListPanel;
  private readonly report: ReportPanel;
  private readonly progress: ProgressPanel;
  private readonly messages: MessagesPanel;
  private readonly status: HTMLElement;

  constructor() {
    window.__cgview = this.hooks;
    this.viewer = new Viewer(byId('viewport'), { onFrame: () => ++this.hooks.frames });
    this.list = new MeshListPanel(byId('mesh-list'), {
      select: (id) => this.select(id),
      remove: (id) => void this.remove(id),
    });
    this.report = new ReportPanel(byId('report'));
    this.progress = new ProgressPanel(byId('progress'));
    this.messages = new MessagesPanel(byId('messages'));
    this.status = byId('connection');
    new UploadControl(byId<HTMLInputElement>('file-input'), document.body, (files) => void this.upload(files));
    byId('fit').addEventListener('click', () => this.viewer.fitToView());
  }

  async start(): Promise<void> {
    this.report.render(null);
    this.socket.onEvent((ev) => {
      if (ev.type === 'mesh_added') this.upsert(ev.mesh);
      else this.forget(ev.mesh_id);
    });
    let connectedBefore = false;
    this.socket.onStatus((connected) => {
      this.status.dataset.state = connected ? 'connected' : 'disconnected';
      this.status.title = connected ? 'Connected to the server' : 'Not connected; retrying';
      // Events may have been missed while disconnected.
      if (connected && connectedBefore) void this.refresh();
      if (connected) connectedBefore = true;
    });
    this.socket.connect().catch(() => this.error('Cannot open the WebSocket to the server; retrying.'));
    await this.refresh();
    this.hooks.ready = true;
  }

  /** Reloads the mesh list from the server. */
  async refresh(): Promise<void> {
    try {
      this.meshes = await listMeshes();
      if (this.selectedId && !this.meshes.some((m) => m.id === this.selectedId)) this.forget(this.selectedId);
      this.renderList();
    } catch (e) {
      this.renderList();
      this.error(`Cannot list meshes: ${describe(e)}`);
    }
  }

  /** Uploads files one after the other and shows the last one uploaded. */
  async upload(files: File[]): Promise<void> {
    let last: Mesh | null = null;
    for (const file of files) {
      this.progress.show('uploading', null, file.name);
      try {
        const mesh = await uploadMesh(file.name, file);
        this.upsert(mesh);
        for (const w of mesh.warnings ?? []) this.messages.notice(`${mesh.name}: ${w}`);
        last = mesh;
      } catch (e) {
        this.error(`Upload of ${file.name} failed: ${describe(e)}`);
      } finally {
        this.progress.hide();
      }
    }
    if (last) this.select(last.id);
  }

  select(id: string): void {
    const mesh = this.meshes.find((m) => m.id === id);
    if (!mesh) return;
    this.selectedId = id;
    this.renderList();
    this.report.render(mesh);
    void this.show(mesh);
  }

  async remove(id: string): Promise<void> {
    const mesh = this.meshes.find((m) => m.id === id);
    try {
      await deleteMesh(id);
      this.forget(id);
    } catch (e) {
      this.error(`Cannot delete ${mesh?.name ?? id}: ${describe(e)}`);
    }
  }

  /** Downloads the mesh over the WebSocket, decodes it in the worker and shows it. */
  private async show(mesh: Mesh): Promise<void> {
    this.load?.controller.abort();
    const load = { id: mesh.id, controller: new AbortController() };
    this.load = load;
    const current = () => this.load === load;
    const timer = new LoadTimer();
    try {
      this.progress.show('downloading', 0, mesh.name);
      const transfer = await this.socket.getMesh(mesh.id, {
        signal: load.controller.signal,
        onSent: () => timer.mark('request'),
        onBegin: () => timer.mark('first-byte'),
        onProgress: (received, total) => {
          if (received > 0) timer.mark('first-chunk');
          if (received >= total) timer.mark('last-chunk');
          if (current()) this.progress.show('downloading', total > 0 ? received / total : 0, mesh.name);
        },
      });
      if (!current()) return;
      this.progress.show('decoding', null, mesh.name);
      const bytes = transfer.payload.byteLength; // before the worker takes the buffer
      timer.mark('decode-start');
      const decoded = await this.decoder.decode(transfer.payload);
      if (!current()) return;
      timer.mark('decode-end');
      timer.setWorkerTiming(decoded.timing);
      const object = buildSurface(decoded);
      timer.mark('geometry-built');
      this.viewer.show(object, () => {
        if (this.viewer.object !== object) return;
        timer.mark('first-frame');
        this.hooks.timings = null;
        this.hooks.lastLoaded = { id: mesh.id, vertices: decoded.vertices, faces: decoded.faces, bytes };
        void timer.markGpuDone(this.viewer.renderer.getContext()).then(() => {
          if (this.viewer.object === object) this.hooks.timings = timer.finish();
        });
      });
      this.progress.hide();
    } catch (e) {
      if (isAbort(e) || !current()) return;
      this.progress.hide();
      this.error(`Cannot show ${mesh.name}: ${describe(e)}`);
    } finally {
      if (current()) this.load = null;
    }
  }

  private upsert(mesh: Mesh): void {
    const i = this.meshes.findIndex((m) => m.id === mesh.id);
    if (i >= 0) this.meshes[i] = mesh;
    else this.meshes.push(mesh);
    this.renderList();
    if (mesh.id === this.selectedId) this.report.render(mesh);
  }

  /** Drops a mesh that no longer exists on the server; clears the view if it was shown. */
  private forget(id: string): void {
    this.meshes = this.meshes.filter((m) => m.id !== id);
    if (this.selectedId === id) {
      this.selectedId = null;
      if (this.load?.id === id) {
        this.load.controller.abort();
        this.load = null;
        this.progress.hide();
      }
      this.viewer.clear();
      this.hooks.lastLoaded = null;
      this.hooks.timings = null;
      this.report.render(null);
    }
    this.renderList();
  }

  private renderList(): void {
    this.list.render(this.meshes, this.selectedId);
  }

  private error(text: string): void {
    this.hooks.lastError = text;
    this.messages.error(text);
  }
}
