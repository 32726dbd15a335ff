// Live lectures (protocol/API.md, "Live lectures (rooms)"): a room carries
// its presenter's view, in parts, to every follower. Over the WebSocket:
// present, follow, room_set (the presenter's changes), raise_hand, show_hand
// and room_end, and the events room_update, room_presence and room_ended;
// over REST a course's lectures and a lecture's recording.
import { request } from './rest.ts';
import type { CgviewSocket, ServerError } from './ws.ts';

/** A point picked on a mesh: the mesh's id and the point in its own coordinates. */
export interface HandPoint {
  mesh: string;
  position: [number, number, number];
}

/** A follower's raised hand. */
export interface Hand {
  user: string;
  point: HandPoint;
}

/** The answer to present: the room, and its course or its join code. */
export interface PresentedRoom {
  room: string;
  course?: string;
  code?: string;
}

/** The answer to follow: the room, its presenter and its whole state at once. */
export interface FollowedRoom {
  room: string;
  presenter: string;
  state: Record<string, unknown>;
}

export type RoomEvent =
  | { type: 'room_update'; room: string; part: string; value: unknown; t_ms: number }
  | { type: 'room_presence'; room: string; followers: number; hands: Hand[] }
  | { type: 'room_ended'; room: string };

const ROOM_EVENTS: ReadonlySet<string> = new Set(['room_update', 'room_presence', 'room_ended']);

/** A course's lecture, live or recorded (GET /courses/{id}/rooms). */
export interface RoomSummary {
  room: string;
  presenter: string;
  started: string;
  ended: string | null;
  live: boolean;
}

/** A change of a lecture's part, at its time from the lecture's start. */
export interface RecordedChange {
  t_ms: number;
  part: string;
  value: unknown;
}

/** A lecture's recording (GET /rooms/{id}/recording): every change in order. */
export interface Recording {
  room: string;
  course: string;
  presenter: string;
  started: string;
  ended: string | null;
  live: boolean;
  events: RecordedChange[];
}

export class RoomsApi {
  private readonly socket: CgviewSocket;

  constructor(socket: CgviewSocket) {
    this.socket = socket;
  }

  /** The events of the rooms this page is in (the caller filters by room: a user's other pages get them too). */
  onEvent(handler: (event: RoomEvent) => void): () => void {
    return this.socket.onMessages(ROOM_EVENTS, (m) => handler(m as unknown as RoomEvent));
  }

  /** Presents to a course (its members follow) or, with `code`, to anyone given the room's join code. */
  async present(target: { course: string } | { code: true }): Promise<PresentedRoom> {
    return (await this.socket.request({ type: 'present', ...target }, 'room')) as unknown as PresentedRoom;
  }

  /** Follows a course's room, or a room by its join code. */
  async follow(target: { room: string } | { code: string }): Promise<FollowedRoom> {
    return (await this.socket.request({ type: 'follow', ...target }, 'room_state')) as unknown as FollowedRoom;
  }

  /** A follower stops following: no more updates, no longer counted, its hand lowered. */
  leave(room: string, onError: (e: ServerError) => void): void {
    this.socket.tell({ type: 'leave', room }, onError);
  }

  /** The presenter's change of one part; `onError` hears a refusal (anyone else's is forbidden). */
  set(room: string, part: string, value: unknown, onError: (e: ServerError) => void): void {
    this.socket.tell({ type: 'room_set', room, part, value }, onError);
  }

  /** A follower's hand with a point picked on a mesh; null lowers it. */
  raiseHand(room: string, point: HandPoint | null, onError: (e: ServerError) => void): void {
    this.socket.tell({ type: 'raise_hand', room, point }, onError);
  }

  /** The presenter shows a follower's hand to everybody (the part `hand`). */
  showHand(room: string, user: string, onError: (e: ServerError) => void): void {
    this.socket.tell({ type: 'show_hand', room, user }, onError);
  }

  end(room: string, onError: (e: ServerError) => void): void {
    this.socket.tell({ type: 'room_end', room }, onError);
  }

  /**
   * Tells a room_set and waits for the server to have read it (a ping after
   * it): resolves with the refusal's code, or null when it was taken.
   */
  async trySet(room: string, part: string, value: unknown): Promise<string | null> {
    let refused: string | null = null;
    this.set(room, part, value, (e) => (refused = e.code));
    await this.socket.ping();
    return refused;
  }
}

/** A course's lectures, live and recorded, oldest first. */
export function listRooms(course: string): Promise<RoomSummary[]> {
  return request<RoomSummary[]>(`/courses/${encodeURIComponent(course)}/rooms`);
}

export function getRecording(room: string): Promise<Recording> {
  return request<Recording>(`/rooms/${encodeURIComponent(room)}/recording`);
}
