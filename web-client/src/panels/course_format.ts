// What the Course panel works out from the server's answers, pure: a
// deadline typed in local time as the server's UTC time, scores as text, who
// is stuck (their latest submission did not build), the grades of several
// assignments as one table, a plugin name from an assignment's title, and
// the comparisons each kind of output offers. Imports nothing at run time,
// so that unit tests load it (tests/course_format.test.mjs).
import type { Assignment, GradeRow, Grades, Submission } from '../api/courses.ts';

/**
 * A `datetime-local` input's value ("2026-12-01T23:59", local time) as the
 * server's UTC time ("2026-12-01T22:59:00Z" in Paris in winter); null when
 * empty; throws on a value that is not a time.
 */
export function deadlineToUtc(local: string): string | null {
  const text = local.trim();
  if (!text) return null;
  if (!/^\d{4}-\d{2}-\d{2}T\d{2}:\d{2}(:\d{2}(\.\d+)?)?$/.test(text)) throw new Error(`not a date and time: "${local}"`);
  // Without an offset, a date-time string is the browser's local time.
  const t = new Date(text);
  if (Number.isNaN(t.getTime())) throw new Error(`not a date and time: "${local}"`);
  return t.toISOString().replace(/\.\d{3}Z$/, 'Z');
}

/** A number of points as it reads: whole, or to two decimals at most ("7.5", "10"). */
export function pointsText(n: number | null | undefined): string {
  if (n === null || n === undefined || !Number.isFinite(n)) return '—';
  return String(Number(n.toFixed(2)));
}

/** "7.5 / 10"; "— / 10" for none. */
export function scoreText(score: number | null | undefined, max: number): string {
  return `${pointsText(score)} / ${pointsText(max)}`;
}

/** An assignment's total points. */
export function maxPoints(a: Pick<Assignment, 'points_per_mesh' | 'hidden_count'>): number {
  return a.points_per_mesh * a.hidden_count;
}

/** A compiler's first message, "file:line:column: message", or the build's error. */
export function firstDiagnostic(s: Pick<Submission, 'build'>): string {
  const diagnostics = s.build?.diagnostics ?? [];
  const d = diagnostics.find((x) => String(x.severity).includes('error')) ?? diagnostics[0];
  if (!d) return s.build?.error || 'did not build';
  const where = d.line > 0 ? `${d.file}:${d.line}${d.column > 0 ? `:${d.column}` : ''}` : d.file;
  return `${where}: ${d.message}`;
}

/** Each student's latest submission (by time, then by order given). */
export function latestPerStudent(submissions: readonly Submission[]): Submission[] {
  const latest = new Map<string, Submission>();
  for (const s of submissions) {
    const old = latest.get(s.student);
    if (!old || s.created >= old.created) latest.set(s.student, s);
  }
  return [...latest.values()];
}

/** Who is stuck: students whose latest submission did not build, with the compiler's first message. */
export function stuckStudents(submissions: readonly Submission[]): Array<{ student: string; submission: string; message: string }> {
  return latestPerStudent(submissions)
    .filter((s) => s.state === 'failed')
    .sort((a, b) => a.student.localeCompare(b.student))
    .map((s) => ({ student: s.student, submission: s.id, message: firstDiagnostic(s) }));
}

/** A row of the grades table: a student and their row of each assignment (null: none yet). */
export interface GradeTableRow {
  login: string;
  name: string;
  cells: Array<GradeRow | null>;
}

/** The grades of several assignments as one table: a row per student (in the order first met), a cell per assignment. */
export function gradeTable(assignments: readonly Pick<Assignment, 'id'>[], grades: ReadonlyMap<string, Grades>): GradeTableRow[] {
  const rows = new Map<string, GradeTableRow>();
  assignments.forEach((a, column) => {
    for (const g of grades.get(a.id)?.students ?? []) {
      let row = rows.get(g.login);
      if (!row) {
        row = { login: g.login, name: g.name, cells: assignments.map(() => null) };
        rows.set(g.login, row);
      }
      row.cells[column] = g;
      if (!row.name && g.name) row.name = g.name;
    }
  });
  return [...rows.values()];
}

/** A plugin's name (1 to 64 of A-Z a-z 0-9 _ -) from an assignment's title: "Distance from the centroid" → "distance-from-the-centroid". */
export function pluginName(title: string): string {
  const slug = title
    .normalize('NFKD')
    .replace(/[\u0300-\u036f]/g, '')
    .toLowerCase()
    .replace(/[^a-z0-9_-]+/g, '-')
    .replace(/^-+|-+$/g, '')
    .slice(0, 64)
    .replace(/-+$/, '');
  return slug || 'assignment';
}

/** A way to compare an output with the reference's, and its tolerance's default (algorithms/compare/compare_output.h). */
export interface CompareMethod {
  method: string;
  label: string;
  tolerance: number;
}

/** The comparisons an output of that kind offers, the default first. */
export function compareMethods(kind: string): CompareMethod[] {
  switch (kind) {
    case 'scalar_field':
      return [
        { method: 'relative', label: 'relative error (mean over the range)', tolerance: 0.03 },
        { method: 'correlation', label: 'correlation (Pearson)', tolerance: 0.95 },
      ];
    case 'mesh':
    case 'skeleton':
      return [{ method: 'hausdorff', label: 'Hausdorff distance (over the diagonal)', tolerance: 0.01 }];
    case 'metrics':
      return [{ method: 'tolerance', label: 'relative, per key', tolerance: 0.01 }];
    default:
      return [];
  }
}
