// A computer-graphics course in the viewer, end to end against the real
// server (--auth required) and Debian's chromium: one browser, a teacher's
// page and a student's, each in a context of its own (its own storage).
//
// Set up over REST (not under test): the teacher (`user add tina --role
// teacher`) uploads two hidden meshes and a public one and builds the
// reference, the built-in centroid_distance as a plugin (as
// tests/support/centroid_distance_plugin.h makes it). Then, in the pages:
// the teacher creates a course, enrols a roster pasted as CSV and reads the
// sign-in links as URLs (copied to the clipboard), and posts the assignment
// with the form (pictures shown, a deadline in local time sent as UTC). The
// student opens their link (their own token kept, the ticket gone from the
// address; opened again, it is refused and the page says so), finds the
// Course panel open, reads the statement rendered from Markdown, opens a
// public mesh and the starter (their own copy, in the code panel), submits a
// wrong solution from the code panel, code that does not build (its
// compiler's messages; the teacher sees who is stuck) and a right one from
// the assignment: 0 and 10 points, each hidden mesh's reason, and the
// pictures, decoded. The teacher sees them in the grades table, reads the
// code read-only, opens a graded run in the viewer (named as the student's
// in the job list), grades again, and exports the CSV, read from the
// download.
//
// The tests build on each other (one server and browser for the file).
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES (default build/samples), CHROMIUM.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { artifactsDir, launchBrowser, repo, serverBin, startServer, apiCall } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
/** A build and the runs on two hidden meshes, on a busy 2-core machine. */
const GRADING_MS = 55_000;
const TITLE = 'Distance from the centroid';

// The reference: the built-in centroid_distance as a plugin registering `name`
// (tests/support/centroid_distance_plugin.h): its header pasted over its
// include, its function renamed (a string, the field's name, kept).
function centroidDistancePlugin(name) {
  const read = (file) => fs.readFileSync(path.join(repo, 'algorithms', 'examples', file), 'utf8');
  const header = read('centroid_distance.h').replace('#pragma once\n', '');
  const include = '#include "examples/centroid_distance.h"\n';
  const cpp = read('centroid_distance.cpp');
  assert.ok(cpp.includes(include), 'centroid_distance.cpp includes its header');
  const s = cpp.replace(include, header);
  return s.replace(/centroid_distance/g, (word, at) => (s[at - 1] === '"' ? word : name));
}
const RIGHT = centroidDistancePlugin('distance');
const LINE = 'field.values[i] = float(std::pow(norm(mesh.positions[i] - c), p.exponent));';
assert.ok(RIGHT.includes(LINE), 'the line a student writes');
const variant = (to) => RIGHT.replace(LINE, to);
// Every distance 10% too far; the starter leaves the line to the student.
const WRONG = variant('field.values[i] = 1.1f * float(std::pow(norm(mesh.positions[i] - c), p.exponent));');
const BROKEN = variant('field.values[i] = flot(norm(mesh.positions[i] - c));');
const STARTER = variant('field.values[i] = 0.0f;  // TODO: the distance of vertex i from the centroid c, to the power p.exponent');
const STATEMENT = '# Distances\n\nColour each vertex by its **distance** from the centroid, raised to `exponent`.\n\n- one value a vertex\n- graded on two hidden meshes\n';

let server = null;
let browser = null;
let tina = null; // the teacher's token
const ids = {}; // meshes, the reference plugin, the course, the assignment
let link = null; // the student's sign-in URL
let teacher = null;
let student = null;
const problems = [];
const describeProblems = () => (problems.length ? `\npage problems:\n${problems.join('\n')}` : '');

const api = (token, method, route, body, contentType) => apiCall(server.url, token, method, route, body, contentType);

/** A page of its own context, watched for errors once `name` is signed in. */
async function newPage(name, options = {}) {
  const context = await browser.newContext({ viewport: { width: 1280, height: 800 }, acceptDownloads: true, ...options });
  const page = await context.newPage();
  page.on('pageerror', (e) => problems.push(`${name}: pageerror: ${e.message}`));
  page.on('response', (r) => {
    // Before sign-in the server refuses (the token form asks): not a problem.
    if (r.status() >= 400 && !(r.status() === 401 && page.__signingIn)) problems.push(`${name}: HTTP ${r.status()}: ${r.request().method()} ${r.url()}`);
  });
  return page;
}

