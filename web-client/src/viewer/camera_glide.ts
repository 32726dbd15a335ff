// A camera that glides to where it is told to be (a lecture's presenter's,
// which comes 30 times a second at most): each new goal starts a short glide
// from where the camera is, eased, and the glide ends exactly on the goal, so
// that the same camera over the same objects draws the same picture as the
// presenter's.
import type { ViewState } from './view_state.ts';
import { applyCamera, readCamera } from './camera_state.ts';
import type { Viewer } from './viewer.ts';

type Camera = ViewState['camera'];
type Vec3 = [number, number, number];

/** How long a glide takes: a little more than the time between two of the presenter's cameras. */
const GLIDE_MS = 120;

const mix = (a: Vec3, b: Vec3, t: number): Vec3 => [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t];

export class CameraGlide {
  private readonly viewer: Viewer;
  private glide: { from: Camera; to: Camera; start: number } | null = null;
  private frame = 0;

  constructor(viewer: Viewer) {
    this.viewer = viewer;
  }

  /** Whether a glide is under way. */
  get moving(): boolean {
    return this.glide !== null;
  }

  /** Glides from where the camera is to `to`. */
  to(to: Camera): void {
    this.glide = { from: readCamera(this.viewer), to, start: performance.now() };
    if (!this.frame) this.frame = requestAnimationFrame(() => this.step());
  }

  /** Puts the camera at `to` at once. */
  jump(to: Camera): void {
    this.stop();
    applyCamera(this.viewer, to);
  }

  /** Stops where the camera is (the user takes it over). */
  stop(): void {
    this.glide = null;
    cancelAnimationFrame(this.frame);
    this.frame = 0;
  }

  private step(): void {
    this.frame = 0;
    const g = this.glide;
    if (!g) return;
    const s = Math.min(1, (performance.now() - g.start) / GLIDE_MS);
    if (s >= 1) {
      this.glide = null;
      applyCamera(this.viewer, g.to);
      return;
    }
    const t = s * s * (3 - 2 * s);
    applyCamera(this.viewer, {
      position: mix(g.from.position, g.to.position, t),
      target: mix(g.from.target, g.to.target, t),
      up: mix(g.from.up, g.to.up, t),
      fov: g.from.fov + (g.to.fov - g.from.fov) * t,
    });
    this.frame = requestAnimationFrame(() => this.step());
  }
}
