// The WebSocket half of protocol/API.md (`/api/v1/ws`): JSON requests with a
// client-chosen request_id, get_mesh answered by mesh_begin, K binary chunk
// frames and mesh_end, and the server's events: mesh_added / mesh_deleted and
// job_progress / job_done / job_failed / job_cancelled, and others a module
// asks for by type (a live lecture's: api/rooms.ts). Messages the server
// answers only when it refuses them (a lecture's changes) are told.
// Reconnects by itself; requests in flight when the connection drops fail.
import { ChunkAssembler, FrameError, FrameKind, decodeFrame } from './frames.ts';
import { receiveTransferFrame, receiveTransferText, type GetMeshOptions, type MeshTransfer, type Pending, type SliceBegin } from './transfers.ts';
import { getToken, reportUnauthorized } from './auth.ts';
import { SERVER_EVENT_TYPES, type Mesh, type ServerEvent } from './types.ts';
import { decodeAnimationPayload } from './animation_payload.ts';
import { decodeSlicePayload, type Axis, type VoxelSlice } from './voxel_slice.ts';

export type { GetMeshOptions, MeshTransfer, SliceBegin } from './transfers.ts';

/** An `{"type":"error"}` answer: the server's code and detail. */
export class ServerError extends Error {
  readonly code: string;
  readonly detail: string;

  constructor(code: string, detail: string) {
    super(detail ? `${detail} (${code})` : code);
    this.name = 'ServerError';
    this.code = code;
    this.detail = detail;
  }
}

type EventHandler = (event: ServerEvent) => void;
type MessageHandler = (message: Record<string, unknown>) => void;
/** How many told messages are remembered for the refusal that may follow (the newest). */
const TOLD_KEPT = 512;
type StatusHandler = (connected: boolean) => void;

export function defaultSocketUrl(): string {
  const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:';
  return `${scheme}//${location.host}/api/v1/ws`;
}

export class CgviewSocket {
  private readonly url: string;
  private socket: WebSocket | null = null;
  private opened: Promise<void> | null = null;
  private nextId = 1;
  private readonly pending = new Map<number, Pending>();
  private readonly eventHandlers = new Set<EventHandler>();
  private readonly statusHandlers = new Set<StatusHandler>();
  /** Handlers of other events (no request_id), by the types they take. */
  private readonly messageHandlers = new Set<{ types: ReadonlySet<string>; handler: MessageHandler }>();
  /** Told messages by request id: who hears their refusal. */
  private readonly told = new Map<number, (error: ServerError) => void>();
  private retryMs = 500;
  private closedByUser = false;

  constructor(url: string = defaultSocketUrl()) {
    this.url = url;
  }

  /** Server events (mesh_* and job_*). Returns a function that unsubscribes. */
  onEvent(handler: EventHandler): () => void {
    this.eventHandlers.add(handler);
    return () => this.eventHandlers.delete(handler);
  }

  /** Events of other `types` than mesh_* and job_* (a lecture's). Returns a function that unsubscribes. */
  onMessages(types: ReadonlySet<string>, handler: MessageHandler): () => void {
    const entry = { types, handler };
    this.messageHandlers.add(entry);
    return () => this.messageHandlers.delete(entry);
  }

  /** Connection state changes (true on every (re)connect). */
  onStatus(handler: StatusHandler): () => void {
    this.statusHandlers.add(handler);
    return () => this.statusHandlers.delete(handler);
  }

  get connected(): boolean {
    return this.socket !== null && this.socket.readyState === WebSocket.OPEN;
  }

