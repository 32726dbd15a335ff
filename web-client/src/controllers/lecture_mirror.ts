// A follower's viewer (and a replay's) showing a lecture's parts: the view
// parts (viewer/view_state.ts: meshes, display, overlays, field, skeletons)
// through the view links' own restore, the camera gliding to each of the
// presenter's (or jumping, in a replay playing), the selection and the voxel
// slice by their owners. What the presenter shows of their own their
// followers read while the room lasts: a mesh or job not known here yet is
// asked for first. Detached, nothing is applied but the parts are kept, and
// "Follow again" shows them all at once. The code and the hand shown go to
// the controller (controllers/lecture.ts), detached or not.
import { getJob } from '../api/rest.ts';
import { AXES } from '../api/voxel_slice.ts';
import type { SliceView } from '../panels/voxel_slices.ts';
import { CameraGlide } from '../viewer/camera_glide.ts';
import { checkCamera, viewFromParts, VIEW_PARTS, type FullView, type ViewState } from '../viewer/view_state.ts';
import { describe, jobOf, type AppContext, meshOf } from './context.ts';
import type { Kinds } from '../kinds/registry.ts';
import type { JobsController } from './jobs.ts';
import type { MeshesController } from './meshes.ts';
import type { ViewLinks } from './view_links.ts';

/** What a follower's view is shown through: the view links, the mesh list, the jobs, the voxel slices. */
export interface MirrorDeps {
  links: Pick<ViewLinks, 'show'>;
  meshes: Pick<MeshesController, 'refresh'>;
  jobs: Pick<JobsController, 'upsert'>;
  kinds: Pick<Kinds, 'voxels'>;
}

/** The parts the controller shows itself (not in the view). */
export type SidePart = 'code' | 'hand';

const isObject = (v: unknown): v is Record<string, unknown> => typeof v === 'object' && v !== null && !Array.isArray(v);

export class LectureMirror {
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: MirrorDeps;
  private readonly onSide: (part: SidePart, value: unknown) => void;
  readonly glide: CameraGlide;
  private parts: Record<string, unknown> = {};
  private attachedNow = true;
  /** A view being shown (its meshes and fields load); a change meanwhile shows the view again after it. */
  private applying = false;
  private again = false;
  /** The last error said, so that a part that keeps failing does not say it at every change. */
  private said = '';

  constructor(ctx: AppContext, deps: MirrorDeps, onSide: (part: SidePart, value: unknown) => void) {
    this.ctx = ctx;
    this.deps = deps;
    this.onSide = onSide;
    this.glide = new CameraGlide(ctx.viewer);
  }

  get attached(): boolean {
    return this.attachedNow;
  }

  /** Whether the view is still being shown (meshes, fields loading, the camera gliding). */
  get busy(): boolean {
    return this.applying || this.glide.moving;
  }

  /** Forgets the lecture (left, ended, a replay closed). */
  reset(): void {
    this.parts = {};
    this.attachedNow = true;
    this.said = '';
    this.glide.stop();
  }

  /** The whole state at once (joining, seeking a replay): shown at once, the camera jumping to its place. */
  setAll(state: Readonly<Record<string, unknown>>): void {
    this.parts = { ...state };
    this.onSide('code', this.parts.code ?? null);
    this.onSide('hand', this.parts.hand ?? null);
    if (this.attachedNow) void this.showView();
  }

  /** One part changed: the camera glides to it (`glide`, live) or jumps (a replay playing). */
  set(part: string, value: unknown, glide = true): void {
    this.parts[part] = value;
    if (part === 'code' || part === 'hand') return this.onSide(part, value);
    if (!this.attachedNow || this.applying) {
      // Shown after the view being shown, which ends with the latest camera, selection and slice.
      if (this.applying && (VIEW_PARTS as readonly string[]).includes(part) && part !== 'camera') this.again = true;
      return;
    }
    if (part === 'camera') {
      const camera = this.camera();
      if (camera && glide) this.glide.to(camera);
      else if (camera) this.glide.jump(camera);
    } else if (part === 'selection') void this.showSelection();
    else if (part === 'slice') this.showSlice();
    else if ((VIEW_PARTS as readonly string[]).includes(part)) void this.showView();
  }

  /** Follows again: the whole state shown at once. */
  attach(): void {
    this.attachedNow = true;
    void this.showView();
  }

