// Courses (protocol/API.md "Courses, assignments and grades"): the caller's
// courses and the one chosen, its assignments, the open assignment's
// submissions (asked for again every second while one is being graded), the
// staff's grades, members and sign-in links, and the actions of the Course
// panel (panels/course.ts), which renders from the state. A student's copy
// of a starter opens in the code panel (controllers/plugins.ts), whose file
// "Submit" saves and submits; the staff read a submission's source there,
// read-only, and open its runs in the viewer as any job's result. The panel
// is shown by the top bar's "Course", there for a user in a course or with a
// token of their own (who may create or join one), and opened at start for
// one in a course.
import { getToken, saveBlob } from '../api/auth.ts';
import { sessionToken } from '../api/tickets.ts';
import {
  createCourse,
  enrolRoster,
  getCourse,
  getGrades,
  getSubmission,
  gradesCsv,
  joinCourse,
  listAssignments,
  listCourses,
  listSubmissions,
  newSignInLink,
  postAssignment,
  regrade,
  signInUrl,
  submissionSettled,
  submitPlugin,
  type AssignmentSpec,
  type Grades,
  type Submission,
} from '../api/courses.ts';
import { createPlugin, listPlugins } from '../api/plugins.ts';
import { ApiError, getMe, listAlgorithms } from '../api/rest.ts';
import { CoursePanel, type MeshChoice, type ReferenceChoice } from '../panels/course.ts';
import { pluginName } from '../panels/course_format.ts';
import type { CodePanel } from '../panels/playground_toggle.ts';
import { isStaff, submittable, type CourseState, type CourseTab } from '../state/app_state.ts';
import { describe, type AppContext, meshOf } from './context.ts';
import type { JobsController } from './jobs.ts';
import type { MeshesController } from './meshes.ts';

/** What the Course panel opens things with: the mesh list, a job's result. */
export interface CourseDeps {
  meshes: Pick<MeshesController, 'refresh' | 'select'>;
  jobs: Pick<JobsController, 'openResult'>;
}

/** How often the open assignment's submissions are asked for while one is being graded. */
const POLL_MS = 1000;
/** The course chosen last, kept across visits. */
const COURSE_KEY = 'cgview.course';

function remembered(): string | null {
  try {
    return localStorage.getItem(COURSE_KEY);
  } catch {
    return null;
  }
}

function remember(id: string): void {
  try {
    localStorage.setItem(COURSE_KEY, id);
  } catch {
    // storage disabled: the first course is chosen next time
  }
}

/** The same submissions, in the same states (a poll that changes nothing renders nothing). */
function sameSubmissions(a: readonly Submission[], b: readonly Submission[]): boolean {
  return JSON.stringify(a) === JSON.stringify(b);
}

export class CourseController {
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: CourseDeps;
  private readonly code: CodePanel;
  private readonly panel: CoursePanel;
  private readonly section: HTMLElement;
  private readonly toggle: HTMLButtonElement;
  private timer = 0;
  /** Counts course loads: a later one makes an earlier one's answers stale. */
  private loads = 0;

  constructor(ctx: AppContext, deps: CourseDeps, section: HTMLElement, toggle: HTMLButtonElement, code: CodePanel) {
    this.ctx = ctx;
    this.deps = deps;
    this.code = code;
    this.section = section;
    this.toggle = toggle;
    this.panel = new CoursePanel(section, {
      chooseCourse: (id) => void this.choose(id),
      createCourse: (title) => this.create(title),
      joinCourse: (code) => this.join(code),
      tab: (tab) => this.setTab(tab),
      openAssignment: (id) => void this.openAssignment(id),
      openMesh: (id) => void this.openMesh(id),
      openStarter: () => void this.act(() => this.openStarter()),
      submit: () => void this.submit(),
      pick: (submission, assignment) => void this.pick(submission, assignment),
      openCode: (submission) => void this.act(() => this.openCode(submission)),
      openResult: (submission, index) => void this.act(() => this.openResult(submission, index)),
      regrade: (assignment) => void this.act(() => this.regrade(assignment)),
      exportCsv: (assignment) => void this.act(() => this.exportCsv(assignment)),
      enrol: (csv) => this.enrol(csv),
      newLink: (login) => void this.act(() => this.newLink(login)),
      copy: (text) => this.copy(text),
      post: (spec) => this.post(spec),
      formShown: () => void this.loadChoices(),
    });
    toggle.addEventListener('click', () => this.show(section.hidden));
    const { store } = ctx;
    store.subscribe(
      (s) => [s.course, s.meshes],
      () => this.render(),
      { now: true },
    );
    // The form offers the user's meshes as they come and go.
    store.subscribe(
      (s) => [s.meshes, s.me?.user],
      () => {
        if (store.get().course.tab === 'new') this.panel.setChoices(this.meshChoices(), null);
      },
    );
  }