  /** Opens the connection (once); resolves when it is open. */
  connect(): Promise<void> {
    if (this.opened) return this.opened;
    this.closedByUser = false;
    this.opened = new Promise<void>((resolve, reject) => {
      const ws = new WebSocket(this.url);
      ws.binaryType = 'arraybuffer';
      this.socket = ws;
      let didOpen = false;
      ws.onopen = () => {
        // Where the server needs a token, it must be the first message.
        const token = getToken();
        if (token) ws.send(JSON.stringify({ type: 'auth', request_id: 0, token }));
        didOpen = true;
        this.retryMs = 500;
        resolve();
        for (const h of this.statusHandlers) h(true);
      };
      ws.onmessage = (ev: MessageEvent) => this.receive(ev.data);
      ws.onerror = () => {
        // onclose follows and does the work.
      };
      ws.onclose = () => {
        this.socket = null;
        this.opened = null;
        reject(new Error(`cannot connect to ${this.url}`));
        this.failAll(new Error('the connection to the server was closed'));
        if (didOpen) for (const h of this.statusHandlers) h(false);
        if (!this.closedByUser) {
          const delay = this.retryMs;
          this.retryMs = Math.min(this.retryMs * 2, 5000);
          setTimeout(() => {
            if (!this.closedByUser && !this.opened) this.connect().catch(() => {});
          }, delay);
        }
      };
    });
    return this.opened;
  }

  close(): void {
    this.closedByUser = true;
    this.socket?.close();
  }

  listMeshes(): Promise<Mesh[]> {
    return this.call({ type: 'list_meshes' }, 'meshes').then((m) => m.meshes as Mesh[]);
  }

  ping(): Promise<void> {
    return this.call({ type: 'ping' }, 'pong').then(() => undefined);
  }

  /** A request answered by a message of type `expect` (or an error, which rejects with a ServerError). */
  request(body: Record<string, unknown>, expect: string): Promise<Record<string, unknown>> {
    return this.call(body, expect);
  }

  /**
   * Sends a message the server answers only when it refuses it: `onError`
   * hears the refusal. Not connected, it is dropped (the caller is told so).
   */
  tell(body: Record<string, unknown>, onError: (error: ServerError) => void): void {
    if (!this.connected) return onError(new ServerError('not_connected', 'not connected to the server'));
    const id = this.takeId();
    this.told.set(id, onError);
    if (this.told.size > TOLD_KEPT) this.told.delete(this.told.keys().next().value!);
    this.socket!.send(JSON.stringify({ ...body, request_id: id }));
  }

  /** Streams a mesh as Draco: resolves with mesh_begin's fields and the joined payload. */
  async getMesh(meshId: string, options: GetMeshOptions = {}): Promise<MeshTransfer> {
    await this.connect();
    const id = this.takeId();
    const request: Record<string, unknown> = { type: 'get_mesh', request_id: id, mesh_id: meshId };
    if (options.quantization !== undefined) request.quantization = options.quantization;
    if (options.onPreview) request.lod = 'progressive';
    return new Promise<MeshTransfer>((resolve, reject) => {
      const signal = options.signal;
      if (signal?.aborted) {
        reject(new DOMException('aborted', 'AbortError'));
        return;
      }
      signal?.addEventListener(
        'abort',
        () => {
          if (this.pending.delete(id)) reject(new DOMException('aborted', 'AbortError'));
        },
        { once: true },
      );
      this.pending.set(id, { kind: 'mesh', begin: null, assembler: new ChunkAssembler(id), options, resolve, reject });
      this.send(request);
      if (this.pending.has(id)) options.onSent?.();
    });
  }

  /** A 2D slice of a done job's voxel grid artifact (get_slice). */
  getSlice(jobId: string, artifact: string, axis: Axis, index: number): Promise<{ begin: SliceBegin; slice: VoxelSlice }> {
    return this.getPayload({ type: 'get_slice', job_id: jobId, artifact, axis, index }, 'slice', 'slice_end', FrameKind.VoxelSlice, async (begin, payload) => ({
      begin: begin as unknown as SliceBegin,
      slice: await decodeSlicePayload(payload),
    }));
  }

  /** A done job's animation artifact (get_animation): the .frames bytes, sent as zlib-compressed quantized deltas. */
  getAnimation(jobId: string, artifact: string): Promise<ArrayBuffer> {
    return this.getPayload({ type: 'get_animation', job_id: jobId, artifact }, 'animation_begin', 'animation_end', FrameKind.Animation, (begin, payload) =>
      decodeAnimationPayload(payload, Number(begin.raw_bytes)),
    );
  }