const course = (page) => page.locator('#course');

/** Waits for the Course panel's status line to say `pattern`. */
async function courseSays(page, pattern, timeout = 30_000) {
  await page
    .waitForFunction((source) => new RegExp(source).test(document.querySelector('#course .course-status')?.textContent ?? ''), pattern.source, { timeout })
    .catch(async (e) => {
      throw new Error(`the Course panel never said ${pattern}: "${await course(page).locator('.course-status').textContent()}" (${e.message})${describeProblems()}`);
    });
}

before(async () => {
  server = await startServer({ tmpPrefix: 'cgview-course-', extraArgs: ['--auth', 'required', '--job-timeout-s', '120'] });
  tina = execFileSync(serverBin, ['--data-dir', server.dataDir, 'user', 'add', 'tina', '--role', 'teacher'], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'ignore'] }).trim();
  assert.match(tina, /^cgv_/);
  const [launched] = await Promise.all([
    launchBrowser(),
    (async () => {
      for (const name of ['elephant', 'blobby', 'sphere']) {
        const up = await api(tina, 'POST', `/meshes?name=${name}.off`, fs.readFileSync(path.join(samples, `${name}.off`)), 'application/octet-stream');
        assert.equal(up.status, 201, up.text);
        ids[name] = up.json.id;
      }
      const plugin = await api(tina, 'POST', '/plugins', { name: 'reference', source: RIGHT });
      assert.equal(plugin.status, 201, plugin.text);
      ids.reference = plugin.json.id;
      const build = await api(tina, 'POST', `/plugins/${ids.reference}/build`);
      assert.equal(build.status, 202, build.text);
      for (let job = build.json; ; await new Promise((r) => setTimeout(r, 200))) {
        job = (await api(tina, 'GET', `/jobs/${build.json.id}`)).json;
        if (job.state === 'done') break;
        assert.ok(job.state === 'queued' || job.state === 'running', `the reference builds: ${JSON.stringify(job)}\n${server.log()}`);
      }
      assert.equal((await api(tina, 'GET', `/plugins/${ids.reference}`)).json.build.state, 'ok');
    })(),
  ]);
  browser = launched;
});

after(async () => {
  await browser?.close();
  await server?.stop();
});

test('the teacher creates a course in the page and enrols a roster: the sign-in links are URLs to hand out', async () => {
  const origin = server.url;
  teacher = await newPage('teacher', { permissions: ['clipboard-read', 'clipboard-write'] });
  teacher.__signingIn = true;
  await teacher.goto(origin + '/');
  await teacher.locator('#token-form input').fill(tina);
  await Promise.all([teacher.waitForEvent('load'), teacher.locator('#token-form button').click()]);
  await teacher.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30_000 });
  teacher.__signingIn = false;

  // Signed in but in no course yet: "Course" is there, the panel closed.
  const toggle = teacher.getByRole('button', { name: 'Course', exact: true });
  await toggle.waitFor();
  assert.equal(await toggle.getAttribute('aria-pressed'), 'false');
  await toggle.click();
  await course(teacher).locator('.course-none').getByText('You are in no course yet.').waitFor();
  await course(teacher).locator('.course-create input').fill('Computer Graphics 2027');
  await course(teacher).locator('.course-create button').click();
  await courseSays(teacher, /^Created Computer Graphics 2027/);
  assert.equal(await course(teacher).locator('.course-role').textContent(), 'teacher');
  const courses = (await api(tina, 'GET', '/courses')).json;
  assert.equal(courses.length, 1);
  ids.course = courses[0].id;
  assert.equal(await course(teacher).locator('.course-tab[aria-pressed="true"]').textContent(), 'Members');
  assert.match(await course(teacher).locator('.course-join-code code').textContent(), /^[0-9a-f]{10}$/);

  // A roster pasted from a spreadsheet: a header, a name with a comma.
  await course(teacher).locator('.course-roster textarea').fill('login,name\nsam,"Sam, S."\nkim,Kim K\n');
  await course(teacher).locator('.course-roster button[type="submit"]').click();
  await courseSays(teacher, /^Enrolled\. 2 new accounts/);
  const rows = course(teacher).locator('.course-members tbody tr');
  assert.deepEqual(await rows.evaluateAll((trs) => trs.map((tr) => [...tr.cells].slice(0, 3).map((td) => td.textContent))), [
    ['tina', '', 'teacher'],
    ['kim', 'Kim K', 'student'],
    ['sam', 'Sam, S.', 'student'],
  ]);
  const url = course(teacher).locator('.course-links li[data-user="sam"] input.course-link-url');
  link = await url.inputValue();
  assert.match(link, new RegExp(`^${origin.replace(/[.]/g, '\\.')}/#ticket=cgl_[0-9a-f]{16}_[0-9a-f]{64}$`));
  assert.match(await course(teacher).locator('.course-links li[data-user="kim"] input.course-link-url').inputValue(), /#ticket=cgl_/);
  await course(teacher).locator('.course-links li[data-user="sam"] .course-link-copy').click();
  await course(teacher).locator('.course-links li[data-user="sam"] .course-link-copy', { hasText: 'Copied' }).waitFor();
  assert.equal(await teacher.evaluate(() => navigator.clipboard.readText()), link);
  await teacher.screenshot({ path: path.join(artifactsDir, 'e2e-course-members.png') });
  assert.equal(problems.length, 0, describeProblems());
});

