// The Course panel's DOM: the caller's courses (a chooser, their role); for
// a student the assignments, one open with its deadline, points, statement
// (Markdown, panels/markdown.ts), public meshes, "Open starter" and "Submit",
// and their submissions with state, score, each hidden mesh's reason and the
// pictures where the teacher shows them; for the staff (teacher, or an
// assistant who changes nothing) also everyone's submissions with their code
// and runs, who is stuck, "Grade again" and "Export CSV", the grades table
// (students × assignments), the members with a roster to enrol and the
// sign-in links it made, and the form of a new assignment. Without a course,
// a join code or a new course's title. It draws what the controller
// (controllers/course.ts) tells it and hands it the clicks.
import { setImageSource } from '../api/auth.ts';
import type { Assignment, AssignmentSpec, Course, CourseDetail, Grades, Submission, SubmissionResult } from '../api/courses.ts';
import type { CourseTab } from '../state/app_state.ts';
import { compareMethods, deadlineToUtc, firstDiagnostic, gradeTable, maxPoints, pointsText, scoreText, stuckStudents } from './course_format.ts';
import { el, localTime as when, smallButton as button } from './dom.ts';
import './course.css';

export interface CourseActions {
  chooseCourse(id: string): void;
  createCourse(title: string): Promise<boolean>;
  joinCourse(code: string): Promise<boolean>;
  tab(tab: CourseTab): void;
  /** Opens an assignment (null: back to the list). */
  openAssignment(id: string | null): void;
  /** Shows a mesh in the viewer. */
  openMesh(id: string): void;
  /** The student's own copy of the starter, in the code panel. */
  openStarter(): void;
  /** Saves the code panel's file and submits it to the open assignment. */
  submit(): void;
  /** Marks a submission (its pictures shown; the staff: from the grades table, its assignment opened). */
  pick(submission: string, assignment?: string): void;
  /** The staff: a submission's source, read-only, in the code panel. */
  openCode(submission: string): void;
  /** The staff: a submission's run on hidden mesh `index`, as any job's result, in the viewer. */
  openResult(submission: string, index: number): void;
  regrade(assignment: string): void;
  exportCsv(assignment: string): void;
  /** Enrols a roster of CSV lines; resolves true when enrolled. */
  enrol(csv: string): Promise<boolean>;
  newLink(login: string): void;
  /** Copies text to the clipboard; resolves whether it could. */
  copy(text: string): Promise<boolean>;
  /** Posts a new assignment; resolves null when posted, else the server's reason. */
  post(spec: AssignmentSpec): Promise<string | null>;
  /** The new assignment's form is shown: its meshes and plugins are asked for again. */
  formShown(): void;
}

/** A mesh the form offers: the caller's own, or another's (named with its owner). */
export interface MeshChoice {
  id: string;
  name: string;
  owner: string | null;
}

/** A built plugin the form offers as the reference, with its algorithms and their outputs' kinds. */
export interface ReferenceChoice {
  id: string;
  name: string;
  /** Its owner, when not the caller. */
  owner: string | null;
  algorithms: Array<{ name: string; outputs: Array<{ name: string; kind: string }> }>;
}

export interface CourseView {
  courses: readonly Course[];
  current: CourseDetail | null;
  tab: CourseTab;
  assignments: readonly Assignment[];
  open: Assignment | null;
  submissions: readonly Submission[];
  picked: string | null;
  grades: ReadonlyMap<string, Grades>;
  /** The sign-in links to hand out, as full URLs. */
  links: ReadonlyArray<{ user: string; url: string }>;
  status: { level: 'info' | 'ok' | 'error'; text: string } | null;
  /** A mesh's name, or null when the caller cannot read it (yet). */
  meshName(id: string): string | null;
}

const TAB_LABELS: Record<CourseTab, string> = { assignments: 'Assignments', grades: 'Grades', members: 'Members', new: 'New assignment' };
/** The pictures' size as the server renders them: two thirds of its default, three side by side. */
const PICTURE = { width: 320, height: 240 };

