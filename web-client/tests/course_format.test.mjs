// Unit tests of what the Course panel works out from the server's answers
// (src/panels/course_format.ts): deadlines typed in local time sent as UTC,
// scores as text, who is stuck, the grades of several assignments as one
// table, a plugin's name from a title, the comparisons by kind of output.
// `npm run test:unit`.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { importTs } from './ts_module.mjs';

const { deadlineToUtc, pointsText, scoreText, maxPoints, firstDiagnostic, stuckStudents, gradeTable, pluginName, compareMethods } = await importTs('panels/course_format.ts');

test('a datetime-local value is the local time, sent as the UTC time the server reads', () => {
  assert.equal(deadlineToUtc(''), null);
  assert.equal(deadlineToUtc('   '), null);
  const local = '2026-12-01T23:59';
  const utc = deadlineToUtc(local);
  assert.match(utc, /^\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}Z$/);
  assert.equal(new Date(utc).getTime(), new Date(2026, 11, 1, 23, 59, 0).getTime(), 'the same instant as the local time typed');
  assert.equal(new Date(deadlineToUtc('2026-12-01T23:59:30')).getSeconds(), 30);
  assert.throws(() => deadlineToUtc('tomorrow'), /not a date and time/);
  assert.throws(() => deadlineToUtc('2026-13-45T99:99'), /not a date and time/);
});

test('points read whole or to two decimals; none is a dash', () => {
  assert.equal(pointsText(10), '10');
  assert.equal(pointsText(7.5), '7.5');
  assert.equal(pointsText(1 / 3), '0.33');
  assert.equal(pointsText(null), '—');
  assert.equal(scoreText(0, 10), '0 / 10');
  assert.equal(scoreText(null, 10), '— / 10');
  assert.equal(maxPoints({ points_per_mesh: 5, hidden_count: 2 }), 10);
});

const failed = (student, created, diagnostics, error = '') => ({ id: `${student}-${created}`, student, created, state: 'failed', build: { state: 'failed', error, diagnostics } });
const graded = (student, created) => ({ id: `${student}-${created}`, student, created, state: 'graded', build: { state: 'ok', error: '', diagnostics: [] } });

test("who is stuck: students whose latest submission did not build, with the compiler's first error", () => {
  const warning = { file: 'distance.cpp', line: 3, column: 1, severity: 'warning', message: 'unused variable' };
  const error = { file: 'distance.cpp', line: 12, column: 5, severity: 'error', message: "'flot' was not declared" };
  const subs = [
    failed('alice', '2026-01-01T10:00:00Z', [error]),
    graded('alice', '2026-01-01T11:00:00Z'), // fixed since: not stuck
    graded('bob', '2026-01-01T10:00:00Z'),
    failed('bob', '2026-01-01T12:00:00Z', [warning, error]),
    failed('carol', '2026-01-01T09:00:00Z', [], 'the build timed out'),
  ];
  assert.deepEqual(stuckStudents(subs), [
    { student: 'bob', submission: 'bob-2026-01-01T12:00:00Z', message: "distance.cpp:12:5: 'flot' was not declared" },
    { student: 'carol', submission: 'carol-2026-01-01T09:00:00Z', message: 'the build timed out' },
  ]);
  assert.equal(firstDiagnostic({ build: { diagnostics: [warning] } }), 'distance.cpp:3:1: unused variable', 'a warning when there is no error');
  assert.equal(firstDiagnostic({ build: { diagnostics: [{ ...error, line: 0 }] } }), "distance.cpp: 'flot' was not declared");
});

test('the grades of several assignments: a row per student, a cell per assignment', () => {
  const row = (login, score, n) => ({ login, name: login.toUpperCase(), score, max_score: 10, submissions: n });
  const grades = new Map([
    ['a1', { students: [row('alice', 10, 2), row('bob', null, 0)] }],
    ['a2', { students: [row('bob', 5, 1), row('carol', 0, 3)] }],
  ]);
  const table = gradeTable([{ id: 'a1' }, { id: 'a2' }, { id: 'a3' }], grades);
  assert.deepEqual(
    table.map((r) => [r.login, r.name, r.cells.map((c) => c?.score ?? 'none')]),
    [
      ['alice', 'ALICE', [10, 'none', 'none']],
      ['bob', 'BOB', ['none', 5, 'none']],
      ['carol', 'CAROL', ['none', 0, 'none']],
    ],
  );
  assert.equal(table[1].cells[0].submissions, 0, 'a student without a submission keeps their row');
});

test("a plugin's name from a title: 1 to 64 of letters, digits, _ and -", () => {
  assert.equal(pluginName('Distance from the centroid'), 'distance-from-the-centroid');
  assert.equal(pluginName('  Écart: « moyen » !'), 'ecart-moyen');
  assert.equal(pluginName('???'), 'assignment');
  const long = pluginName('x'.repeat(40) + ' ' + 'y'.repeat(40));
  assert.ok(long.length <= 64 && /^[A-Za-z0-9_-]+$/.test(long) && !long.endsWith('-'), long);
});

test('each kind of output offers its comparisons, the default first, with their tolerances', () => {
  assert.deepEqual(
    compareMethods('scalar_field').map((m) => [m.method, m.tolerance]),
    [
      ['relative', 0.03],
      ['correlation', 0.95],
    ],
  );
  assert.deepEqual(
    compareMethods('mesh').map((m) => m.method),
    ['hausdorff'],
  );
  assert.deepEqual(
    compareMethods('metrics').map((m) => m.method),
    ['tolerance'],
  );
  assert.deepEqual(compareMethods('text'), []);
});