  private get state(): CourseState {
    return this.ctx.store.get().course;
  }

  private set(patch: Partial<CourseState>): void {
    this.ctx.store.update((s) => ({ course: { ...s.course, ...patch } }));
  }

  private say(text: string, level: 'info' | 'ok' | 'error' = 'info'): void {
    this.set({ status: { level, text } });
  }

  /** Runs an action, its failure said in the panel's status line. */
  private async act(action: () => Promise<void>): Promise<void> {
    try {
      await action();
    } catch (e) {
      this.say(describe(e), 'error');
    }
  }

  private render(): void {
    const s = this.state;
    // A member of a course, or one with a token of their own (a teacher may create a course; anyone may join one,
    // or a lecture, with its code); a notebook's view (a ticket's session) shows none.
    this.toggle.hidden = !s.available || (s.courses.length === 0 && !(getToken() && !sessionToken()));
    const { meshes } = this.ctx.store.get();
    this.panel.render({
      courses: s.courses,
      current: s.current,
      tab: s.tab,
      assignments: s.assignments,
      open: s.assignments.find((a) => a.id === s.open) ?? null,
      submissions: s.submissions,
      picked: s.picked,
      grades: s.grades,
      links: s.links.map((l) => ({ user: l.user, url: signInUrl(l.ticket) })),
      status: s.status,
      meshName: (id) => meshes.find((m) => m.id === id)?.name ?? null,
    });
  }

  /** Shows or hides the panel. */
  show(open: boolean): void {
    this.section.hidden = !open;
    this.toggle.setAttribute('aria-pressed', String(open));
    this.set({ shown: open });
    if (!open) this.panel.hidden();
    else this.render();
  }

  /**
   * Asks for the caller's courses and loads the one chosen last (or the
   * first); opens the panel for one in a course, or signed in with a course's
   * link (`open`).
   */
  async start(open: boolean): Promise<void> {
    try {
      const [courses, me] = await Promise.all([listCourses(), getMe()]);
      this.set({ available: true, courses, teacher: me.teacher === true });
      const last = remembered();
      const chosen = courses.find((c) => c.id === last) ?? courses[0];
      if (chosen) await this.choose(chosen.id);
      if (open || courses.length) this.show(true);
    } catch {
      // A server without courses, or one that refuses the caller (401: the token form asks): no panel.
      this.set({ available: false });
    }
  }

  private async choose(id: string): Promise<void> {
    const load = ++this.loads;
    remember(id);
    this.set({ open: null, submissions: [], picked: null, links: [], grades: new Map(), status: { level: 'info', text: 'Loading the course…' } });
    try {
      const [current, assignments] = await Promise.all([getCourse(id), listAssignments(id)]);
      if (load !== this.loads) return;
      this.set({ current, assignments, status: null, tab: isStaff(current) ? this.state.tab : 'assignments' });
      if (isStaff(current)) await this.loadGrades();
    } catch (e) {
      if (load === this.loads) this.say(`Cannot open the course: ${describe(e)}`, 'error');
    }
  }

  private async create(title: string): Promise<boolean> {
    try {
      const course = await createCourse(title);
      this.set({ courses: [...this.state.courses, course], tab: 'members' });
      await this.choose(course.id);
      this.say(`Created ${course.title}: enrol its students under Members.`, 'ok');
      return true;
    } catch (e) {
      this.say(describe(e), 'error');
      return false;
    }
  }

  private async join(code: string): Promise<boolean> {
    try {
      const course = await joinCourse(code);
      const courses = await listCourses();
      this.set({ courses });
      await this.choose(course.id);
      this.say(`You are in ${course.title}.`, 'ok');
      return true;
    } catch (e) {
      this.say(e instanceof ApiError && e.status === 404 ? 'No course has that join code.' : describe(e), 'error');
      return false;
    }
  }

  private setTab(tab: CourseTab): void {
    this.set({ tab, status: null });
    if (tab === 'new') void this.loadChoices();
    if (tab === 'grades') void this.loadGrades();
    // Others may have submitted meanwhile.
    if (tab === 'assignments') void this.loadSubmissions();
  }

  // ---- assignments ----------------------------------------------------------

  private async openAssignment(id: string | null): Promise<void> {
    this.set({ open: id, submissions: [], picked: null, tab: 'assignments', status: null });
    if (id) await this.loadSubmissions();
  }