export class CoursePanel {
  private readonly root: HTMLElement;
  private readonly actions: CourseActions;
  private readonly head: HTMLElement;
  private readonly chooser: HTMLSelectElement;
  private readonly role: HTMLElement;
  private readonly statusLine: HTMLElement;
  private readonly tabs: HTMLElement;
  private readonly sections: Record<CourseTab, HTMLElement>;
  private readonly none: HTMLElement;
  private readonly more: HTMLDetailsElement;
  private readonly roster: HTMLFormElement;
  private readonly form: AssignmentForm;
  /** The statement drawn, by assignment id and text: drawn again only when it changes. */
  private statement: { key: string; node: HTMLElement } | null = null;
  /** Pictures by URL, kept while their submission is in view, so that each is fetched once. */
  private pictures = new Map<string, HTMLImageElement>();
  /** The submission picked at the last render: a newly picked one is scrolled into view. */
  private shownPicked: string | null = null;
  private readonly joinCreate: HTMLElement[];
  private readonly noneText: HTMLElement;
  /** The members tab's parts, built once (a render moves no form: what is typed keeps its focus). */
  private readonly members: { code: HTMLElement; links: HTMLElement; table: HTMLTableSectionElement };

  constructor(root: HTMLElement, actions: CourseActions) {
    this.root = root;
    this.actions = actions;
    this.chooser = el('select', { class: 'course-choose', 'aria-label': 'Course' });
    this.chooser.addEventListener('change', () => actions.chooseCourse(this.chooser.value));
    this.role = el('span', { class: 'course-role' });
    this.head = el('div', { class: 'course-row course-head' }, el('h2', {}, 'Course'), this.chooser, this.role);
    this.statusLine = el('p', { class: 'course-status', role: 'status' });
    this.tabs = el('nav', { class: 'course-tabs', 'aria-label': 'Course views' });
    this.sections = {
      assignments: el('div', { class: 'course-section', 'data-tab': 'assignments' }),
      grades: el('div', { class: 'course-section', 'data-tab': 'grades' }),
      members: el('div', { class: 'course-section', 'data-tab': 'members' }),
      new: el('div', { class: 'course-section', 'data-tab': 'new' }),
    };
    this.noneText = el('p', { class: 'empty' });
    this.none = el('div', { class: 'course-none' }, this.noneText);
    this.more = el('details', { class: 'course-more' }, el('summary', {}, 'Join or create a course'));
    this.roster = this.rosterForm();
    this.joinCreate = this.joinCreateForms();
    this.members = { code: el('p', { class: 'course-join-code' }), links: el('div', { class: 'course-links' }), table: el('tbody') };
    this.sections.members.append(
      this.members.code,
      this.members.links,
      this.roster,
      el('table', { class: 'course-members' }, el('thead', {}, el('tr', {}, el('th', {}, 'Login'), el('th', {}, 'Name'), el('th', {}, 'Role'), el('th', {}))), this.members.table),
    );
    this.form = new AssignmentForm(actions);
    this.sections.new.append(this.form.root);
    const body = el('div', { class: 'course-body' }, this.head, this.statusLine, this.none, this.tabs, ...Object.values(this.sections), this.more);
    this.root.prepend(body);
  }

  /** The panel was hidden: its pictures go (their blob URLs were let go once drawn). */
  hidden(): void {
    this.pictures.clear();
    this.sections.assignments.querySelectorAll('.submission-pictures').forEach((p) => p.remove());
  }

  render(view: CourseView): void {
    const { courses, current } = view;
    this.chooser.replaceChildren(...courses.map((c) => el('option', { value: c.id }, c.title)));
    this.chooser.value = current?.id ?? '';
    this.chooser.hidden = courses.length === 0;
    this.chooser.disabled = courses.length < 2;
    this.role.textContent = current ? current.role : '';
    this.role.dataset.role = current?.role ?? '';
    this.statusLine.textContent = view.status?.text ?? '';
    this.statusLine.dataset.level = view.status?.level ?? 'info';
    this.root.dataset.role = current?.role ?? '';

    // The join and create forms: in the panel without a course, folded under it with one; moved only then.
    const place = (parent: HTMLElement): void => {
      if (this.joinCreate[0]!.parentElement !== parent) parent.append(...this.joinCreate);
    };
    if (!current) {
      this.noneText.textContent = courses.length ? 'Choose a course.' : 'You are in no course yet.';
      place(this.none);
      this.none.hidden = false;
      this.more.hidden = true;
      this.tabs.hidden = true;
      for (const s of Object.values(this.sections)) s.hidden = true;
      return;
    }
    this.none.hidden = true;
    place(this.more);
    this.more.hidden = false;

    const staff = current.role === 'teacher' || current.role === 'assistant';
    const teacher = current.role === 'teacher';
    const tabs: CourseTab[] = staff ? (teacher ? ['assignments', 'grades', 'members', 'new'] : ['assignments', 'grades', 'members']) : ['assignments'];
    const tab = tabs.includes(view.tab) ? view.tab : 'assignments';
    this.tabs.hidden = tabs.length < 2;
    this.tabs.replaceChildren(
      ...tabs.map((t) => {
        const b = button(TAB_LABELS[t], 'course-tab', () => this.actions.tab(t));
        b.dataset.tab = t;
        b.setAttribute('aria-pressed', String(t === tab));
        return b;
      }),
    );
    for (const [t, s] of Object.entries(this.sections) as Array<[CourseTab, HTMLElement]>) s.hidden = t !== tab;

    this.renderAssignments(view, staff, teacher);
    if (staff) this.renderGrades(view);
    if (staff) this.renderMembers(view, teacher);
  }

