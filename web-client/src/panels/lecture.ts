// The live lecture's part of the Course panel: for a course's staff "Present
// to the course", for anyone "Present with a join code"; the course's
// lectures, a live one with "Follow" and a recorded one with "Replay"; "Join
// with code". Presenting: who follows, the hands raised with "Show to all",
// "End lecture". Following: "Detach" and "Follow again", "Raise hand" (then
// a click on the mesh) and "Lower hand", "Leave", and the presenter's code,
// read-only, while their code panel is open. Replaying: play and pause, the
// time to seek, the speed, "Detach" and "Follow again". It draws what the
// controller (controllers/lecture.ts) tells it and hands it the clicks.
import type { RoomSummary } from '../api/rooms.ts';
import type { LectureState, ReplayClock } from '../state/app_state.ts';
import { el, localTime as when, smallButton as button } from './dom.ts';
import './lecture.css';

export interface LectureActions {
  present(to: 'course' | 'code'): void;
  follow(target: { room: string } | { code: string }): void;
  replay(room: string): void;
  end(): void;
  /** A follower leaves, or a replay closes. */
  leave(): void;
  detach(): void;
  attach(): void;
  raiseHand(): void;
  lowerHand(): void;
  showHand(user: string): void;
  play(): void;
  pause(): void;
  seek(t: number): void;
  speed(speed: number): void;
  /** Shares what the lecture just ended showed with its course, for its replay. */
  shareForReplay(): void;
}

/** What the panel draws: the lecture and where the caller stands in the course. */
export interface LectureView {
  lecture: LectureState;
  /** The course chosen (null: none; a code room is still offered). */
  course: { title: string; staff: boolean } | null;
}

export const SPEEDS = [0.5, 1, 2, 4];

/** A time from the lecture's start as m:ss. */
export function clockText(ms: number): string {
  const s = Math.max(0, Math.floor(ms / 1000));
  return `${Math.floor(s / 60)}:${String(s % 60).padStart(2, '0')}`;
}

export class LecturePanel {
  readonly root: HTMLElement;
  private readonly actions: LectureActions;
  private readonly body: HTMLElement;
  private readonly statusLine: HTMLElement;
  /** The replay's clock controls, built once per replay so that a drag of the slider is not cut by a render. */
  private readonly clock = {
    slider: el('input', { type: 'range', min: '0', max: '0', step: '1', value: '0', 'aria-label': 'Replay time', class: 'replay-time' }),
    label: el('span', { class: 'replay-clock' }),
    play: el('button', { type: 'button', class: 'button small replay-play' }, 'Play'),
    speed: el('select', { 'aria-label': 'Speed', class: 'replay-speed' }, ...SPEEDS.map((s) => el('option', { value: String(s) }, `${s}×`))),
  };
  private readonly joinInput = el('input', { type: 'text', 'aria-label': 'Join code', placeholder: 'join code', autocomplete: 'off', spellcheck: 'false' });
  /** What the last render drew, but the clock: a change of the clock alone moves the clock only. */
  private drawn = '';
  private playing = false;

  constructor(actions: LectureActions) {
    this.actions = actions;
    this.statusLine = el('p', { class: 'lecture-status', role: 'status' });
    this.body = el('div', { class: 'lecture-body' });
    this.root = el('section', { class: 'lecture', 'aria-label': 'Live lecture' }, el('h3', {}, 'Live lecture'), this.body, this.statusLine);
    const { slider, play, speed } = this.clock;
    slider.addEventListener('input', () => actions.seek(Number(slider.value)));
    play.addEventListener('click', () => (this.playing ? actions.pause() : actions.play()));
    speed.addEventListener('change', () => actions.speed(Number(speed.value)));
  }

  render(view: LectureView): void {
    const { lecture } = view;
    this.statusLine.textContent = lecture.status?.text ?? '';
    this.statusLine.dataset.level = lecture.status?.level ?? 'info';
    this.root.dataset.role = lecture.role;
    this.root.dataset.attached = String(lecture.attached);
    if (lecture.replay) this.renderClock(lecture.replay);
    const key = JSON.stringify({ ...view, lecture: { ...lecture, status: null, replay: lecture.replay && { ...lecture.replay, t: 0 } } });
    if (key === this.drawn) return;
    this.drawn = key;
    switch (lecture.role) {
      case 'presenter':
        return this.body.replaceChildren(...this.presenting(lecture));
      case 'follower':
        return this.body.replaceChildren(...this.following(lecture));
      case 'replay':
        return this.body.replaceChildren(...this.replaying(lecture));
      default:
        return this.body.replaceChildren(...this.idle(view));
    }
  }