  /** Looks around alone: nothing is applied until attach(). */
  detach(): void {
    this.attachedNow = false;
    this.glide.stop();
  }

  private camera(): ViewState['camera'] | null {
    try {
      return this.parts.camera ? checkCamera(this.parts.camera) : null;
    } catch {
      return null;
    }
  }

  private say(text: string): void {
    if (text === this.said) return;
    this.said = text;
    this.ctx.error(text);
  }

  private async showView(): Promise<void> {
    if (this.applying) {
      this.again = true;
      return;
    }
    this.applying = true;
    try {
      do {
        this.again = false;
        let view: FullView | null;
        try {
          view = viewFromParts(this.parts);
        } catch (e) {
          this.say(`Cannot show the lecture's view: ${describe(e)}`);
          return;
        }
        if (!view) return;
        if (!(await this.readable(view))) return;
        if (!this.attachedNow) return;
        this.glide.stop();
        await this.deps.links.show(view, 'lecture');
        if (!this.attachedNow) return;
        // The view began with the camera then: the latest one now.
        const camera = this.camera();
        if (camera) this.glide.jump(camera);
        await this.showSelection();
        this.showSlice();
      } while (this.again && this.attachedNow);
    } finally {
      this.applying = false;
    }
  }

  /**
   * Asks for what the view names and this page does not know yet (the
   * presenter's meshes and jobs, read while the room lasts; a replay's, when
   * shared with the course). False, said, when its mesh cannot be read.
   */
  private async readable(view: FullView): Promise<boolean> {
    const { deps } = this;
    const { state } = view;
    const meshes = [state.mesh, ...(state.scene ?? []).map((o) => String(o.mesh)).filter((m) => !m.startsWith('job:'))];
    if (meshes.some((m) => !meshOf(this.ctx, m))) await deps.meshes.refresh();
    const unread = meshes.filter((m) => !meshOf(this.ctx, m));
    if (unread.length) {
      this.say(`The lecture shows a mesh you cannot read (${unread.join(', ')}): its presenter may share it with the course.`);
      return false;
    }
    const jobs = new Set<string>();
    if (state.field) jobs.add(state.field.job);
    for (const key of [...view.compare, ...view.show]) jobs.add(key.slice(0, key.indexOf('/')));
    for (const o of state.scene ?? []) if (String(o.mesh).startsWith('job:')) jobs.add(String(o.mesh).slice(4, String(o.mesh).indexOf('/')));
    const slice = this.parts.slice;
    if (isObject(slice) && typeof slice.job === 'string') jobs.add(slice.job);
    await Promise.all(
      [...jobs]
        .filter((id) => !jobOf(this.ctx, id))
        .map((id) =>
          getJob(id).then(
            (job) => deps.jobs.upsert(job),
            () => {},
          ),
        ),
    );
    return true;
  }

  private async showSelection(): Promise<void> {
    const tool = this.ctx.selectionTool;
    const s = this.parts.selection;
    const now = tool.state();
    if (!isObject(s) || !Array.isArray(s.ids) || typeof s.mesh !== 'string') {
      if (now.ids.length) tool.clear();
      return;
    }
    const kind = s.kind === 'vertices' ? 'vertices' : 'faces';
    const ids = s.ids.filter((i): i is number => Number.isInteger(i) && i >= 0);
    if (now.meshId === s.mesh && now.kind === kind && now.ids.length === ids.length && now.ids.every((x, i) => x === ids[i])) return;
    try {
      await tool.restore(s.mesh, kind, ids);
    } catch (e) {
      this.say(`Cannot show the lecture's selection: ${describe(e)}`);
    }
  }

  private showSlice(): void {
    const voxels = this.deps.kinds.voxels;
    const s = this.parts.slice;
    const ok =
      isObject(s) &&
      typeof s.job === 'string' &&
      typeof s.artifact === 'string' &&
      AXES.includes(s.axis as never) &&
      Number.isInteger(s.index) &&
      typeof s.threshold === 'number' &&
      Number.isFinite(s.threshold);
    const want = ok
      ? ({ job: s.job, artifact: s.artifact, axis: s.axis, index: s.index, threshold: s.threshold, cut: s.cut === true, voxels: s.voxels === true } as SliceView)
      : null;
    if (JSON.stringify(want) !== JSON.stringify(voxels.sliceView())) voxels.setSliceView(want);
  }
}