  /** The meshes and built plugins the new assignment's form offers. */
  setChoices(meshes: readonly MeshChoice[], references: readonly ReferenceChoice[] | null): void {
    this.form.setChoices(meshes, references);
  }

  private joinCreateForms(): HTMLElement[] {
    const code = el('input', { type: 'text', name: 'code', placeholder: 'join code', autocomplete: 'off', 'aria-label': 'Join code', required: '' });
    const join = el('form', { class: 'course-row course-join' }, code, el('button', { type: 'submit', class: 'button small' }, 'Join'));
    join.addEventListener('submit', (ev) => {
      ev.preventDefault();
      if (code.value.trim()) void this.actions.joinCourse(code.value.trim()).then((ok) => ok && (code.value = ''));
    });
    const title = el('input', { type: 'text', name: 'title', placeholder: 'Geometry Processing 2027', maxlength: '200', 'aria-label': 'New course title', required: '' });
    const create = el('form', { class: 'course-row course-create' }, title, el('button', { type: 'submit', class: 'button small' }, 'Create course'));
    create.addEventListener('submit', (ev) => {
      ev.preventDefault();
      if (title.value.trim()) void this.actions.createCourse(title.value.trim()).then((ok) => ok && (title.value = ''));
    });
    return [join, create];
  }

  // ---- assignments --------------------------------------------------------

  private renderAssignments(view: CourseView, staff: boolean, teacher: boolean): void {
    const section = this.sections.assignments;
    const a = view.open;
    if (!a) {
      this.statement = null;
      this.pictures.clear();
      const items = view.assignments.map((x) => {
        const open = el('button', { type: 'button', class: 'course-assignment-open' }, x.title);
        open.addEventListener('click', () => this.actions.openAssignment(x.id));
        return el(
          'li',
          { class: 'course-assignment', 'data-assignment-id': x.id },
          open,
          el('span', { class: 'course-assignment-meta' }, `${pointsText(maxPoints(x))} points${x.deadline ? ` · due ${when(x.deadline)}` : ''}`),
        );
      });
      section.replaceChildren(
        items.length
          ? el('ul', { class: 'course-assignments' }, ...items)
          : el('p', { class: 'empty' }, staff ? 'No assignment yet.' : 'No assignment yet: your teacher posts them here.'),
      );
      return;
    }
    const back = button('← All assignments', 'assignment-back', () => this.actions.openAssignment(null));
    const due = a.deadline ? `Due ${when(a.deadline)}${new Date(a.deadline).getTime() < Date.now() ? ' (passed: submissions now are late)' : ''}` : 'No deadline';
    const points = `${pointsText(maxPoints(a))} points: ${pointsText(a.points_per_mesh)} for each of ${a.hidden_count} hidden mesh${a.hidden_count === 1 ? '' : 'es'}`;
    const meshes = a.public_meshes.map((id) => {
      const name = view.meshName(id);
      const open = button(name ?? id.slice(0, 8), 'assignment-mesh-open', () => this.actions.openMesh(id), 'Show it in the viewer');
      return el('li', { 'data-mesh-id': id }, open);
    });
    const actions = el('div', { class: 'course-row assignment-actions' });
    if (!staff) {
      actions.append(
        button('Open starter', 'assignment-starter', () => this.actions.openStarter(), 'Your own copy of the starter, in the code panel'),
        button('Submit', 'assignment-submit', () => this.actions.submit(), "Save the code panel's file and submit it"),
      );
    } else {
      if (teacher) actions.append(button('Grade again', 'assignment-regrade', () => this.actions.regrade(a.id), 'Grade every submission again'));
      actions.append(button('Export CSV', 'assignment-export', () => this.actions.exportCsv(a.id), "The grades for a gradebook's import"));
    }
    const parts: Array<HTMLElement | null> = [
      back,
      el('h3', { class: 'assignment-title' }, a.title),
      el('p', { class: 'assignment-meta' }, `${due} · ${points}${a.show_pictures ? ' · pictures shown' : ''}`),
      this.statementNode(a),
      meshes.length ? el('div', { class: 'assignment-public' }, el('h4', {}, 'Meshes to try it on'), el('ul', { class: 'assignment-meshes' }, ...meshes)) : null,
      actions,
    ];
    if (staff) parts.push(this.stuckNode(view.submissions));
    parts.push(el('h4', {}, staff ? 'Submissions' : 'Your submissions'), this.submissionsNode(view, staff));
    section.replaceChildren(el('div', { class: 'assignment-view', 'data-assignment-id': a.id }, ...parts.filter((p): p is HTMLElement => p !== null)));
    if (view.picked !== this.shownPicked) {
      this.shownPicked = view.picked;
      const picked = view.picked ? section.querySelector(`li.submission[data-submission-id="${CSS.escape(view.picked)}"]`) : null;
      picked?.scrollIntoView({ block: 'nearest' });
    }
  }

