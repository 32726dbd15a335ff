// The viewer's application state: what the page shows, in one object held by
// a Store (state/store.ts). Controllers update it; panels subscribe to the
// parts they show. Three.js objects, tokens and caches stay in the
// controllers and kinds that own them.
import type { Assignment, Course, CourseDetail, Grades, SignInLink, Submission } from '../api/courses.ts';
import type { Hand, RoomSummary } from '../api/rooms.ts';
import type { Job, Me, Mesh } from '../api/types.ts';
import { DEFAULT_DISPLAY, type DisplaySettings } from '../viewer/display_modes.ts';
import { DEFAULT_OVERLAYS, type OverlaySettings } from '../viewer/overlays.ts';
import type { SceneObjectState } from '../viewer/scene_state.ts';
import type * as THREE from 'three';
import { Store } from './store.ts';

/** An artifact of a job, by job id and artifact name. */
export interface ArtifactRef {
  jobId: string;
  artifact: string;
}

/** A job's output that the next job runs on ("Run on this"), with its kind. */
export interface RunTarget extends ArtifactRef {
  kind: string;
}

/**
 * An object of the scene: its state, its mesh's name, and (for those beside
 * the first) the surface drawn once loaded. The Scene panel edits an entry in
 * place (its sliders), so such edits do not render the panel again.
 */
export interface SceneEntry extends SceneObjectState {
  name: string;
  object: THREE.Mesh | null;
}

/** A message shown in the page; each one is a new object. A warning is a notice that stays longer, to be read. */
export interface Message {
  level: 'error' | 'warning' | 'notice';
  text: string;
  /** A button on the message ("Undo"): pressing it runs `run` and dismisses the message. */
  action?: { label: string; run: () => void };
  /** How long a notice stays (the default: a few seconds). */
  timeoutMs?: number;
  /** What it is about ("job-failed:simplify:<mesh>"): a newer message of the topic replaces it, and it goes when the topic is dismissed. */
  topic?: string;
}

/** What the Course panel shows: the assignments (and one open), the grades table, the members, a new assignment's form. */
export type CourseTab = 'assignments' | 'grades' | 'members' | 'new';

/** The caller's courses, the one chosen and what of it the Course panel shows (controllers/course.ts). */
export interface CourseState {
  /** Whether the server answered GET /courses (null until asked; false: a server without courses). */
  available: boolean | null;
  /** Whether the caller may create courses (GET /me's teacher). */
  teacher: boolean;
  /** Whether the panel is shown. */
  shown: boolean;
  courses: readonly Course[];
  /** The course chosen, as GET /courses/{id} answered (its staff: with the members). */
  current: CourseDetail | null;
  assignments: readonly Assignment[];
  /** The assignment open, by id (null: the list). */
  open: string | null;
  /** The open assignment's submissions, oldest first: the student's own; the staff's: everyone's. */
  submissions: readonly Submission[];
  /** The submission the staff chose (from the grades table or the list), marked in the list. */
  picked: string | null;
  /** The grades of the course's assignments (its staff), by assignment id. */
  grades: ReadonlyMap<string, Grades>;
  /** The sign-in links of the accounts the last roster made (or a new link asked for). */
  links: readonly SignInLink[];
  tab: CourseTab;
  /** How the panel's last action went, or what is under way. */
  status: { level: 'info' | 'ok' | 'error'; text: string } | null;
}

/** What this page does in a live lecture (controllers/lecture.ts): nothing, present, follow, or replay one. */
export type LectureRole = 'none' | 'presenter' | 'follower' | 'replay';

/** A replay's clock (controllers/replay.ts), in ms from the lecture's start. */
export interface ReplayClock {
  t: number;
  duration: number;
  playing: boolean;
  speed: number;
}

/** A live lecture as this page takes part in it, and the course's lectures (the Lecture part of the Course panel). */
export interface LectureState {
  role: LectureRole;
  /** The room presented, followed or replayed. */
  room: string | null;
  /** Its course's title (null: a room with a join code). */
  courseTitle: string | null;
  /** A code room's join code, for its presenter to hand out. */
  code: string | null;
  presenter: string | null;
  /** A follower's (or a replay's) view follows the presenter's; false: detached, looking around on their own. */
  attached: boolean;
  /** How many follow (the presenter's). */
  followers: number;
  /** The hands raised (the presenter's). */
  hands: readonly Hand[];
  /** The hand the presenter shows to everybody. */
  shownHand: Hand | null;
  /** The follower's own hand is up; picking: the next click on the mesh raises it. */
  handUp: boolean;
  picking: boolean;
  /** The presenter's code, while their code panel is open (read-only here). */
  presenterCode: string | null;
  /** The course's lectures, live and recorded. */
  rooms: readonly RoomSummary[];
  replay: ReplayClock | null;
  /** A course's lecture just ended: the presenter's own meshes and jobs it showed, to share with the course for its replay. */
  toShare: { course: string; meshes: string[]; jobs: string[] } | null;
  status: { level: 'info' | 'ok' | 'error'; text: string } | null;
}

