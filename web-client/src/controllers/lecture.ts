// Live lectures in the viewer (protocol/API.md, "Live lectures (rooms)";
// docs/TEACHING.md, "A live lecture"): a course's teacher (or anyone, with a
// join code) presents, and every follower's viewer shows what theirs shows.
// The presenter's view goes out in parts (controllers/lecture_broadcast.ts);
// a follower's viewer shows them (controllers/lecture_mirror.ts), may be
// detached to look around alone (or by taking the camera) and follows again
// at once; a follower raises a hand with a point picked on the mesh, which the
// presenter sees as a marker with the follower's name (viewer/hand_markers.ts)
// and may show to everybody. A course's recorded lectures replay as live 3D
// (controllers/replay.ts). The panel (panels/lecture.ts) sits under the
// course in the Course panel, and draws this state.
import { getRecording, listRooms, RoomsApi, type FollowedRoom, type Hand, type HandPoint, type RoomEvent } from '../api/rooms.ts';
import { setSharing } from '../api/rest.ts';
import type { ServerError } from '../api/ws.ts';
import { byId } from '../panels/dom.ts';
import { LecturePanel } from '../panels/lecture.ts';
import type { CodePanel } from '../panels/playground_toggle.ts';
import { isStaff, noLecture, type LectureState } from '../state/app_state.ts';
import { HandMarkers, pickPoint, type HandMark } from '../viewer/hand_markers.ts';
import type * as THREE from 'three';
import { describe, jobOf, type AppContext, meshOf } from './context.ts';
import { LectureBroadcast, type BroadcastDeps } from './lecture_broadcast.ts';
import { LectureMirror, type MirrorDeps } from './lecture_mirror.ts';
import { ReplayPlayer } from './replay.ts';

/** How often the course's lectures are asked for while the Course panel is open, in view, and no lecture is followed. */
const LIST_MS = 4000;

const isObject = (v: unknown): v is Record<string, unknown> => typeof v === 'object' && v !== null && !Array.isArray(v);

function isHand(v: unknown): v is Hand {
  if (!isObject(v) || typeof v.user !== 'string' || !isObject(v.point)) return false;
  const p = v.point;
  return typeof p.mesh === 'string' && Array.isArray(p.position) && p.position.length === 3 && p.position.every((x) => typeof x === 'number' && Number.isFinite(x));
}

export class LectureController {
  private readonly ctx: AppContext;
  private readonly rooms: RoomsApi;
  private readonly mirror: LectureMirror;
  private readonly broadcast: LectureBroadcast;
  private readonly replay: ReplayPlayer;
  private readonly panel: LecturePanel;
  private readonly markers: HandMarkers;
  /** How a follower follows again after a reconnect: the room, or a code room's code. */
  private target: { room: string } | { code: string } | null = null;
  /** Events that came while a follow was being answered (the state's room unknown yet). */
  private early: RoomEvent[] | null = null;
  /** The follower's own hand, drawn for them. */
  private myHand: HandPoint | null = null;
  private listTimer = 0;