  /** The statement, rendered from Markdown once per text (its module loaded then). */
  private statementNode(a: Assignment): HTMLElement {
    const key = `${a.id}\n${a.statement}`;
    if (this.statement?.key === key) return this.statement.node;
    const node = el('div', { class: 'assignment-statement markdown' });
    this.statement = { key, node };
    if (!a.statement.trim()) node.append(el('p', { class: 'empty' }, 'No statement.'));
    else {
      node.dataset.loading = '';
      void import('./markdown.ts').then(
        (m) => {
          node.replaceChildren(m.renderMarkdown(a.statement));
          delete node.dataset.loading;
        },
        () => {
          node.replaceChildren(el('pre', {}, a.statement));
          delete node.dataset.loading;
        },
      );
    }
    return node;
  }

  private stuckNode(submissions: readonly Submission[]): HTMLElement {
    const stuck = stuckStudents(submissions);
    return el(
      'div',
      { class: 'assignment-stuck' },
      el('h4', {}, 'Who is stuck'),
      stuck.length
        ? el(
            'ul',
            {},
            ...stuck.map((s) => {
              const open = button(s.student, 'stuck-student', () => this.actions.pick(s.submission), 'Show the submission');
              return el('li', { 'data-student': s.student }, open, ' ', el('code', { class: 'stuck-message' }, s.message));
            }),
          )
        : el('p', { class: 'empty' }, "Nobody: every student's latest submission builds."),
    );
  }

  private submissionsNode(view: CourseView, staff: boolean): HTMLElement {
    if (!view.submissions.length) return el('p', { class: 'empty submissions-none' }, staff ? 'No submission yet.' : 'None yet: "Submit" sends the code panel\'s file.');
    const newest = [...view.submissions].reverse();
    // Pictures: of the submission picked, else of the newest.
    const withPictures = view.picked && newest.some((s) => s.id === view.picked) ? view.picked : newest[0]!.id;
    const used = new Set<string>();
    const items = newest.map((s) => this.submissionItem(s, staff, s.id === withPictures, s.id === view.picked, used));
    for (const url of [...this.pictures.keys()]) if (!used.has(url)) this.pictures.delete(url);
    return el('ul', { class: 'submissions' }, ...items);
  }

