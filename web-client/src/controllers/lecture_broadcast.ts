// The presenter's side of a live lecture: after a frame is drawn, the view
// as a view link holds it (controllers/view_links.ts), split into the
// lecture's parts (viewer/view_state.ts), with the selection and the voxel
// slice; each part that changed since it was last sent goes to the room, at
// most 30 times a second (the server passes the camera on as often, its
// latest value last). While the code panel is open its text goes too, a
// moment after the typing stops; closed, the part is null.
import type { RoomsApi } from '../api/rooms.ts';
import type { ServerError } from '../api/ws.ts';
import type { CodePanel } from '../panels/playground_toggle.ts';
import { viewParts } from '../viewer/view_state.ts';
import type { AppContext } from './context.ts';
import type { Kinds } from '../kinds/registry.ts';
import type { ViewLinks } from './view_links.ts';

/** What a presenter's view is read from: the view links' state, the voxel slice shown. */
export interface BroadcastDeps {
  links: Pick<ViewLinks, 'current'>;
  kinds: Pick<Kinds, 'voxels'>;
}

/** The least time between two sends of the parts: the server's camera interval. */
const SEND_MS = 33;
/** How long the code stays still before it is sent. */
const CODE_MS = 300;

export class LectureBroadcast {
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: BroadcastDeps;
  private readonly rooms: RoomsApi;
  private readonly onError: (e: ServerError) => void;
  private readonly code: CodePanel;
  /** The code panel's controller, once listened to. */
  private readonly listening = new Set<object>();
  private room: string | null = null;
  /** Each part as last sent, as JSON. */
  private readonly sent = new Map<string, string>();
  /** Every value sent in this room but the camera's and the code's, as JSON (what it named, for a replay). */
  private readonly everSent = new Set<string>();
  private timer = 0;
  private last = 0;
  private codeTimer = 0;

  constructor(ctx: AppContext, deps: BroadcastDeps, rooms: RoomsApi, code: CodePanel, onError: (e: ServerError) => void) {
    this.ctx = ctx;
    this.deps = deps;
    this.rooms = rooms;
    this.onError = onError;
    this.code = code;
    code.onShown((shown) => {
      if (!shown) return this.sendCode(null);
      void code.loaded()?.then((c) => {
        if (!c || !code.isShown()) return;
        if (!this.listening.has(c)) {
          this.listening.add(c);
          c.onText((text) => {
            if (code.isShown()) this.sendCode(text);
          });
        }
        this.sendCode(c.text);
      });
    });
  }

  /**
   * The meshes and jobs the parts sent named (as the server reads them:
   * members `mesh`, `meshes`, `job`, `jobs`): what a replay needs to read.
   */
  named(): { meshes: string[]; jobs: string[] } {
    const out = { meshes: new Set<string>(), jobs: new Set<string>() };
    const walk = (v: unknown, depth: number): void => {
      if (depth > 8 || typeof v !== 'object' || v === null) return;
      for (const [k, x] of Array.isArray(v) ? v.map((x) => ['', x] as const) : Object.entries(v)) {
        const set = k === 'mesh' || k === 'meshes' ? out.meshes : k === 'job' || k === 'jobs' ? out.jobs : null;
        for (const id of set ? (Array.isArray(x) ? x : [x]) : []) if (typeof id === 'string') set!.add(id);
        walk(x, depth + 1);
      }
    };
    for (const json of this.everSent) walk(JSON.parse(json), 0);
    return { meshes: [...out.meshes], jobs: [...out.jobs] };
  }

  /** Sends the whole view to `room` (null: stops). */
  start(room: string | null): void {
    this.room = room;
    this.sent.clear();
    if (room) this.everSent.clear();
    window.clearTimeout(this.timer);
    window.clearTimeout(this.codeTimer);
    this.timer = 0;
    if (!room) return;
    this.sync();
    const shown = this.code.isShown() ? this.code.loaded() : null;
    if (shown) void shown.then((c) => c && this.sendCode(c.text));
  }

  /** A frame was drawn: what changed goes out, at most every SEND_MS. */
  changed(): void {
    if (!this.room || this.timer) return;
    this.timer = window.setTimeout(
      () => {
        this.timer = 0;
        this.sync();
      },
      Math.max(0, this.last + SEND_MS - performance.now()),
    );
  }

  private sync(): void {
    this.last = performance.now();
    const { selectionTool } = this.ctx;
    const { deps } = this;
    const view = deps.links.current();
    if (!view) return; // no mesh shown: the followers keep the last view
    const selection = selectionTool.state();
    const parts: Record<string, unknown> = {
      ...viewParts(view),
      selection: selection.meshId && selection.ids.length ? { mesh: selection.meshId, kind: selection.kind, ids: selection.ids } : null,
      slice: deps.kinds.voxels.sliceView(),
    };
    for (const [part, value] of Object.entries(parts)) this.send(part, value);
  }

  private send(part: string, value: unknown): void {
    if (!this.room) return;
    const json = JSON.stringify(value);
    if (this.sent.get(part) === json) return;
    this.sent.set(part, json);
    if (part !== 'camera' && part !== 'code') this.everSent.add(json);
    this.rooms.set(this.room, part, value, (e) => {
      this.sent.delete(part); // sent again at the next change
      this.onError(e);
    });
  }

  private sendCode(text: string | null): void {
    window.clearTimeout(this.codeTimer);
    if (!this.room) return;
    if (text === null) return this.send('code', null);
    this.codeTimer = window.setTimeout(() => this.send('code', { text }), CODE_MS);
  }
}