  constructor(ctx: AppContext, deps: MirrorDeps & BroadcastDeps, courseSection: HTMLElement, code: CodePanel) {
    this.ctx = ctx;
    const { store, viewer, hooks } = ctx;
    this.rooms = new RoomsApi(ctx.socket);
    this.mirror = new LectureMirror(ctx, deps, (part, value) => {
      if (part === 'code') this.set({ presenterCode: isObject(value) && typeof value.text === 'string' ? value.text : null });
      else this.set({ shownHand: isHand(value) ? value : null });
    });
    this.broadcast = new LectureBroadcast(ctx, deps, this.rooms, code, (e) => this.refused(e));
    this.replay = new ReplayPlayer(this.mirror, (replay) => this.set({ replay }));
    this.panel = new LecturePanel({
      present: (to) => void this.present(to),
      follow: (target) => void this.follow(target),
      replay: (room) => void this.openReplay(room),
      end: () => this.end(),
      leave: () => this.leave(),
      detach: () => this.detach(),
      attach: () => this.attach(),
      raiseHand: () => this.set({ picking: true, status: { level: 'info', text: 'Click the point of the mesh you ask about.' } }),
      lowerHand: () => this.lowerHand(),
      showHand: (user) => this.showHand(user),
      play: () => this.replay.play(),
      pause: () => this.replay.pause(),
      seek: (t) => {
        // A moment sought is the lecture's to show: a detached view follows again.
        if (!this.state.attached) this.attach();
        this.replay.seek(t);
      },
      speed: (s) => this.replay.speed(s),
      shareForReplay: () => void this.shareForReplay(),
    });
    courseSection.append(this.panel.root);
    this.markers = new HandMarkers(byId('viewport'), viewer, (mesh) => this.objectOf(mesh));

    this.rooms.onEvent((ev) => this.onEvent(ev));
    ctx.socket.onStatus((connected) => void this.onStatus(connected));
    // The user takes the camera: a follower (or a replay) is detached.
    viewer.controls.addEventListener('start', () => {
      const { role, attached } = this.state;
      if ((role === 'follower' || role === 'replay') && attached) this.detach();
    });
    // A click while picking raises the hand there; the camera does not see it.
    byId('viewport').addEventListener('pointerdown', (ev) => this.pick(ev), { capture: true });

    store.subscribe(
      (s) => [s.lecture, s.course.current],
      () => this.render(),
      { now: true },
    );
    store.subscribe(
      (s) => [s.lecture.role, s.lecture.hands, s.lecture.shownHand, s.lecture.handUp],
      () => this.drawHands(),
    );
    store.subscribe(
      (s) => [s.course.current?.id, s.course.shown, s.lecture.role],
      () => this.listSoon(0),
      { now: true },
    );
    hooks.lecture = () => {
      const l = this.state;
      return {
        role: l.role,
        room: l.room,
        code: l.code,
        attached: l.attached,
        followers: l.followers,
        hands: l.hands.map((h) => h.user),
        shownHand: l.shownHand?.user ?? null,
        presenterCode: l.presenterCode,
        replay: l.replay,
        busy: this.mirror.busy,
      };
    };
    hooks.lectureWrite = (part, value) => (this.state.room ? this.rooms.trySet(this.state.room, part, value) : Promise.resolve('no room'));
  }

  private get state(): LectureState {
    return this.ctx.store.get().lecture;
  }

  private set(patch: Partial<LectureState>): void {
    this.ctx.store.update((s) => ({ lecture: { ...s.lecture, ...patch } }));
  }

  private say(text: string, level: 'info' | 'ok' | 'error' = 'info'): void {
    this.set({ status: { level, text } });
  }

  /** Back to no lecture (the course's list kept), with a word on why. */
  private none(text: string | null, level: 'info' | 'ok' | 'error' = 'info'): void {
    this.broadcast.start(null);
    this.replay.close();
    this.mirror.reset();
    this.target = null;
    this.myHand = null;
    this.ctx.viewer.renderer.domElement.classList.remove('picking');
    this.ctx.store.update((s) => ({ lecture: { ...noLecture(s.lecture.rooms), status: text ? { level, text } : null } }));
    this.listSoon(0);
  }

  /** A frame was drawn: the hands follow the view, and a presenter's view goes out. */
  frame(): void {
    this.markers.place();
    if (this.state.role === 'presenter') this.broadcast.changed();
  }

  private render(): void {
    const { course, lecture } = this.ctx.store.get();
    const c = course.current;
    this.panel.render({ lecture, course: c ? { title: c.title, staff: isStaff(c) } : null });
    this.ctx.viewer.renderer.domElement.classList.toggle('picking', lecture.picking);
  }

  // ---- presenting -------------------------------------------------------------

  private async present(to: 'course' | 'code'): Promise<void> {
    const course = this.ctx.store.get().course.current;
    if (this.state.role !== 'none') this.leave();
    if (to === 'course' && !course) return this.say('Choose a course first.', 'error');
    this.say('Starting the lecture…');
    try {
      const r = await this.rooms.present(to === 'course' ? { course: course!.id } : { code: true });
      this.set({
        ...noLecture(this.state.rooms),
        role: 'presenter',
        room: r.room,
        code: r.code ?? null,
        courseTitle: to === 'course' ? course!.title : null,
        status: { level: 'ok', text: r.code ? `Live: give your followers the code ${r.code}.` : `Live: ${course!.title}'s members may follow.` },
      });
      this.broadcast.start(r.room);
    } catch (e) {
      this.say(`Cannot present: ${describe(e)}`, 'error');
    }
  }