test('the teacher posts the assignment with the form: meshes, reference, comparison, points, deadline, pictures', async () => {
  assert.ok(link, 'the roster was enrolled');
  const panel = course(teacher);
  await panel.locator('.course-tab[data-tab="new"]').click();
  const form = panel.locator('form.assignment-form');
  // The reference is the teacher's one built plugin, chosen already; its output a scalar field.
  await form.locator(`select[name="reference"] option[value="${ids.reference}"]`).waitFor({ state: 'attached' });
  assert.equal(await form.locator('select[name="reference"]').inputValue(), ids.reference);
  assert.deepEqual(await form.locator('select[name="method"] option').evaluateAll((os) => os.map((o) => o.value)), ['relative', 'correlation']);
  assert.equal(await form.locator('input[name="tolerance"]').getAttribute('placeholder'), '0.03');
  // The teacher's own meshes first; the samples are others' (the system's), named so.
  const own = await form.locator('.assignment-mesh-choice > table tbody tr').evaluateAll((trs) => trs.map((tr) => tr.dataset.meshId));
  assert.deepEqual(own.sort(), [ids.elephant, ids.blobby, ids.sphere].sort());
  assert.match(await form.locator('.assignment-mesh-choice details tbody tr .owner').first().textContent(), / — system$/);

  await form.locator('input[name="title"]').fill(TITLE);
  await form.locator('textarea[name="statement"]').fill(STATEMENT);
  await form.locator('textarea[name="starter"]').fill(STARTER);
  await form.locator(`tr[data-mesh-id="${ids.sphere}"] input[name="public"]`).check();
  await form.locator(`tr[data-mesh-id="${ids.elephant}"] input[name="hidden"]`).check();
  await form.locator(`tr[data-mesh-id="${ids.blobby}"] input[name="hidden"]`).check();
  await form.locator('select[name="method"]').selectOption('relative');
  await form.locator('input[name="tolerance"]').fill('0.03');
  await form.locator('input[name="points"]').fill('5');
  await form.locator('input[name="time_limit"]').fill('60');
  await form.locator('input[name="deadline"]').fill('2030-12-01T23:59');
  await form.locator('input[name="pictures"]').check();
  await form.screenshot({ path: path.join(artifactsDir, 'e2e-course-form.png') });
  await form.locator('button.assignment-post').click();
  await courseSays(teacher, /^Posted Distance from the centroid: the reference runs on its 2 hidden meshes/);
  await panel.locator('.assignment-view .assignment-title', { hasText: TITLE }).waitFor();

  const [a] = (await api(tina, 'GET', `/courses/${ids.course}/assignments`)).json;
  ids.assignment = a.id;
  assert.equal(a.title, TITLE);
  assert.equal(a.statement, STATEMENT);
  assert.equal(a.starter, STARTER);
  assert.deepEqual(a.public_meshes, [ids.sphere]);
  assert.deepEqual([...a.hidden_meshes].sort(), [ids.elephant, ids.blobby].sort());
  assert.equal(a.reference_plugin, ids.reference);
  assert.equal(a.compare.method, 'relative');
  assert.equal(a.compare.tolerance, 0.03);
  assert.equal(a.points_per_mesh, 5);
  assert.equal(a.time_limit_s, 60);
  assert.equal(a.show_pictures, true);
  // The deadline typed in the browser's local time, sent as UTC.
  const expected = await teacher.evaluate(() => new Date('2030-12-01T23:59').toISOString().replace(/\.000Z$/, 'Z'));
  assert.equal(a.deadline, expected);
  assert.match(await panel.locator('.assignment-meta').textContent(), /10 points: 5 for each of 2 hidden meshes · pictures shown/);
  assert.equal(problems.length, 0, describeProblems());
});