  private async getPayload<T>(
    request: Record<string, unknown>,
    beginType: string,
    endType: string,
    frameKind: number,
    decode: (begin: Record<string, unknown>, payload: Uint8Array) => Promise<T>,
  ): Promise<T> {
    await this.connect();
    const id = this.takeId();
    return new Promise<T>((resolve, reject) => {
      const finish = async (begin: Record<string, unknown>, payload: Uint8Array) => resolve(await decode(begin, payload));
      this.pending.set(id, { kind: 'payload', beginType, endType, frameKind, begin: null, assembler: new ChunkAssembler(id), finish, reject });
      this.send({ ...request, request_id: id });
    });
  }

  private takeId(): number {
    const id = this.nextId;
    this.nextId = this.nextId >= 0xffffffff ? 1 : this.nextId + 1;
    return id;
  }

  private async call(body: Record<string, unknown>, expect: string): Promise<Record<string, unknown>> {
    await this.connect();
    const id = this.takeId();
    return new Promise((resolve, reject) => {
      this.pending.set(id, { kind: 'reply', expect, resolve, reject });
      this.send({ ...body, request_id: id });
    });
  }

  private send(message: Record<string, unknown>): void {
    if (!this.socket || this.socket.readyState !== WebSocket.OPEN) {
      const id = message.request_id as number;
      const p = this.pending.get(id);
      this.pending.delete(id);
      p?.reject(new Error('not connected to the server'));
      return;
    }
    this.socket.send(JSON.stringify(message));
  }

  private failAll(error: Error): void {
    const all = [...this.pending.values()];
    this.pending.clear();
    for (const p of all) p.reject(error);
  }

  private fail(id: number, error: Error): void {
    const p = this.pending.get(id);
    if (!p) return;
    this.pending.delete(id);
    p.reject(error);
  }

  private receive(data: unknown): void {
    if (data instanceof ArrayBuffer) {
      this.receiveBinary(data);
      return;
    }
    let msg: Record<string, unknown>;
    try {
      msg = JSON.parse(String(data)) as Record<string, unknown>;
    } catch {
      console.warn('cgview: a text frame that is not JSON', data);
      return;
    }
    const type = msg.type;
    const id = typeof msg.request_id === 'number' ? msg.request_id : null;

    if (typeof type === 'string' && SERVER_EVENT_TYPES.has(type) && id === null) {
      for (const h of this.eventHandlers) h(msg as unknown as ServerEvent);
      return;
    }
    if (typeof type === 'string' && id === null) {
      for (const h of this.messageHandlers) if (h.types.has(type)) h.handler(msg);
    }
    if (type === 'error' && msg.error === 'unauthorized') reportUnauthorized();
    if (type === 'error' && id !== null && this.told.has(id)) {
      const onError = this.told.get(id)!;
      this.told.delete(id);
      onError(new ServerError(String(msg.error ?? 'error'), String(msg.detail ?? '')));
      return;
    }
    if (id === null) {
      if (type === 'error') console.warn('cgview: server error without a request', msg);
      return;
    }
    const p = this.pending.get(id);
    if (!p) return; // aborted or unknown: drop

    if (type === 'error') {
      this.fail(id, new ServerError(String(msg.error ?? 'error'), String(msg.detail ?? '')));
      return;
    }
    if (p.kind === 'reply') {
      if (type === p.expect) {
        this.pending.delete(id);
        p.resolve(msg);
      }
      return;
    }
    receiveTransferText(p, type, msg, { id, forget: () => this.pending.delete(id), fail: (e) => this.fail(id, e) });
  }

  private receiveBinary(data: ArrayBuffer): void {
    let frame;
    try {
      frame = decodeFrame(data);
    } catch (e) {
      // Without a readable header we cannot tell whose chunk this is.
      console.warn('cgview: unreadable binary frame', e);
      return;
    }
    const id = frame.header.request_id;
    const p = this.pending.get(id);
    if (!p) return; // aborted request: drop its chunks
    if (p.kind === 'reply') {
      this.fail(id, new FrameError(`binary frame for request ${id}, which expects "${p.expect}"`));
      return;
    }
    try {
      receiveTransferFrame(p, frame);
    } catch (e) {
      this.fail(id, e as Error);
    }
  }
}