  private end(): void {
    const room = this.state.room;
    if (this.state.role !== 'presenter' || !room) return;
    const course = this.state.courseTitle ? this.ctx.store.get().course.current : null;
    const named = this.broadcast.named();
    this.rooms.end(room, (e) => this.say(`Cannot end the lecture: ${describe(e)}`, 'error'));
    this.none('The lecture ended; it is recorded for the course to replay.', 'ok');
    // What it showed of the presenter's own, its followers read no more: offered to the course, for its replays.
    const meshes = named.meshes.filter((id) => meshOf(this.ctx, id) && this.ctx.account.mayChange(meshOf(this.ctx, id)!.owner));
    const jobs = named.jobs.filter((id) => jobOf(this.ctx, id) && this.ctx.account.mayChange(jobOf(this.ctx, id)!.owner));
    if (course && meshes.length + jobs.length) this.set({ toShare: { course: course.id, meshes, jobs } });
  }

  private async shareForReplay(): Promise<void> {
    const share = this.state.toShare;
    if (!share) return;
    const course = this.ctx.store.get().course.courses.find((c) => c.id === share.course);
    try {
      await Promise.all([
        ...share.meshes.map((id) => setSharing('meshes', id, { courses: [share.course] }, true)),
        ...share.jobs.map((id) => setSharing('jobs', id, { courses: [share.course] }, true)),
      ]);
      this.set({ toShare: null, status: { level: 'ok', text: `Shared with ${course?.title ?? 'the course'}: its members can replay the lecture.` } });
    } catch (e) {
      this.say(`Cannot share: ${describe(e)}`, 'error');
    }
  }

  private showHand(user: string): void {
    const room = this.state.room;
    if (room) this.rooms.showHand(room, user, (e) => this.refused(e));
  }

  private refused(e: ServerError): void {
    this.say(`The server refused: ${describe(e)}`, 'error');
  }

  // ---- following --------------------------------------------------------------

  private async follow(target: { room: string } | { code: string }): Promise<void> {
    if (this.state.role === 'presenter') return this.say('End your lecture first.', 'error');
    if (this.state.role !== 'none') this.leave();
    this.say('Joining the lecture…');
    this.early = [];
    let r: FollowedRoom;
    try {
      r = await this.rooms.follow(target);
    } catch (e) {
      this.early = null;
      return this.say('code' in target && /not_found|no live room/.test(describe(e)) ? 'No live lecture has that code.' : `Cannot follow: ${describe(e)}`, 'error');
    }
    const early = this.early;
    this.early = null;
    this.target = 'code' in target ? target : { room: r.room };
    this.set({ ...noLecture(this.state.rooms), role: 'follower', room: r.room, presenter: r.presenter, status: { level: 'ok', text: `You follow ${r.presenter}.` } });
    this.mirror.reset();
    this.mirror.setAll(r.state);
    for (const ev of early) this.onEvent(ev);
  }

  private leave(): void {
    const { role, room } = this.state;
    // The server lowers the hand of a follower who leaves (a room already ended refuses: nothing to do).
    if (role === 'follower' && room) this.rooms.leave(room, () => {});
    if (role === 'follower' || role === 'replay') this.none(null);
  }

  private detach(): void {
    this.mirror.detach();
    if (this.state.role === 'replay') this.replay.detached();
    const who = this.state.role === 'replay' ? "the lecture's view" : `${this.state.presenter ?? 'the presenter'}'s view`;
    this.set({ attached: false, status: { level: 'info', text: `Detached: the view is yours. Follow again returns to ${who}.` } });
  }

  private attach(): void {
    this.set({ attached: true, status: null });
    this.mirror.attach();
  }

  private onEvent(ev: RoomEvent): void {
    if (this.early) {
      this.early.push(ev);
      return;
    }
    const { role, room } = this.state;
    if (ev.room !== room || (role !== 'presenter' && role !== 'follower')) return;
    switch (ev.type) {
      case 'room_update':
        // The presenter hears their own changes: only the hand shown is news.
        if (role === 'follower') this.mirror.set(ev.part, ev.value);
        else if (ev.part === 'hand') this.set({ shownHand: isHand(ev.value) ? ev.value : null });
        break;
      case 'room_presence':
        if (role === 'presenter') this.set({ followers: ev.followers, hands: ev.hands.filter(isHand) });
        break;
      case 'room_ended':
        if (role === 'follower') this.none('The lecture ended.', 'info');
        break;
    }
  }