test('the student signs in with the link, reads the statement, opens a public mesh and the starter', async () => {
  assert.ok(ids.assignment, 'the assignment was posted');
  student = await newPage('student');
  await student.goto(link);
  await student.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30_000 });
  // The link's token is the student's own, kept; the ticket is gone from the address.
  const token = await student.evaluate(() => localStorage.getItem('cgview.token'));
  assert.match(token, /^cgv_/);
  assert.ok(!student.url().includes('ticket'), student.url());
  assert.equal((await api(token, 'GET', '/me')).json.user, 'sam');
  assert.equal(await student.evaluate(() => sessionStorage.getItem('cgview.session')), null, 'a token, not a session');
  // The link works once: opened again elsewhere, the page says so where it asks for a token.
  const elsewhere = await browser.newContext();
  const again = await elsewhere.newPage();
  await again.goto(link);
  await again
    .getByRole('form', { name: 'Sign in to CGView' })
    .filter({ hasText: 'This sign-in link is used or expired: ask your teacher for another' })
    .waitFor({ timeout: 30_000 });
  assert.equal(await again.evaluate(() => localStorage.getItem('cgview.token')), null);
  await elsewhere.close();

  // The Course panel is open on the course; the assignment listed.
  assert.equal(await student.getByRole('button', { name: 'Course', exact: true }).getAttribute('aria-pressed'), 'true');
  const panel = course(student);
  assert.equal(await panel.locator('.course-role').textContent(), 'student');
  assert.equal(await panel.locator('.course-tabs').isHidden(), true, 'a student has no staff views');
  const item = panel.locator(`li.course-assignment[data-assignment-id="${ids.assignment}"]`);
  assert.match(await item.textContent(), /Distance from the centroid10 points · due /);
  await item.locator('button').click();

  // The statement, rendered from Markdown.
  const statement = panel.locator('.assignment-statement');
  await statement.locator('h1').waitFor();
  assert.equal(await statement.locator('h1').textContent(), 'Distances');
  assert.equal(await statement.locator('strong').textContent(), 'distance');
  assert.equal(await statement.locator('code').textContent(), 'exponent');
  assert.equal(await statement.locator('li').count(), 2);
  assert.match(await panel.locator('.assignment-meta').textContent(), /^Due .*2030.* · 10 points: 5 for each of 2 hidden meshes/);

  // A public mesh opens in the viewer; no hidden mesh is listed.
  await panel.locator(`.assignment-meshes li[data-mesh-id="${ids.sphere}"] button`).click();
  await student.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, ids.sphere, { timeout: 60_000 });
  const listed = await student.locator('#mesh-list li.mesh').evaluateAll((lis) => lis.map((li) => li.dataset.meshId));
  assert.ok(listed.includes(ids.sphere) && !listed.includes(ids.elephant) && !listed.includes(ids.blobby), JSON.stringify(listed));

  // The starter: the student's own copy, in the code panel, with "Submit" beside it.
  await panel.locator('.assignment-starter').click();
  await courseSays(student, /^The starter is yours now/);
  const code = student.locator('#playground');
  assert.equal(await code.isVisible(), true);
  await code.locator('.cm-content').waitFor();
  // The editor draws the lines in view only: its first, and the whole file as the server keeps it.
  const firstLine = STARTER.slice(0, STARTER.indexOf('\n'));
  await student.waitForFunction((line) => document.querySelector('#playground .cm-line')?.textContent === line, firstLine);
  assert.equal(await code.locator('.playground-name').inputValue(), 'distance-from-the-centroid');
  assert.equal(await code.locator('.playground-assignment-title').textContent(), `Assignment: ${TITLE}`);
  const plugins = (await api(token, 'GET', '/plugins')).json.plugins.filter((p) => p.owner === 'sam');
  assert.deepEqual(
    plugins.map((p) => p.name),
    ['distance-from-the-centroid'],
  );
  assert.equal((await api(token, 'GET', `/plugins/${plugins[0].id}`)).json.source, STARTER);
  assert.equal(problems.length, 0, describeProblems());
});