  private submissionItem(s: Submission, staff: boolean, pictures: boolean, picked: boolean, used: Set<string>): HTMLElement {
    const settled = s.state === 'graded' || s.state === 'failed';
    const head = el(
      'div',
      { class: 'submission-head' },
      staff ? el('span', { class: 'submission-student' }, s.student) : null,
      el('span', { class: 'submission-when', title: s.created }, when(s.created)),
      el('span', { class: `submission-state state-${s.state}` }, s.state === 'failed' ? 'did not build' : s.state),
      s.late ? el('span', { class: 'submission-late', title: 'Submitted after the deadline' }, 'late') : null,
      el('span', { class: 'submission-score' }, settled ? scoreText(s.score, s.max_score) : `… / ${pointsText(s.max_score)}`),
    );
    const li = el('li', {
      class: `submission${picked ? ' picked' : ''}`,
      'data-submission-id': s.id,
      'data-state': s.state,
      'data-late': String(s.late),
      'data-score': settled ? String(s.score) : '',
    });
    li.append(head);
    const buttons = el('div', { class: 'course-row submission-actions' });
    if (staff) buttons.append(button('Code', 'submission-code', () => this.actions.openCode(s.id), 'Its source, read-only, in the code panel'));
    const hasPictures = s.results.some((r) => r.pictures);
    if (hasPictures && !pictures) buttons.append(button('Pictures', 'submission-show-pictures', () => this.actions.pick(s.id), 'Show its pictures'));
    if (buttons.childElementCount) li.append(buttons);
    if (s.state === 'failed') {
      const diagnostics = s.build.diagnostics.slice(0, 20);
      li.append(el('p', { class: 'submission-error' }, `Does not build: ${firstDiagnostic(s)}`));
      if (diagnostics.length)
        li.append(
          el(
            'ul',
            { class: 'submission-diagnostics' },
            ...diagnostics.map((d) =>
              el(
                'li',
                { 'data-severity': d.severity },
                el('span', { class: 'diagnostic-where' }, d.line > 0 ? `${d.file}:${d.line}${d.column > 0 ? `:${d.column}` : ''}` : d.file),
                ' ',
                el('span', { class: 'diagnostic-severity' }, `${d.severity}:`),
                ' ',
                el('span', { class: 'diagnostic-message' }, d.message),
              ),
            ),
          ),
        );
    }
    if (s.results.length && s.state !== 'failed') {
      li.append(el('ul', { class: 'submission-results' }, ...s.results.map((r, i) => this.resultItem(s, r, i, staff, pictures, used))));
    }
    return li;
  }

  private resultItem(s: Submission, r: SubmissionResult, index: number, staff: boolean, pictures: boolean, used: Set<string>): HTMLElement {
    const item = el(
      'li',
      { class: 'submission-result', 'data-state': r.state, 'data-points': String(r.points) },
      el('span', { class: 'result-mesh' }, r.mesh),
      ' ',
      el('span', { class: 'result-points' }, r.state === 'queued' || r.state === 'running' ? r.state : scoreText(r.points, r.max_points)),
      r.reason ? el('span', { class: 'result-reason' }, r.reason) : null,
    );
    if (staff && r.detail) item.append(el('span', { class: 'result-detail', title: 'The run’s own message (the staff’s)' }, r.detail));
    if (staff && r.job) item.append(button('Show', 'result-open', () => this.actions.openResult(s.id, index), 'Its run, in the viewer'));
    if (pictures && r.pictures) {
      // A field's result, reference and difference; a mesh output's result and reference.
      const figures = (['result', 'reference', 'difference'] as const).flatMap((which) => {
        const at = r.pictures![which];
        if (!at) return [];
        const url = `${at}?width=${PICTURE.width}&height=${PICTURE.height}`;
        used.add(url);
        let img = this.pictures.get(url);
        if (!img) {
          img = el('img', { class: 'submission-picture', 'data-which': which, alt: `${which} on ${r.mesh}`, width: String(PICTURE.width), height: String(PICTURE.height) });
          img.addEventListener('click', () => img!.classList.toggle('large'));
          setImageSource(img, url);
          this.pictures.set(url, img);
        }
        return el('figure', {}, img, el('figcaption', {}, which));
      });
      item.append(el('div', { class: 'submission-pictures' }, ...figures));
    }
    return item;
  }

  // ---- grades -------------------------------------------------------------

  private renderGrades(view: CourseView): void {
    const section = this.sections.grades;
    if (!view.assignments.length) {
      section.replaceChildren(el('p', { class: 'empty' }, 'No assignment yet.'));
      return;
    }
    const rows = gradeTable(view.assignments, view.grades);
    const headers = view.assignments.map((a) =>
      el(
        'th',
        { 'data-assignment-id': a.id, scope: 'col' },
        el('span', { class: 'grades-title' }, a.title),
        el('span', { class: 'grades-max' }, ` (${pointsText(maxPoints(a))})`),
        button('CSV', 'grades-export', () => this.actions.exportCsv(a.id), `Export the grades of ${a.title} as CSV`),
      ),
    );
    const body = rows.map((row) =>
      el(
        'tr',
        { 'data-login': row.login },
        el('th', { scope: 'row', title: row.login }, row.name ? `${row.name} (${row.login})` : row.login),
        ...row.cells.map((g, i) => {
          const a = view.assignments[i]!;
          const td = el('td', { 'data-assignment-id': a.id });
          if (!g || !g.submissions) {
            td.append(el('span', { class: 'grades-none' }, '—'));
            return td;
          }
          td.dataset.score = g.score === null ? '' : String(g.score);
          td.dataset.submissions = String(g.submissions);
          // Late submissions alone count for nothing (the server counts the latest before the deadline).
          const text = !g.submission ? '— (late only)' : g.score === null ? (g.state ?? '…') : scoreText(g.score, g.max_score);
          const score = el('span', { class: 'grades-score' }, text);
          const open = g.submission ? button('', 'grades-open', () => this.actions.pick(g.submission!, a.id), `Open ${row.login}'s submission`) : null;
          if (open) open.append(score);
          td.append(open ?? score, el('span', { class: 'grades-count' }, `${g.submissions} submission${g.submissions === 1 ? '' : 's'}`));
          if (g.submitted) td.append(el('span', { class: 'grades-when', title: g.submitted }, `${when(g.submitted)}${g.late ? ' (late)' : ''}`));
          return td;
        }),
      ),
    );
    section.replaceChildren(
      el(
        'div',
        { class: 'grades-scroll' },
        el('table', { class: 'grades' }, el('thead', {}, el('tr', {}, el('th', { scope: 'col' }, 'Student'), ...headers)), el('tbody', {}, ...body)),
      ),
    );
    if (!rows.length) section.append(el('p', { class: 'empty' }, 'No student yet: enrol a roster under Members.'));
  }