export function noLecture(rooms: readonly RoomSummary[] = []): LectureState {
  return {
    role: 'none',
    room: null,
    courseTitle: null,
    code: null,
    presenter: null,
    attached: true,
    followers: 0,
    hands: [],
    shownHand: null,
    handUp: false,
    picking: false,
    presenterCode: null,
    rooms,
    replay: null,
    toShare: null,
    status: null,
  };
}

export interface AppState {
  meshes: readonly Mesh[];
  selectedId: string | null;
  /** The signed-in user and their quota use (GET /me); null on a server without it, or until it answers. */
  me: Me | null;
  /** The WebSocket: null before its first connection. */
  connected: boolean | null;
  /** Whether the server answered GET /api/v1/algorithms (null until asked). */
  algorithmsApi: boolean | null;
  jobs: ReadonlyMap<string, Job>;
  runTarget: RunTarget | null;
  /** What the algorithm form runs on, as its label says: the selected mesh's name, or the job output chosen with "Run on this"; null: Run is disabled. */
  inputName: string | null;
  /** Each artifact kind's part of the state (what the job list shows of its artifacts), by the kind's string: kinds/slice.ts. */
  artifacts: Readonly<Record<string, unknown>>;
  /** The fields (or skeletons) compared side by side; empty: one view. */
  compared: readonly ArtifactRef[];
  /** The scene: the selected mesh first (the viewer's shown object), then the meshes added beside it. */
  scene: readonly SceneEntry[];
  /** Whether the scene's objects are side by side, one per pane. */
  scenePanes: boolean;
  /** How surfaces are drawn (mode, material) and the overlays over the shown one: controllers/display.ts applies them. */
  display: { settings: DisplaySettings; overlays: OverlaySettings };
  /** The scene object chosen in the Scene panel: the Display panel's overlays are drawn over it. */
  picked: number;
  message: Message | null;
  course: CourseState;
  lecture: LectureState;
}

export type AppStore = Store<AppState>;

export function initialState(): AppState {
  return {
    meshes: [],
    selectedId: null,
    me: null,
    connected: null,
    algorithmsApi: null,
    jobs: new Map(),
    runTarget: null,
    inputName: null,
    artifacts: {},
    compared: [],
    scene: [],
    scenePanes: false,
    display: { settings: { ...DEFAULT_DISPLAY }, overlays: { ...DEFAULT_OVERLAYS } },
    picked: 0,
    message: null,
    course: {
      available: null,
      teacher: false,
      shown: false,
      courses: [],
      current: null,
      assignments: [],
      open: null,
      submissions: [],
      picked: null,
      grades: new Map(),
      links: [],
      tab: 'assignments',
      status: null,
    },
    lecture: noLecture(),
  };
}

/** Whether the caller is the course's staff (teacher or assistant): they see everyone's work. */
export function isStaff(course: Pick<Course, 'role'> | null | undefined): boolean {
  return course?.role === 'teacher' || course?.role === 'assistant';
}

/** The assignment open in the Course panel, when the caller submits to it (a student): the code panel offers "Submit". */
export function submittable(state: Readonly<AppState>): Assignment | null {
  const c = state.course;
  if (!c.open || !c.current || c.current.role !== 'student') return null;
  return c.assignments.find((a) => a.id === c.open) ?? null;
}

export function selectedMesh(state: Readonly<AppState>): Mesh | null {
  return state.meshes.find((m) => m.id === state.selectedId) ?? null;
}

export function artifactKey(jobId: string, artifact: string): string {
  return `${jobId}/${artifact}`;
}

/** A `${jobId}/${artifact}` key back into its parts. */
export function splitKey(key: string): ArtifactRef {
  const i = key.indexOf('/');
  return { jobId: key.slice(0, i), artifact: key.slice(i + 1) };
}

/** A copy of `map` with `key` set to `value`. */
export function withEntry<K, V>(map: ReadonlyMap<K, V>, key: K, value: V): Map<K, V> {
  return new Map(map).set(key, value);
}