/** Replaces the code panel's text as a paste does (all selected first). */
async function paste(page, text) {
  const content = page.locator('#playground .cm-content');
  await content.click();
  await page.keyboard.press('ControlOrMeta+a');
  await content.evaluate((node, t) => {
    const data = new DataTransfer();
    data.setData('text/plain', t);
    node.dispatchEvent(new ClipboardEvent('paste', { clipboardData: data, bubbles: true, cancelable: true }));
  }, text);
}

/** The student's submissions as the panel lists them, newest first, once `count` are graded. */
async function graded(count) {
  await student
    .waitForFunction((n) => document.querySelectorAll('#course li.submission[data-state="graded"]').length >= n, count, { timeout: GRADING_MS })
    .catch(async (e) => {
      const subs = (await api(tina, 'GET', `/assignments/${ids.assignment}/submissions`)).json;
      throw new Error(`${count} graded submissions never showed: ${e.message}\n${JSON.stringify(subs)}${describeProblems()}`);
    });
  return course(student).locator('li.submission');
}

/** The pictures shown in a submission's entry, once each has decoded: their widths. */
async function picturesDecoded(entry) {
  const pictures = entry.locator('img.submission-picture');
  await entry.page().waitForFunction(
    (el) => {
      const imgs = [...el.querySelectorAll('img.submission-picture')];
      return imgs.length > 0 && imgs.every((i) => i.complete && i.dataset.fetching === undefined && i.naturalWidth > 0);
    },
    await entry.elementHandle(),
    { timeout: 30_000 },
  );
  return pictures.evaluateAll((imgs) => imgs.map((i) => [i.dataset.which, i.naturalWidth, i.naturalHeight]));
}

test('a wrong solution, submitted from the code panel, scores 0 with each hidden mesh’s reason and the pictures', async () => {
  assert.ok(student, 'the student is signed in');
  await paste(student, WRONG);
  await student.waitForFunction(() => document.querySelector('#playground .cm-content')?.textContent.includes('1.1f * float('));
  await student.locator('#playground .playground-submit').click();
  await student.locator('#playground .playground-status', { hasText: `Submitted to ${TITLE}` }).waitFor({ timeout: 30_000 });
  const list = await graded(1);
  const entry = list.first();
  assert.equal(await entry.locator('.submission-score').textContent(), '0 / 10');
  assert.equal(await entry.getAttribute('data-late'), 'false');
  const results = await entry
    .locator('.submission-result')
    .evaluateAll((lis) =>
      lis.map((li) => [li.querySelector('.result-mesh').textContent, li.querySelector('.result-points').textContent, li.querySelector('.result-reason').textContent]),
    );
  assert.equal(results.length, 2);
  for (const [mesh, points, reason] of results) {
    assert.match(mesh, /^hidden [12]$/);
    assert.equal(points, '0 / 5');
    assert.match(reason, /mean error .* of the range over the 3% allowed/);
  }
  const pictures = await picturesDecoded(entry);
  assert.deepEqual(
    pictures.map(([which]) => which),
    ['result', 'reference', 'difference', 'result', 'reference', 'difference'],
  );
  for (const [which, width, height] of pictures) assert.ok(width === 320 && height === 240, `${which}: ${width}×${height}`);
  // What the student sent is what the server graded.
  const [sub] = (await api(tina, 'GET', `/assignments/${ids.assignment}/submissions`)).json;
  assert.equal((await api(tina, 'GET', `/submissions/${sub.id}`)).json.source, WRONG);
  assert.equal(problems.length, 0, describeProblems());
});