  private idle(view: LectureView): HTMLElement[] {
    const a = this.actions;
    const out: HTMLElement[] = [];
    const start = el('div', { class: 'lecture-row' });
    if (view.course?.staff)
      start.append(button('Present to the course', 'lecture-present', () => a.present('course'), `Your view, live, in the viewers of ${view.course.title}'s members`));
    start.append(button('Present with a join code', 'lecture-present-code', () => a.present('code'), 'Your view, live, for anyone you give the code to'));
    out.push(start);
    const share = view.lecture.toShare;
    if (share) {
      const n = share.meshes.length + share.jobs.length;
      out.push(
        el(
          'div',
          { class: 'lecture-row lecture-share' },
          el('span', {}, `Its followers read your ${n === 1 ? 'mesh or result' : `${n} meshes and results`} no more; for the course's replays:`),
          button('Share with the course', 'lecture-share-course', () => this.actions.shareForReplay()),
        ),
      );
    }
    const live = view.lecture.rooms.filter((r) => r.live);
    const past = view.lecture.rooms.filter((r) => !r.live);
    if (live.length) out.push(el('ul', { class: 'lecture-rooms live' }, ...live.map((r) => this.roomItem(r, true))));
    else if (view.course) out.push(el('p', { class: 'empty' }, `No live lecture in ${view.course.title} now.`));
    const join = el('form', { class: 'lecture-row lecture-join' }, this.joinInput, el('button', { type: 'submit', class: 'button small' }, 'Join with code'));
    join.addEventListener('submit', (ev) => {
      ev.preventDefault();
      const code = this.joinInput.value.trim();
      if (code) a.follow({ code });
    });
    out.push(join);
    if (past.length) {
      out.push(el('h4', {}, 'Recorded lectures'), el('ul', { class: 'lecture-rooms recorded' }, ...[...past].reverse().map((r) => this.roomItem(r, false))));
    }
    return out;
  }

  private roomItem(r: RoomSummary, live: boolean): HTMLElement {
    const li = el(
      'li',
      { 'data-room': r.room },
      el('span', { class: 'lecture-room-name' }, live ? `${r.presenter} is presenting, since ${when(r.started)}` : `${r.presenter}, ${when(r.started)}`),
    );
    li.append(live ? button('Follow', 'lecture-follow', () => this.actions.follow({ room: r.room })) : button('Replay', 'lecture-replay', () => this.actions.replay(r.room)));
    return li;
  }

  private presenting(l: LectureState): HTMLElement[] {
    const a = this.actions;
    const to = l.code
      ? el('p', { class: 'lecture-to' }, 'Presenting with the join code ', el('code', { class: 'lecture-code' }, l.code))
      : el('p', { class: 'lecture-to' }, `Presenting to ${l.courseTitle ?? 'the course'}`);
    const hands = l.hands.map((h) =>
      el(
        'li',
        { 'data-user': h.user, class: l.shownHand?.user === h.user ? 'shown' : '' },
        el('span', {}, `${h.user} raised a hand`),
        button('Show to all', 'lecture-show-hand', () => a.showHand(h.user), `Shows ${h.user}'s point in every follower's view`),
      ),
    );
    return [
      to,
      el('p', { class: 'lecture-followers' }, `${l.followers} following`),
      hands.length ? el('ul', { class: 'lecture-hands', 'aria-label': 'Raised hands' }, ...hands) : el('p', { class: 'empty' }, 'No hand raised.'),
      el(
        'div',
        { class: 'lecture-row' },
        button('End lecture', 'lecture-end', () => a.end()),
      ),
    ];
  }

  private following(l: LectureState): HTMLElement[] {
    const a = this.actions;
    const out: HTMLElement[] = [el('p', { class: 'lecture-to' }, `Following ${l.presenter ?? 'the presenter'}'s lecture`, l.attached ? '' : ': you look around on your own')];
    const row = el('div', { class: 'lecture-row' });
    row.append(
      l.attached
        ? button('Detach', 'lecture-detach', () => a.detach(), 'Look around on your own')
        : button('Follow again', 'lecture-attach', () => a.attach(), "Back to the presenter's view"),
    );
    if (l.picking)
      row.append(
        el('span', { class: 'lecture-picking' }, 'Click a point on the mesh…'),
        button('Cancel', 'lecture-hand-cancel', () => a.lowerHand()),
      );
    else if (l.handUp) row.append(button('Lower hand', 'lecture-lower-hand', () => a.lowerHand()));
    else row.append(button('Raise hand', 'lecture-raise-hand', () => a.raiseHand(), 'Then click the point of the mesh you ask about'));
    row.append(button('Leave', 'lecture-leave', () => a.leave()));
    out.push(row);
    return [...out, ...this.code(l)];
  }

  private replaying(l: LectureState): HTMLElement[] {
    const a = this.actions;
    const { slider, label, play, speed } = this.clock;
    const row = el('div', { class: 'lecture-row' });
    row.append(
      l.attached
        ? button('Detach', 'lecture-detach', () => a.detach(), 'Stop here and look around')
        : button('Follow again', 'lecture-attach', () => a.attach(), "Back to the lecture's view"),
    );
    row.append(button('Close replay', 'lecture-leave', () => a.leave()));
    return [
      el('p', { class: 'lecture-to' }, `Replay of ${l.presenter ?? 'a'}'s lecture`),
      el('div', { class: 'lecture-row replay-controls' }, play, slider, label, speed),
      row,
      ...this.code(l),
    ];
  }

  private renderClock(c: ReplayClock): void {
    const { slider, label, play, speed } = this.clock;
    this.playing = c.playing;
    slider.max = String(Math.round(c.duration));
    if (document.activeElement !== slider) slider.value = String(Math.round(c.t));
    label.textContent = `${clockText(c.t)} / ${clockText(c.duration)}`;
    play.textContent = c.playing ? 'Pause' : 'Play';
    speed.value = String(c.speed);
  }

  private code(l: LectureState): HTMLElement[] {
    if (l.presenterCode === null) return [];
    return [el('h4', {}, `${l.presenter ?? 'The presenter'}'s code`), el('pre', { class: 'lecture-code-text', 'aria-label': "Presenter's code", tabindex: '0' }, l.presenterCode)];
  }
}