  /** The open assignment's submissions; asked for again every second while one is being graded. */
  private async loadSubmissions(): Promise<void> {
    const id = this.state.open;
    if (!id) return;
    let submissions: Submission[];
    try {
      submissions = await listSubmissions(id);
    } catch (e) {
      this.say(`Cannot list the submissions: ${describe(e)}`, 'error');
      return;
    }
    if (this.state.open !== id) return;
    const before = this.state.submissions;
    if (!sameSubmissions(before, submissions)) {
      this.set({ submissions });
      // One ended since: the grades follow.
      const ended = submissions.some((s) => submissionSettled(s) && !before.some((b) => b.id === s.id && submissionSettled(b)));
      if (ended && isStaff(this.state.current)) void this.loadGrades([id]);
    }
    this.pollIfGrading();
  }

  private pollIfGrading(): void {
    window.clearTimeout(this.timer);
    if (this.state.submissions.some((s) => !submissionSettled(s))) this.timer = window.setTimeout(() => void this.loadSubmissions(), POLL_MS);
  }

  private async openMesh(id: string): Promise<void> {
    const { deps } = this;
    if (!meshOf(this.ctx, id)) await deps.meshes.refresh();
    if (!meshOf(this.ctx, id)) return this.say('That mesh is not yours to read (any more).', 'error');
    deps.meshes.select(id);
  }

  /** The student's own copy of the starter (made the first time, as a plugin named after the assignment), opened in the code panel. */
  private async openStarter(): Promise<void> {
    const a = submittable(this.ctx.store.get());
    if (!a) return;
    const name = pluginName(a.title);
    const me = this.ctx.store.get().me?.user;
    const plugins = await listPlugins();
    const mine = plugins.find((p) => p.name === name && p.origin !== 'lab' && (!me || p.owner === me));
    const plugin = mine ?? (await createPlugin(name, a.starter));
    const code = await this.code.open();
    if (!code) return;
    await code.openPlugin(plugin.id);
    code.note(mine ? `Your copy of the starter of ${a.title}, as you left it.` : `Your own copy of the starter of ${a.title}: Submit sends it.`);
    this.say(mine ? 'Your copy of the starter is open in the code panel.' : 'The starter is yours now: it is open in the code panel.', 'ok');
  }

  /** Saves the code panel's file and submits it to the open assignment; the submission is followed until graded. */
  async submit(): Promise<void> {
    const a = submittable(this.ctx.store.get());
    if (!a) return this.say('Open an assignment first.', 'error');
    const loaded = this.code.loaded();
    const code = loaded ? await loaded : null;
    try {
      if (!code) throw new Error('Open the starter first (your code is in the code panel).');
      code.note(`Submitting to ${a.title}…`);
      const plugin = await code.fileToSubmit();
      const s = await submitPlugin(a.id, plugin);
      code.note(`Submitted to ${a.title}: graded on ${a.hidden_count} hidden mesh${a.hidden_count === 1 ? '' : 'es'}, the Course panel shows how it went.`, 'ok');
      if (this.state.open !== a.id) await this.openAssignment(a.id);
      this.set({ submissions: [...this.state.submissions.filter((x) => x.id !== s.id), s], picked: null });
      this.say(`Submitted${s.late ? ', late' : ''}: building…`, 'ok');
      if (this.section.hidden) this.show(true);
      this.pollIfGrading();
    } catch (e) {
      code?.note(describe(e), 'error');
      this.say(describe(e), 'error');
    }
  }

  private async pick(submission: string, assignment?: string): Promise<void> {
    if (assignment && this.state.open !== assignment) await this.openAssignment(assignment);
    else if (!this.state.submissions.some((s) => s.id === submission)) await this.loadSubmissions();
    this.set({ picked: submission, tab: 'assignments' });
  }

  private async submissionOf(id: string): Promise<Submission> {
    return this.state.submissions.find((s) => s.id === id) ?? (await getSubmission(id));
  }

  /** The staff: a submission's source, read-only, in the code panel. */
  private async openCode(id: string): Promise<void> {
    const s = await getSubmission(id);
    if (s.source === undefined) throw new Error('Only the staff read a submission’s code.');
    const code = await this.code.open();
    if (!code) return;
    const time = new Date(s.created).toLocaleString();
    await code.showSource(`${s.student}-submission`, s.source, `${s.student}'s submission of ${time} (${s.state}), read-only.`);
    this.set({ picked: id });
  }

  /** The staff: a submission's run on hidden mesh `index`, a job shared with them, opened as any job's result. */
  private async openResult(id: string, index: number): Promise<void> {
    const s = await this.submissionOf(id);
    const job = s.results[index]?.job;
    if (!job) throw new Error(`${s.results[index]?.mesh ?? 'This result'} has no run to show.`);
    const a = this.state.assignments.find((x) => x.id === s.assignment);
    this.set({ picked: id });
    try {
      await this.deps.jobs.openResult(job, a?.output);
    } catch (e) {
      throw new Error(`Cannot show ${s.student}'s run on ${s.results[index]!.mesh}: ${describe(e)}`);
    }
  }