test("code that does not build: the student reads the compiler's messages, the teacher sees who is stuck", async () => {
  assert.ok(student, 'the student is signed in');
  await paste(student, BROKEN);
  await student.waitForFunction(() => document.querySelector('#playground .cm-content')?.textContent.includes('flot('));
  await student.locator('#playground .playground-submit').click();
  const entry = course(student).locator('li.submission[data-state="failed"]');
  await entry.waitFor({ timeout: GRADING_MS });
  assert.equal(await course(student).locator('li.submission').first().getAttribute('data-state'), 'failed', 'the newest first');
  assert.equal(await entry.locator('.submission-state').textContent(), 'did not build');
  assert.match(await entry.locator('.submission-error').textContent(), /^Does not build: .*:\d+:\d+: .*.flot. was not declared/);
  const errors = await entry.locator('.submission-diagnostics li[data-severity="error"]').allTextContents();
  assert.ok(
    errors.some((e) => /.flot. was not declared/.test(e)),
    JSON.stringify(errors),
  );
  assert.equal(await entry.locator('.submission-result').count(), 0, 'no run, no score per mesh');

  // The teacher, back on the assignment, sees sam stuck on the compiler's first message.
  await course(teacher).locator('.course-tab[data-tab="assignments"]').click();
  const stuck = course(teacher).locator('.assignment-stuck li[data-student="sam"]');
  await stuck.waitFor({ timeout: 30_000 });
  assert.match(await stuck.locator('.stuck-message').textContent(), /:\d+:\d+: .*.flot. was not declared/);
  assert.equal(problems.length, 0, describeProblems());
});

test('the right one, submitted from the assignment, scores 10; all are listed, with their pictures', async () => {
  assert.ok(student, 'the student is signed in');
  await paste(student, RIGHT);
  await student.waitForFunction(() => !document.querySelector('#playground .cm-content')?.textContent.includes('1.1f * float('));
  await course(student).locator('.assignment-submit').click();
  const list = await graded(2);
  assert.equal(await list.count(), 3);
  const newest = list.first();
  assert.equal(await newest.locator('.submission-score').textContent(), '10 / 10');
  const reasons = await newest.locator('.result-reason').allTextContents();
  assert.equal(reasons.length, 2);
  for (const r of reasons) assert.match(r, /^within tolerance: mean error .* of the range \(3% allowed\)$/);
  const pictures = await picturesDecoded(newest);
  assert.equal(pictures.length, 6);
  await student.locator('#course .assignment-view').screenshot({ path: path.join(artifactsDir, 'e2e-course-student.png') });
  await student.screenshot({ path: path.join(artifactsDir, 'e2e-course-student-page.png') });
  // The first one's pictures come back on demand (the one that did not build has none).
  assert.equal(await list.nth(1).locator('.submission-show-pictures').count(), 0);
  const first = list.nth(2);
  assert.equal(await first.locator('.submission-score').textContent(), '0 / 10');
  await first.locator('.submission-show-pictures').click();
  assert.equal((await picturesDecoded(course(student).locator('li.submission.picked'))).length, 6);
  assert.equal(await course(student).locator('li.submission.picked .submission-score').textContent(), '0 / 10');
  assert.equal(problems.length, 0, describeProblems());
});