  // ---- members ------------------------------------------------------------

  private rosterForm(): HTMLFormElement {
    const text = el('textarea', { name: 'roster', rows: '5', spellcheck: 'false', placeholder: 'login,name\nsam,Sam Smith\nkim,Kim Lee,assistant', 'aria-label': 'Roster (CSV)' });
    const form = el(
      'form',
      { class: 'course-roster' },
      el('label', {}, 'Enrol a roster: CSV lines login,name[,role] (pasted from a spreadsheet)', text),
      el('div', { class: 'course-row' }, el('button', { type: 'submit', class: 'button small' }, 'Enrol')),
    );
    form.addEventListener('submit', (ev) => {
      ev.preventDefault();
      if (text.value.trim()) void this.actions.enrol(text.value).then((ok) => ok && (text.value = ''));
    });
    return form;
  }

  private renderMembers(view: CourseView, teacher: boolean): void {
    const { code, links, table } = this.members;
    const joinCode = view.current?.join_code;
    code.hidden = !joinCode;
    code.replaceChildren('Join code: ', el('code', {}, joinCode ?? ''));
    this.roster.hidden = !teacher;
    links.hidden = view.links.length === 0;
    const items = view.links.map((l) => {
      const url = el('input', { type: 'text', class: 'course-link-url', readonly: '', value: l.url, 'aria-label': `Sign-in link of ${l.user}` });
      url.addEventListener('focus', () => url.select());
      const copy = button('Copy', 'course-link-copy', () => {
        void this.actions.copy(l.url).then((ok) => {
          copy.textContent = ok ? 'Copied' : 'Select it';
          if (!ok) url.select();
        });
      });
      return el('li', { 'data-user': l.user }, el('span', { class: 'course-link-user' }, l.user), url, copy);
    });
    const all = `login,link\n${view.links.map((l) => `${l.user},${l.url}`).join('\n')}\n`;
    links.replaceChildren(
      el('h4', {}, 'Sign-in links: each works once, for its student alone'),
      el('ul', {}, ...items),
      button('Copy all (CSV)', 'course-links-copy-all', () => void this.actions.copy(all)),
    );
    table.replaceChildren(
      ...(view.current?.members ?? []).map((m) =>
        el(
          'tr',
          { 'data-login': m.login },
          el('td', {}, m.login),
          el('td', {}, m.name),
          el('td', {}, m.role),
          el('td', {}, teacher && m.role === 'student' ? button('New link', 'member-link', () => this.actions.newLink(m.login), 'A new one-time sign-in link') : null),
        ),
      ),
    );
  }
}

/** The form of a new assignment (a teacher's): built once, so that what is typed survives the panel's renders. */
class AssignmentForm {
  readonly root: HTMLFormElement;
  private readonly actions: CourseActions;
  private readonly fields: {
    title: HTMLInputElement;
    statement: HTMLTextAreaElement;
    starter: HTMLTextAreaElement;
    reference: HTMLSelectElement;
    algorithm: HTMLSelectElement;
    method: HTMLSelectElement;
    tolerance: HTMLInputElement;
    points: HTMLInputElement;
    deadline: HTMLInputElement;
    pictures: HTMLInputElement;
    timeLimit: HTMLInputElement;
  };
  private readonly meshes: HTMLElement;
  private readonly error: HTMLElement;
  private readonly post: HTMLButtonElement;
  private references: readonly ReferenceChoice[] = [];