  private async regrade(assignment: string): Promise<void> {
    const r = await regrade(assignment);
    // The list first, so that the message never stands beside the scores
    // of before (a script waiting on both would read those).
    if (this.state.open === assignment) await this.loadSubmissions();
    this.say(`Grading ${r.regrading} submission${r.regrading === 1 ? '' : 's'} again…`, 'ok');
  }

  private async exportCsv(assignment: string): Promise<void> {
    const { blob, name } = await gradesCsv(assignment);
    saveBlob(blob, name);
  }

  /** The staff: the grades of the course's assignments (or of those named). */
  private async loadGrades(only?: string[]): Promise<void> {
    const course = this.state.current?.id;
    const ids = only ?? this.state.assignments.map((a) => a.id);
    try {
      const answers = await Promise.all(ids.map((id) => getGrades(id)));
      if (this.state.current?.id !== course) return;
      const grades = new Map<string, Grades>(only ? this.state.grades : []);
      answers.forEach((g, i) => grades.set(ids[i]!, g));
      this.set({ grades });
    } catch (e) {
      this.say(`Cannot read the grades: ${describe(e)}`, 'error');
    }
  }

  // ---- members ---------------------------------------------------------------

  private async enrol(csv: string): Promise<boolean> {
    const course = this.state.current;
    if (!course) return false;
    try {
      const r = await enrolRoster(course.id, csv);
      const made = r.created.length;
      this.set({ current: { ...course, members: r.members }, links: r.links });
      this.say(
        `Enrolled. ${made ? `${made} new account${made === 1 ? '' : 's'}: hand each student their sign-in link below.` : 'Everyone had an account already: they find the course at their next visit.'}`,
        'ok',
      );
      if (isStaff(course)) void this.loadGrades();
      return true;
    } catch (e) {
      this.say(describe(e), 'error');
      return false;
    }
  }

  private async newLink(login: string): Promise<void> {
    const course = this.state.current;
    if (!course) return;
    const link = await newSignInLink(course.id, login);
    this.set({ links: [...this.state.links.filter((l) => l.user !== login), link] });
    this.say(`A new sign-in link for ${login}: the old one no longer matters once this one is used.`, 'ok');
  }

  private async copy(text: string): Promise<boolean> {
    try {
      await navigator.clipboard.writeText(text);
      return true;
    } catch {
      return false; // no clipboard here (plain http, a denied permission): the panel selects the text
    }
  }

  // ---- a new assignment ------------------------------------------------------

  /** The meshes the form offers: the caller's own, then the others they read, with their owners. */
  private meshChoices(): MeshChoice[] {
    const { meshes, me } = this.ctx.store.get();
    const own = (owner: string | undefined) => !me || owner === undefined || owner === me.user;
    return [...meshes]
      .sort((a, b) => Number(own(b.owner)) - Number(own(a.owner)) || a.name.localeCompare(b.name))
      .map((m) => ({ id: m.id, name: m.name, owner: own(m.owner) ? null : (m.owner ?? null) }));
  }

  /** Asks for the built plugins (the reference is one) and their algorithms' outputs, for the form. */
  private async loadChoices(): Promise<void> {
    this.panel.setChoices(this.meshChoices(), null);
    try {
      const [plugins, algorithms] = await Promise.all([listPlugins(), listAlgorithms()]);
      const me = this.ctx.store.get().me?.user;
      const references: ReferenceChoice[] = plugins
        .filter((p) => p.build.state === 'ok' && p.origin !== 'lab')
        .sort((a, b) => Number(a.owner !== me) - Number(b.owner !== me) || a.name.localeCompare(b.name))
        .map((p) => ({
          id: p.id,
          name: p.name,
          owner: !me || p.owner === me ? null : p.owner,
          algorithms: algorithms.filter((a) => a.plugin === p.id).map((a) => ({ name: a.name, outputs: a.outputs ?? [] })),
        }));
      this.panel.setChoices(this.meshChoices(), references);
    } catch (e) {
      this.say(`Cannot list your plugins: ${describe(e)}`, 'error');
    }
  }

  private async post(spec: AssignmentSpec): Promise<string | null> {
    const course = this.state.current;
    if (!course) return 'Choose a course first.';
    try {
      const a = await postAssignment(course.id, spec);
      this.set({ assignments: [...this.state.assignments, a] });
      await this.openAssignment(a.id);
      this.say(`Posted ${a.title}: the reference runs on its ${a.hidden_count} hidden mesh${a.hidden_count === 1 ? '' : 'es'}.`, 'ok');
      void this.loadGrades([a.id]);
      return null;
    } catch (e) {
      return describe(e);
    }
  }
}