test('the teacher sees the submissions in the grades table, reads the code, opens a run in the viewer, grades again and exports the CSV', async () => {
  assert.ok(teacher && student, 'both pages are open');
  const panel = course(teacher);
  await panel.locator('.course-tab[data-tab="grades"]').click();
  const cell = panel.locator(`table.grades tr[data-login="sam"] td[data-assignment-id="${ids.assignment}"]`);
  await teacher.waitForFunction(
    (sel) => document.querySelector(sel)?.dataset.submissions === '3',
    `#course table.grades tr[data-login="sam"] td[data-assignment-id="${ids.assignment}"]`,
    {
      timeout: 30_000,
    },
  );
  assert.equal(await cell.locator('.grades-score').textContent(), '10 / 10');
  assert.equal(await cell.locator('.grades-count').textContent(), '3 submissions');
  assert.equal(await panel.locator('table.grades tr[data-login="sam"] th').textContent(), 'Sam, S. (sam)');
  await teacher.screenshot({ path: path.join(artifactsDir, 'e2e-course-grades.png') });
  assert.equal(await panel.locator(`table.grades tr[data-login="kim"] td[data-assignment-id="${ids.assignment}"]`).textContent(), '—');

  // The CSV, as a gradebook imports it, read from the download.
  const [download] = await Promise.all([teacher.waitForEvent('download'), panel.locator(`th[data-assignment-id="${ids.assignment}"] .grades-export`).click()]);
  assert.equal(download.suggestedFilename(), `grades-${ids.assignment}.csv`);
  const csv = fs.readFileSync(await download.path(), 'utf8');
  fs.writeFileSync(path.join(artifactsDir, 'e2e-course-grades.csv'), csv);
  const lines = csv.trim().split('\n');
  assert.equal(lines[0], 'Student,ID,SIS User ID,SIS Login ID,Section,Distance from the centroid (10 points),Submissions,Submitted,Late');
  assert.match(lines.find((l) => l.includes(',sam,')) ?? '', /^"Sam, S\.",,sam,sam,,10,3,\d{4}-\d{2}-\d{2}T[0-9:]+Z,$/);
  assert.match(lines.find((l) => l.includes(',kim,')) ?? '', /^Kim K,,kim,kim,,,0,,$/);

  // The cell opens the submission counted: its code, read-only, and its run on a hidden mesh in the viewer.
  await cell.locator('.grades-open').click();
  const picked = panel.locator('li.submission.picked');
  await picked.waitFor();
  assert.equal(await picked.locator('.submission-student').textContent(), 'sam');
  assert.equal(await picked.locator('.submission-score').textContent(), '10 / 10');
  assert.equal(await panel.locator('li.submission').count(), 3);
  assert.match(await panel.locator('.assignment-stuck').textContent(), /Nobody/, 'sam is stuck no more');
  await picked.locator('.submission-code').click();
  const code = teacher.locator('#playground');
  await code.locator('.cm-content').waitFor();
  await teacher.waitForFunction(() => /sam's submission of .* read-only/.test(document.querySelector('#playground .playground-status')?.textContent ?? ''));
  assert.equal(await code.locator('.cm-content').getAttribute('aria-readonly'), 'true');
  assert.equal(await code.locator('.playground-name').inputValue(), 'sam-submission');
  assert.ok(await code.locator('.playground-build').isDisabled());
  const subId = await picked.getAttribute('data-submission-id');
  const staffView = (await api(tina, 'GET', `/submissions/${subId}`)).json;
  await picked.locator('.submission-result').first().locator('.result-open').click();
  await teacher.waitForFunction((job) => window.__cgview.lastField?.jobId === job, staffView.results[0].job, { timeout: 60_000 });
  assert.equal(await teacher.evaluate(() => window.__cgview.lastField.meshId), staffView.results[0].mesh_id);
  assert.ok([ids.elephant, ids.blobby].includes(staffView.results[0].mesh_id), "a hidden mesh, the teacher's own");
  // Beside it in the job list: the student's run, named as theirs.
  assert.equal(await teacher.locator(`#jobs li.job[data-job-id="${staffView.results[0].job}"] .job-owner`).textContent(), 'grading:sam');

  await teacher.screenshot({ path: path.join(artifactsDir, 'e2e-course-teacher.png') });

  // Grade again: the same scores.
  await panel.locator('.assignment-regrade').click();
  await courseSays(teacher, /^Grading 2 submissions again/);
  await teacher.waitForFunction(() => [...document.querySelectorAll('#course li.submission')].every((li) => li.dataset.state === 'graded' || li.dataset.state === 'failed'), null, {
    timeout: GRADING_MS,
  });
  assert.deepEqual(await panel.locator('li.submission .submission-score').allTextContents(), ['10 / 10', '0 / 10', '0 / 10']);
  assert.equal(problems.length, 0, describeProblems());
});