  constructor(actions: CourseActions) {
    this.actions = actions;
    const f = (this.fields = {
      title: el('input', { type: 'text', name: 'title', maxlength: '200', required: '', autocomplete: 'off' }),
      statement: el('textarea', { name: 'statement', rows: '8', placeholder: '# The task\nWhat to compute, and how it is graded (Markdown).' }),
      starter: el('textarea', { name: 'starter', rows: '8', spellcheck: 'false', wrap: 'off', class: 'code', placeholder: 'The C++ file each student starts from.' }),
      reference: el('select', { name: 'reference', required: '' }),
      algorithm: el('select', { name: 'algorithm' }),
      method: el('select', { name: 'method' }),
      tolerance: el('input', { type: 'number', name: 'tolerance', step: 'any', min: '0' }),
      points: el('input', { type: 'number', name: 'points', step: 'any', min: '0.01', max: '1000', value: '1', required: '' }),
      deadline: el('input', { type: 'datetime-local', name: 'deadline' }),
      pictures: el('input', { type: 'checkbox', name: 'pictures' }),
      timeLimit: el('input', { type: 'number', name: 'time_limit', step: '1', min: '1', max: '3600', value: '60', required: '' }),
    });
    this.meshes = el('div', { class: 'assignment-mesh-choice' });
    this.error = el('p', { class: 'form-error', role: 'alert' });
    this.post = el('button', { type: 'submit', class: 'button assignment-post' }, 'Post assignment');
    const row = (label: string, input: HTMLElement, help?: string): HTMLElement =>
      el('label', { class: 'assignment-field' }, el('span', {}, label), input, help ? el('small', { class: 'param-help' }, help) : null);
    f.reference.addEventListener('change', () => this.referenceChanged());
    f.algorithm.addEventListener('change', () => this.algorithmChanged());
    f.method.addEventListener('change', () => this.methodChanged());
    this.root = el(
      'form',
      { class: 'assignment-form', novalidate: '' },
      row('Title', f.title),
      row('Statement (Markdown)', f.statement),
      row('Starter (C++)', f.starter),
      el('div', { class: 'assignment-field' }, el('span', {}, 'Meshes'), this.meshes),
      row('Reference', f.reference, 'Your built plugin that solves it: it runs on every hidden mesh.'),
      row("Reference's algorithm", f.algorithm),
      el('div', { class: 'course-row' }, row('Compare by', f.method), row('Tolerance', f.tolerance)),
      el('div', { class: 'course-row' }, row('Points per hidden mesh', f.points), row('Time limit (s)', f.timeLimit)),
      row('Deadline (your local time)', f.deadline, 'Empty: none. Later submissions are marked late.'),
      el('label', { class: 'assignment-field assignment-check' }, f.pictures, el('span', {}, 'Show students the pictures of their results on the hidden meshes')),
      el('div', { class: 'course-row' }, this.post),
      this.error,
    );
    this.root.addEventListener('submit', (ev) => {
      ev.preventDefault();
      void this.submit();
    });
    this.setChoices([], null);
  }

