// Courses, assignments and grades (protocol/API.md "Courses, assignments and
// grades"): the caller's courses and their members, rosters enrolled with
// one-time sign-in links, assignments graded on hidden meshes, submissions
// with their scores, reasons and pictures, the grades as JSON or as CSV.
import type { PluginDiagnostic } from './plugins.ts';
import { request, requestOk } from './rest.ts';

export type CourseRole = 'teacher' | 'assistant' | 'student';

export interface Course {
  id: string;
  title: string;
  created: string;
  role: CourseRole | string;
}

export interface Member {
  login: string;
  name: string;
  role: CourseRole | string;
  added: string;
}

/** GET /courses/{id}: the staff also get the members, a teacher the join code. */
export interface CourseDetail extends Course {
  members?: Member[];
  join_code?: string;
}

/** A one-time sign-in link of a new account (`cgl_…`, redeemed at /tickets/redeem). */
export interface SignInLink {
  user: string;
  ticket: string;
  expires_s: number;
}

export interface Enrolment {
  members: Member[];
  /** The logins whose accounts were made. */
  created: string[];
  links: SignInLink[];
}

export interface CompareSpec {
  method: string;
  tolerance?: number;
  keys?: Record<string, number>;
}

export interface Assignment {
  id: string;
  course: string;
  owner: string;
  created: string;
  title: string;
  /** Markdown. */
  statement: string;
  /** C++: the student's copy starts from it. */
  starter: string;
  public_meshes: string[];
  deadline: string | null;
  points_per_mesh: number;
  show_pictures: boolean;
  compare: CompareSpec;
  algorithm: string;
  output: string;
  params: Record<string, unknown>;
  time_limit_s: number;
  hidden_count: number;
  /** The staff's. */
  hidden_meshes?: string[];
  reference_plugin?: string;
  reference_jobs?: string[];
}

/** What POST /courses/{id}/assignments takes. */
export interface AssignmentSpec {
  title: string;
  statement: string;
  starter: string;
  public_meshes: string[];
  hidden_meshes: string[];
  reference_plugin: string;
  algorithm?: string;
  compare: CompareSpec;
  points_per_mesh: number;
  deadline: string | null;
  show_pictures: boolean;
  time_limit_s: number;
}

export type SubmissionState = 'building' | 'running' | 'graded' | 'failed';

/** A result's pictures (URLs under /api/v1): a scalar field's three; a mesh output's result and reference. */
export interface SubmissionPictures {
  result: string;
  reference: string;
  difference?: string;
}

/** A submission's result on one hidden mesh. */
export interface SubmissionResult {
  /** "hidden 1", "hidden 2"… */
  mesh: string;
  state: string;
  points: number;
  max_points: number;
  reason: string;
  /** Where the assignment shows them (always to the staff): URLs under /api/v1. */
  pictures?: SubmissionPictures;
  /** The staff's: the run, a job shared with them. */
  job?: string;
  mesh_id?: string;
  detail?: string;
  measures?: Record<string, unknown>;
}

export interface Submission {
  id: string;
  assignment: string;
  student: string;
  created: string;
  late: boolean;
  state: SubmissionState | string;
  score: number;
  max_score: number;
  build: { state: string; error: string; diagnostics: PluginDiagnostic[] };
  results: SubmissionResult[];
  /** The staff's, one submission asked for. */
  source?: string;
  plugin?: string;
}

/** A student's row of an assignment's grades: the latest submission counted. */
export interface GradeRow {
  login: string;
  name: string;
  score: number | null;
  max_score: number;
  submissions: number;
  submission?: string;
  submitted?: string;
  late?: boolean;
  state?: string;
}

export interface Grades {
  assignment: string;
  title: string;
  late_counted: boolean;
  max_score: number;
  students: GradeRow[];
}

const FINAL = new Set(['graded', 'failed']);

/** Whether a submission's grading has ended. */
export function submissionSettled(s: Pick<Submission, 'state'>): boolean {
  return FINAL.has(s.state);
}

const id = (v: string): string => encodeURIComponent(v);

function json(method: string, body: unknown): RequestInit {
  return { method, headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) };
}

export function listCourses(): Promise<Course[]> {
  return request<Course[]>('/courses');
}

export function getCourse(course: string): Promise<CourseDetail> {
  return request<CourseDetail>(`/courses/${id(course)}`);
}

/** A new course, the caller its teacher (403 for a user who is not a teacher). */
export function createCourse(title: string): Promise<Course> {
  return request<Course>('/courses', json('POST', { title }));
}

/** Joins a course as a student with its join code. */
export function joinCourse(code: string): Promise<Course> {
  return request<Course>('/courses/join', json('POST', { code }));
}

/** Enrols a roster given as CSV lines `login,name[,role]` (a header line is skipped). */
export function enrolRoster(course: string, csv: string): Promise<Enrolment> {
  return request<Enrolment>(`/courses/${id(course)}/members`, { method: 'POST', headers: { 'Content-Type': 'text/csv' }, body: csv });
}

/** A new sign-in link for a member. */
export function newSignInLink(course: string, user: string): Promise<SignInLink> {
  return request<SignInLink>(`/courses/${id(course)}/members/${id(user)}/link`, json('POST', {}));
}

export function listAssignments(course: string): Promise<Assignment[]> {
  return request<Assignment[]>(`/courses/${id(course)}/assignments`);
}

export function postAssignment(course: string, spec: AssignmentSpec): Promise<Assignment> {
  return request<Assignment>(`/courses/${id(course)}/assignments`, json('POST', spec));
}

/** Submits the caller's plugin (its source is copied): answers the submission, building. */
export function submitPlugin(assignment: string, plugin: string): Promise<Submission> {
  return request<Submission>(`/assignments/${id(assignment)}/submissions`, json('POST', { plugin }));
}

/** The caller's submissions to the assignment; the staff's: everyone's (without sources). */
export function listSubmissions(assignment: string): Promise<Submission[]> {
  return request<Submission[]>(`/assignments/${id(assignment)}/submissions`);
}

export function getSubmission(submission: string): Promise<Submission> {
  return request<Submission>(`/submissions/${id(submission)}`);
}

/** The staff's: a row per student of the course. */
export function getGrades(assignment: string): Promise<Grades> {
  return request<Grades>(`/assignments/${id(assignment)}/grades`);
}

export function regrade(assignment: string): Promise<{ assignment: string; regrading: number }> {
  return request(`/assignments/${id(assignment)}/regrade`, { method: 'POST' });
}

/** The grades as CSV for a gradebook's import, with the file name the server gives it. */
export async function gradesCsv(assignment: string): Promise<{ blob: Blob; name: string }> {
  const r = await requestOk(`/assignments/${id(assignment)}/grades?format=csv`);
  const name = /filename="([^"]+)"/.exec(r.headers.get('Content-Disposition') ?? '')?.[1] ?? `grades-${assignment}.csv`;
  return { blob: await r.blob(), name };
}

/** The page's sign-in URL for a link: the viewer redeems `#ticket=` before anything else. */
export function signInUrl(ticket: string, origin: string = location.origin): string {
  return `${origin}/#ticket=${ticket}`;
}