  private async onStatus(connected: boolean): Promise<void> {
    const { role } = this.state;
    if (!connected && role === 'presenter') return this.none('The connection to the server dropped: your lecture ended.', 'error');
    if (!connected && role === 'follower') return this.say('The connection dropped: reconnecting…', 'error');
    if (connected && role === 'follower' && this.target) {
      const target = this.target;
      try {
        const r = await this.rooms.follow(target);
        this.set({ room: r.room, status: { level: 'ok', text: `You follow ${r.presenter} again.` } });
        if (this.mirror.attached) this.mirror.setAll(r.state);
      } catch {
        this.none('The lecture ended while the connection was down.');
      }
    }
  }

  // ---- hands ------------------------------------------------------------------

  private pick(ev: PointerEvent): void {
    const { picking, room, role } = this.state;
    if (!picking || role !== 'follower' || !room || ev.button !== 0) return;
    ev.stopPropagation();
    ev.preventDefault();
    const rect = this.ctx.viewer.renderer.domElement.getBoundingClientRect();
    const point = pickPoint(this.ctx.viewer, this.objects(), ev.clientX - rect.left, ev.clientY - rect.top);
    if (!point) return this.say('That is not on a mesh: click a point of the mesh.', 'error');
    this.myHand = point;
    this.rooms.raiseHand(room, point, (e) => this.refused(e));
    this.set({ picking: false, handUp: true, status: { level: 'ok', text: `Your hand is up: ${this.state.presenter ?? 'the presenter'} sees the point.` } });
  }

  private lowerHand(): void {
    const { room, handUp } = this.state;
    if (room && handUp) this.rooms.raiseHand(room, null, (e) => this.refused(e));
    this.myHand = null;
    this.set({ picking: false, handUp: false, status: null });
  }

  /** The meshes drawn, each with its object: the one shown and the scene's others. */
  private objects(): Array<{ mesh: string; object: THREE.Object3D }> {
    const { store, viewer } = this.ctx;
    const { selectedId, scene } = store.get();
    const out: Array<{ mesh: string; object: THREE.Object3D }> = [];
    if (selectedId && viewer.object) out.push({ mesh: selectedId, object: viewer.object });
    for (const e of scene.slice(1)) if (e.object) out.push({ mesh: e.mesh, object: e.object });
    return out;
  }

  private objectOf(mesh: string): THREE.Object3D | null {
    return this.objects().find((o) => o.mesh === mesh)?.object ?? null;
  }

  private drawHands(): void {
    const { role, hands, shownHand, handUp } = this.state;
    const marks: HandMark[] = [];
    const mark = (h: Hand, shown: boolean): HandMark => ({ user: h.user, mesh: h.point.mesh, position: h.point.position, shown });
    if (role === 'presenter') for (const h of hands) marks.push(mark(h, h.user === shownHand?.user));
    const me = this.ctx.store.get().me?.user ?? 'you';
    if (role === 'follower' && handUp && this.myHand && shownHand?.user !== me) marks.push(mark({ user: me, point: this.myHand }, false));
    if (shownHand && !(role === 'presenter' && hands.some((h) => h.user === shownHand.user))) marks.push(mark(shownHand, true));
    this.markers.set(role === 'none' ? [] : marks);
  }

  // ---- the course's lectures and their replays ----------------------------------

  private listSoon(ms: number): void {
    window.clearTimeout(this.listTimer);
    const { course, lecture } = this.ctx.store.get();
    if (!course.current || !course.shown || lecture.role === 'presenter' || lecture.role === 'follower') return;
    this.listTimer = window.setTimeout(() => void this.list(), ms);
  }

  private async list(): Promise<void> {
    const course = this.ctx.store.get().course.current;
    if (!course) return;
    if (document.visibilityState === 'hidden') return this.listSoon(LIST_MS);
    try {
      const rooms = await listRooms(course.id);
      if (this.ctx.store.get().course.current?.id === course.id && JSON.stringify(rooms) !== JSON.stringify(this.state.rooms)) this.set({ rooms });
    } catch {
      // A server without lectures, or a moment's failure: asked again.
    }
    this.listSoon(LIST_MS);
  }

  private async openReplay(room: string): Promise<void> {
    if (this.state.role === 'presenter') return this.say('End your lecture first.', 'error');
    if (this.state.role !== 'none') this.leave();
    this.say('Loading the recording…');
    try {
      const recording = await getRecording(room);
      this.set({ ...noLecture(this.state.rooms), role: 'replay', room, presenter: recording.presenter, status: null });
      this.replay.open(recording);
    } catch (e) {
      this.none(`Cannot replay the lecture: ${describe(e)}`, 'error');
    }
  }
}