  setChoices(meshes: readonly MeshChoice[], references: readonly ReferenceChoice[] | null): void {
    // What was ticked stays ticked.
    const ticked = (name: string) => new Set([...this.meshes.querySelectorAll<HTMLInputElement>(`input[name="${name}"]:checked`)].map((i) => i.value));
    const pub = ticked('public');
    const hidden = ticked('hidden');
    const rowOf = (m: MeshChoice): HTMLElement => {
      const box = (name: string, on: Set<string>, disabled: boolean) => {
        const input = el('input', { type: 'checkbox', name, value: m.id, 'aria-label': `${name} ${m.name}` });
        input.checked = on.has(m.id);
        input.disabled = disabled;
        return el('td', {}, input);
      };
      return el(
        'tr',
        { 'data-mesh-id': m.id },
        el('td', { class: 'mesh-choice-name', title: m.name }, m.name, m.owner ? el('span', { class: 'owner' }, ` — ${m.owner}`) : null),
        box('public', pub, false),
        // A hidden mesh is one of the teacher's own, shared with nobody.
        box('hidden', hidden, m.owner !== null),
      );
    };
    const table = (list: readonly MeshChoice[]) =>
      el(
        'table',
        { class: 'mesh-choice' },
        el('thead', {}, el('tr', {}, el('th', {}, 'Mesh'), el('th', {}, 'Public'), el('th', {}, 'Hidden'))),
        el('tbody', {}, ...list.map(rowOf)),
      );
    const own = meshes.filter((m) => m.owner === null);
    const others = meshes.filter((m) => m.owner !== null);
    const wasOpen = this.meshes.querySelector('details')?.open ?? false;
    const othersBox = others.length ? el('details', {}, el('summary', {}, `Others' meshes (${others.length}): public only`), table(others)) : null;
    if (othersBox) othersBox.open = wasOpen || others.some((m) => pub.has(m.id));
    this.meshes.replaceChildren(own.length ? table(own) : el('p', { class: 'empty' }, 'Upload the hidden meshes first (they stay unshared).'), ...(othersBox ? [othersBox] : []));

    if (references === null) return;
    this.references = references;
    const chosen = this.fields.reference.value;
    this.fields.reference.replaceChildren(
      el('option', { value: '' }, references.length ? 'Choose a built plugin…' : 'None built: build one in the code panel'),
      ...references.map((r) => el('option', { value: r.id }, r.owner ? `${r.name} — ${r.owner}` : r.name)),
    );
    this.fields.reference.value = references.some((r) => r.id === chosen) ? chosen : references.length === 1 ? references[0]!.id : '';
    this.referenceChanged();
  }

  private reference(): ReferenceChoice | undefined {
    return this.references.find((r) => r.id === this.fields.reference.value);
  }

  private referenceChanged(): void {
    const r = this.reference();
    const algorithms = r?.algorithms ?? [];
    const chosen = this.fields.algorithm.value;
    this.fields.algorithm.replaceChildren(...algorithms.map((a) => el('option', { value: a.name }, a.name)));
    if (algorithms.some((a) => a.name === chosen)) this.fields.algorithm.value = chosen;
    this.fields.algorithm.closest('label')!.hidden = algorithms.length < 2;
    this.algorithmChanged();
  }

  private algorithmChanged(): void {
    const algorithm = this.reference()?.algorithms.find((a) => a.name === this.fields.algorithm.value);
    const kind = algorithm?.outputs[0]?.kind ?? 'scalar_field';
    const methods = compareMethods(kind);
    const chosen = this.fields.method.value;
    this.fields.method.replaceChildren(...methods.map((m) => el('option', { value: m.method, 'data-tolerance': String(m.tolerance) }, m.label)));
    if (methods.some((m) => m.method === chosen)) this.fields.method.value = chosen;
    this.methodChanged();
  }

  private methodChanged(): void {
    const option = this.fields.method.selectedOptions[0];
    this.fields.tolerance.placeholder = option?.dataset.tolerance ?? '';
  }

  private async submit(): Promise<void> {
    const f = this.fields;
    const fail = (text: string): void => {
      this.error.textContent = text;
    };
    const ids = (name: string) => [...this.meshes.querySelectorAll<HTMLInputElement>(`input[name="${name}"]:checked`)].map((i) => i.value);
    const title = f.title.value.trim();
    if (!title) return fail('Give it a title.');
    const hidden = ids('hidden');
    if (!hidden.length) return fail('Tick at least one hidden mesh: the submissions are graded on them.');
    if (!f.reference.value) return fail('Choose the reference: your built plugin that solves it.');
    let deadline: string | null;
    try {
      deadline = deadlineToUtc(f.deadline.value);
    } catch (e) {
      return fail((e as Error).message);
    }
    const tolerance = f.tolerance.value.trim() === '' ? undefined : Number(f.tolerance.value);
    const spec: AssignmentSpec = {
      title,
      statement: f.statement.value,
      starter: f.starter.value,
      public_meshes: ids('public'),
      hidden_meshes: hidden,
      reference_plugin: f.reference.value,
      compare: tolerance === undefined ? { method: f.method.value } : { method: f.method.value, tolerance },
      points_per_mesh: Number(f.points.value || 1),
      deadline,
      show_pictures: f.pictures.checked,
      time_limit_s: Number(f.timeLimit.value || 60),
    };
    if ((this.reference()?.algorithms.length ?? 0) > 1) spec.algorithm = f.algorithm.value;
    if (!spec.compare.method) delete (spec.compare as { method?: string }).method;
    fail('');
    this.post.disabled = true;
    try {
      const refused = await this.actions.post(spec);
      if (refused) return fail(refused);
      this.root.reset();
      this.referenceChanged();
    } finally {
      this.post.disabled = false;
    }
  }
}
