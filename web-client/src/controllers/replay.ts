// A recorded lecture played again as live 3D: its changes (GET
// /rooms/{id}/recording: each part's value at its time from the start) are
// handed to the lecture mirror (controllers/lecture_mirror.ts) as the clock
// passes them, at 0.5x to 4x; a seek shows the state at that moment (each
// part's latest value by then) at once. Detached (the user takes the camera,
// or "Detach"), the replay stops where it is, and the view is the user's to
// explore; "Follow again" or Play shows the lecture's moment again.
import type { RecordedChange, Recording } from '../api/rooms.ts';
import type { ReplayClock } from '../state/app_state.ts';
import type { LectureMirror } from './lecture_mirror.ts';

/** Each part's latest value at `t`, and how many changes that is. */
export function stateAt(events: readonly RecordedChange[], t: number): { state: Record<string, unknown>; next: number } {
  const state: Record<string, unknown> = {};
  let next = 0;
  while (next < events.length && events[next]!.t_ms <= t) {
    const e = events[next++]!;
    state[e.part] = e.value;
  }
  return { state, next };
}

export class ReplayPlayer {
  private readonly mirror: LectureMirror;
  private readonly onClock: (clock: ReplayClock | null) => void;
  private events: RecordedChange[] = [];
  /** The first change not yet handed to the mirror. */
  private next = 0;
  private clock: ReplayClock | null = null;
  private frame = 0;
  private last = 0;

  constructor(mirror: LectureMirror, onClock: (clock: ReplayClock | null) => void) {
    this.mirror = mirror;
    this.onClock = onClock;
  }

  /** Starts on a recording, paused at its first change (its first view). */
  open(recording: Recording): void {
    this.stop();
    this.events = [...recording.events].sort((a, b) => a.t_ms - b.t_ms);
    const end = this.events.length ? this.events[this.events.length - 1]!.t_ms : 0;
    const ended = recording.ended ? Date.parse(recording.ended) - Date.parse(recording.started) : NaN;
    const duration = Math.max(end, Number.isFinite(ended) ? ended : 0);
    this.clock = { t: 0, duration, playing: false, speed: this.clock?.speed ?? 1 };
    this.mirror.reset();
    this.seek(this.events[0]?.t_ms ?? 0);
  }

  close(): void {
    this.stop();
    this.events = [];
    this.clock = null;
    this.onClock(null);
  }

  play(): void {
    const c = this.clock;
    if (!c || c.playing) return;
    if (!this.mirror.attached) this.mirror.attach();
    // At the end, Play starts again from the beginning.
    if (c.t >= c.duration) this.seek(0);
    this.set({ playing: true });
    this.last = performance.now();
    this.frame = requestAnimationFrame(() => this.tick());
  }

  pause(): void {
    this.stop();
    if (this.clock?.playing) this.set({ playing: false });
  }

  /** Shows the lecture's state at `t` (ms from its start) at once. */
  seek(t: number): void {
    const c = this.clock;
    if (!c) return;
    const at = Math.min(Math.max(0, t), c.duration);
    const { state, next } = stateAt(this.events, at);
    this.next = next;
    this.set({ t: at });
    this.mirror.setAll(state);
  }

  speed(speed: number): void {
    if (this.clock && speed > 0) this.set({ speed });
  }

  /** The user looks around: the replay stops here. */
  detached(): void {
    this.pause();
  }

  private set(patch: Partial<ReplayClock>): void {
    if (!this.clock) return;
    this.clock = { ...this.clock, ...patch };
    this.onClock(this.clock);
  }

  private stop(): void {
    cancelAnimationFrame(this.frame);
    this.frame = 0;
  }

  private tick(): void {
    this.frame = 0;
    const c = this.clock;
    if (!c?.playing) return;
    const now = performance.now();
    const t = Math.min(c.duration, c.t + (now - this.last) * c.speed);
    this.last = now;
    // Each change the clock passed, in order; the camera jumps (the recording is as dense as the presenter's moves).
    while (this.next < this.events.length && this.events[this.next]!.t_ms <= t) {
      const e = this.events[this.next++]!;
      this.mirror.set(e.part, e.value, false);
    }
    this.set({ t, playing: t < c.duration });
    if (t < c.duration) this.frame = requestAnimationFrame(() => this.tick());
  }
}
