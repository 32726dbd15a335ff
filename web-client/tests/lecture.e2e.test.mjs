// A live lecture in the viewer, end to end against the real server (--auth
// required) and Debian's chromium: one browser, a page for the teacher
// (tina) and one for each student (sam, kim), each in a context of its own.
//
// Set up over REST (not under test): tina's course with sam and kim, her
// mesh and a field on it (centroid_distance). Then, in the pages: tina
// presents to the course and sam follows; sam's canvas shows tina's camera
// after she orbits, and her field once she shows it (the pictures compared,
// pixel by pixel, within a tolerance; and a picture without the field is
// not one with it). Sam detaches and looks around (his picture differs from
// tina's), and "Follow again" brings tina's view back; taking the camera
// detaches him too. Kim joins late, after tina changed the view, and has it
// at once. Sam raises a hand on the mesh: tina sees his marker with his name
// and the list, shows it to all, and kim sees it. Tina's code panel's text
// reaches the followers, read-only, and goes when she closes it. A
// follower's room_set is refused (forbidden). Tina ends the lecture and
// shares what it showed with the course; kim replays it: the end of the recording is tina's last view, the moment
// before the field is her view then (pictures compared again), it plays at
// the speed chosen, and taking the camera stops it there.
//
// The tests build on each other (one server and browser for the file).
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES (default build/samples), CHROMIUM.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { artifactsDir, hueStats, launchBrowser, orbitDrag, pictureDifference, pngPixels, repo, serverBin, settle, startServer, apiCall } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
/** Every page's view pinned to this size (the pictures compared are the canvas's own pixels). */
const VIEW = { width: 400, height: 300 };
/** Two pictures match when both hold, over the pixels that are not background in both (display.e2e's measure). */

let server = null;
let browser = null;
const tokens = {};
const ids = {};
const pages = {};
const problems = [];
const describeProblems = () => (problems.length ? `\npage problems:\n${problems.join('\n')}` : '');
/** Tina's pictures: after her first orbit (no field), with the field, and her last view. */
const shots = {};

const api = (token, method, route, body, contentType) => apiCall(server.url, token, method, route, body, contentType);

function addUser(name, ...role) {
  const token = execFileSync(serverBin, ['--data-dir', server.dataDir, 'user', 'add', name, ...role], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'ignore'] }).trim();
  assert.match(token, /^cgv_/);
  return token;
}

/** A page signed in as `name` (its token in the page's storage), in a context of its own, its view pinned to VIEW. */
async function openAs(name) {
  const context = await browser.newContext({ viewport: { width: 1280, height: 800 }, acceptDownloads: true });
  await context.addInitScript((token) => localStorage.setItem('cgview.token', token), tokens[name]);
  const page = await context.newPage();
  page.on('pageerror', (e) => problems.push(`${name}: pageerror: ${e.message}`));
  page.on('console', (m) => {
    if (m.type() === 'error') problems.push(`${name}: console.error: ${m.text()}`);
  });
  page.on('response', (r) => {
    if (r.status() >= 400) problems.push(`${name}: HTTP ${r.status()}: ${r.request().method()} ${r.url()}`);
  });
  await page.goto(server.url + '/');
  await page.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30_000 });
  // The view in the bottom right corner, over the right sidebar: the panels stay clickable. The field's
  // legend (over the view, not in the canvas) hidden, so that a click in the middle of the view reaches it.
  await page.addStyleTag({
    content: `#viewport { position: fixed !important; right: 0; bottom: 0; left: auto; top: auto; z-index: 1000;
      width: ${VIEW.width}px !important; height: ${VIEW.height}px !important; }
      #viewport .legend { display: none !important; }`,
  });
  await page.waitForFunction(({ width, height }) => {
    const c = document.querySelector('#viewport canvas');
    return c && c.width === width && c.height === height;
  }, VIEW);
  pages[name] = page;
  return page;
}

const lecture = (page) => page.evaluate(() => window.__cgview.lecture());
const button = (page, name) => page.locator('section.lecture').getByRole('button', { name, exact: true });

/** Waits until `check(lecture state)` holds on the page. */
async function lectureIs(page, check, what, timeout = 30_000) {
  await page.waitForFunction(check, null, { timeout }).catch(async (e) => {
    throw new Error(`${what}: ${JSON.stringify(await lecture(page))} (${e.message})${describeProblems()}`);
  });
}

/** The canvas as a PNG, through the page's Screenshot button (a download). */
async function screenshot(page, name) {
  await settle(page);
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#screenshot')]);
  const file = path.join(artifactsDir, `lecture-${name}.png`);
  await download.saveAs(file);
  return fs.readFileSync(file);
}

const difference = (page, a, b) => pictureDifference(page, a, b).then((d) => (assert.ok(!d.sizes, `pictures of one size: ${d.sizes}`), d));
const matches = (d) => d.pixels > 1000 && d.same;

async function assertSamePicture(page, a, b, what) {
  const d = await difference(page, a, b);
  assert.ok(matches(d), `${what}: the pictures differ: ${JSON.stringify(d)}`);
}

async function assertOtherPicture(page, a, b, what) {
  const d = await difference(page, a, b);
  assert.ok(!matches(d), `${what}: the pictures should differ: ${JSON.stringify(d)}`);
}

/** The camera as the page's navigation reports it. */
const cameraOf = (page) => page.evaluate(() => window.__cgview.camera());
const near = (a, b) => a.every((x, i) => Math.abs(x - b[i]) < 1e-6 * Math.max(1, Math.abs(b[i])));

/** Waits until the follower's view is shown and its camera is `camera` (the presenter's, or a recorded one). */
async function cameraReaches(page, camera, what, timeout = 30_000) {
  const deadline = Date.now() + timeout;
  for (;;) {
    const [mine, l] = await Promise.all([cameraOf(page), lecture(page)]);
    if (!l.busy && near(mine.position, camera.position) && near(mine.target, camera.target)) return;
    if (Date.now() > deadline) throw new Error(`${what}: the camera never reached ${JSON.stringify(camera)}: ${JSON.stringify(mine)} ${JSON.stringify(l)}${describeProblems()}`);
    await new Promise((r) => setTimeout(r, 50));
  }
}

/** Waits until the follower shows the presenter's camera, then compares their pictures. */
async function followerMatches(follower, name, what) {
  const tina = pages.tina;
  await settle(tina);
  const camera = await cameraOf(tina);
  await cameraReaches(follower, camera, what);
  const [a, b] = await Promise.all([screenshot(tina, `${name}-tina`), screenshot(follower, `${name}-follower`)]);
  await assertSamePicture(tina, a, b, what);
  return a;
}

before(async () => {
  for (const [what, file] of [
    ['the server', serverBin],
    ['the built web client', path.join(repo, 'web-client', 'dist', 'index.html')],
  ]) {
    if (!fs.existsSync(file)) throw new Error(`${what} is missing: ${file}`);
  }
  fs.mkdirSync(artifactsDir, { recursive: true });
  server = await startServer({ tmpPrefix: 'cgview-lecture-', extraArgs: ['--auth', 'required'] });
  tokens.tina = addUser('tina', '--role', 'teacher');
  tokens.sam = addUser('sam');
  tokens.kim = addUser('kim');
  const [launched] = await Promise.all([
    launchBrowser(),
    (async () => {
      const course = await api(tokens.tina, 'POST', '/courses', { title: 'Geometry 101' });
      assert.equal(course.status, 201, course.text);
      ids.course = course.json.id;
      const members = await api(tokens.tina, 'POST', `/courses/${ids.course}/members`, ['sam', 'kim']);
      assert.ok(members.status < 300, members.text);
      const up = await api(tokens.tina, 'POST', '/meshes?name=elephant.off', fs.readFileSync(path.join(samples, 'elephant.off')), 'application/octet-stream');
      assert.equal(up.status, 201, up.text);
      ids.mesh = up.json.id;
      const job = await api(tokens.tina, 'POST', '/jobs', { algorithm: 'centroid_distance', inputs: { mesh: ids.mesh }, params: {} });
      assert.equal(job.status, 201, job.text);
      ids.job = job.json.id;
      for (let j = job.json; j.state !== 'done'; await new Promise((r) => setTimeout(r, 100))) {
        j = (await api(tokens.tina, 'GET', `/jobs/${ids.job}`)).json;
        assert.ok(['queued', 'running', 'done'].includes(j.state), `the field's job: ${JSON.stringify(j)}`);
      }
    })(),
  ]);
  browser = launched;
});

after(async () => {
  await browser?.close();
  await server?.stop();
});

test("the teacher presents to the course: a follower's canvas shows her camera, then her field", async () => {
  const [tina, sam] = await Promise.all([openAs('tina'), openAs('sam')]);
  // Tina shows her mesh and presents; the Course panel is open for both (they are in a course).
  await tina.locator(`#mesh-list li.mesh[data-mesh-id="${ids.mesh}"]`).click();
  await tina.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, ids.mesh, { timeout: 60_000 });
  await button(tina, 'Present to the course').click();
  await lectureIs(tina, () => window.__cgview.lecture().role === 'presenter', 'tina presents');
  await tina.locator('section.lecture .lecture-followers', { hasText: '0 following' }).waitFor();

  // Sam finds the live lecture in the course's list and follows: tina's mesh, which is not his, shows.
  await button(sam, 'Follow').click();
  await lectureIs(sam, () => window.__cgview.lecture().role === 'follower', 'sam follows');
  await sam.waitForFunction((id) => window.__cgview.lastLoaded?.id === id, ids.mesh, { timeout: 60_000 });
  await tina.locator('section.lecture .lecture-followers', { hasText: '1 following' }).waitFor();

  // Tina orbits: sam's camera glides to hers, and the pictures are the same.
  await orbitDrag(tina, 80, 30);
  shots.plain = await followerMatches(sam, 'orbit', "sam's view after tina orbits");

  // Tina shows the field: sam's mesh is coloured by it too, and the picture is another than without it.
  await tina.locator(`#jobs li.job[data-job-id="${ids.job}"] button.show`).click();
  await tina.waitForFunction((job) => window.__cgview.lastField?.jobId === job, ids.job, { timeout: 30_000 });
  await sam.waitForFunction((job) => window.__cgview.lastField?.jobId === job, ids.job, { timeout: 30_000 });
  shots.field = await followerMatches(sam, 'field', "sam's view with tina's field");
  await assertOtherPicture(tina, shots.plain, shots.field, 'the field changes the picture');
  assert.ok(hueStats(await pngPixels(sam, shots.field)).distinct >= 2, 'a colour map shows several hues');
  assert.deepEqual(await sam.evaluate(() => window.__cgview.lastField.range), await tina.evaluate(() => window.__cgview.lastField.range), 'the same range');
  assert.equal(problems.length, 0, describeProblems());
});

test('a follower detaches and looks around, and "Follow again" brings the teacher\'s view back', async () => {
  const { tina, sam } = pages;
  assert.ok(tina && sam, 'the lecture is on');
  await button(sam, 'Detach').click();
  await lectureIs(sam, () => !window.__cgview.lecture().attached, 'sam is detached');
  await orbitDrag(sam, -120, 10);
  await orbitDrag(tina, 0, 50);
  await settle(tina);
  await settle(sam);
  const camera = await cameraOf(tina);
  assert.ok(!near((await cameraOf(sam)).position, camera.position), "detached, sam's camera is his own");
  const [a, b] = await Promise.all([screenshot(tina, 'detached-tina'), screenshot(sam, 'detached-sam')]);
  await assertOtherPicture(tina, a, b, "detached, sam's picture is his own");

  await button(sam, 'Follow again').click();
  await lectureIs(sam, () => window.__cgview.lecture().attached, 'sam follows again');
  await followerMatches(sam, 'again', "sam's view after Follow again");

  // Taking the camera detaches too.
  await orbitDrag(sam, 40, 0);
  await lectureIs(sam, () => !window.__cgview.lecture().attached, 'sam took the camera: detached');
  await button(sam, 'Follow again').click();
  await followerMatches(sam, 'again2', "sam's view after Follow again, once more");
  assert.equal(problems.length, 0, describeProblems());
});

test('a student who joins late gets the current view at once', async () => {
  const { tina, sam } = pages;
  assert.ok(tina && sam, 'the lecture is on');
  // Tina changes the view before kim comes: another camera, the flat display mode.
  await orbitDrag(tina, -60, -20);
  await tina.selectOption('#display-mode', 'flat');
  await tina.waitForFunction(() => window.__cgview.display?.mode === 'flat');
  await settle(tina);
  const kim = await openAs('kim');
  await button(kim, 'Follow').click();
  await lectureIs(kim, () => window.__cgview.lecture().role === 'follower', 'kim follows');
  await kim.waitForFunction((job) => window.__cgview.lastField?.jobId === job && window.__cgview.display?.mode === 'flat', ids.job, { timeout: 60_000 });
  shots.last = await followerMatches(kim, 'late', "kim's view, joined late");
  await followerMatches(sam, 'late-sam', "sam's view meanwhile");
  await tina.locator('section.lecture .lecture-followers', { hasText: '2 following' }).waitFor();
  assert.equal(problems.length, 0, describeProblems());
});

test('a follower raises a hand on the mesh: the teacher sees it with the name and shows it to all', async () => {
  const { tina, sam, kim } = pages;
  assert.ok(tina && sam && kim, 'the lecture is on, with two followers');
  await button(sam, 'Raise hand').click();
  await sam.locator('section.lecture .lecture-picking').waitFor();
  // The middle of the view is the mesh (the orbit's centre); the click does not move the camera.
  const before = await cameraOf(sam);
  const box = await sam.locator('#viewport canvas').boundingBox();
  await sam.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
  await button(sam, 'Lower hand').waitFor();
  assert.ok(near((await cameraOf(sam)).position, before.position), 'the click to pick is not an orbit');
  assert.ok((await lecture(sam)).attached, 'picking a point keeps sam following');

  // Tina: the list, and a marker with the name over her view, near its middle.
  await tina.locator('section.lecture .lecture-hands li[data-user="sam"]', { hasText: 'sam raised a hand' }).waitFor();
  const marker = tina.locator('.hand-marker[data-user="sam"]');
  await marker.waitFor();
  assert.equal(await marker.locator('.hand-name').textContent(), 'sam');
  const m = await marker.boundingBox();
  const view = await tina.locator('#viewport canvas').boundingBox();
  assert.ok(
    Math.abs(m.x + 5 - (view.x + view.width / 2)) < 20 && Math.abs(m.y + 5 - (view.y + view.height / 2)) < 20,
    `the marker is where sam clicked: ${JSON.stringify({ m, view })}`,
  );
  assert.equal(await kim.locator('.hand-marker').count(), 0, 'no one else sees a hand not shown');

  await tina.locator('section.lecture .lecture-hands li[data-user="sam"]').getByRole('button', { name: 'Show to all' }).click();
  await kim.locator('.hand-marker.shown[data-user="sam"]').waitFor();
  await tina.screenshot({ path: path.join(artifactsDir, 'e2e-lecture-teacher.png') });
  await sam.screenshot({ path: path.join(artifactsDir, 'e2e-lecture-follower.png') });
  await lectureIs(kim, () => window.__cgview.lecture().shownHand === 'sam', "kim is shown sam's hand");

  await button(sam, 'Lower hand').click();
  await tina.locator('section.lecture .lecture-hands li[data-user="sam"]').waitFor({ state: 'detached' });
  assert.equal(problems.length, 0, describeProblems());
});

test("the teacher's selection reaches the followers, and goes when she clears it", async () => {
  const { tina, sam, kim } = pages;
  assert.ok(tina && sam && kim, 'the lecture is on, with two followers');
  await tina.locator('#select-tool').click();
  await tina.waitForFunction(() => window.__cgview.selection?.ready === true, null, { timeout: 30_000 });
  const box = await tina.locator('#viewport canvas').boundingBox();
  await tina.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
  await tina.waitForFunction(() => window.__cgview.selection?.count > 0);
  const picked = await tina.evaluate(() => window.__cgview.selection.ids);
  const selected = (ids) => JSON.stringify(window.__cgview.selection?.ids) === JSON.stringify(ids);
  for (const page of [sam, kim]) await page.waitForFunction(selected, picked, { timeout: 30_000 });
  // A click on the background clears it, for everybody.
  await tina.mouse.click(box.x + 3, box.y + 3);
  await tina.waitForFunction(() => window.__cgview.selection?.count === 0);
  for (const page of [sam, kim]) await page.waitForFunction(selected, [], { timeout: 30_000 });
  await tina.locator('#select-tool').click();
  assert.equal(problems.length, 0, describeProblems());
});

test("the teacher's code reaches the followers read-only, and a follower's write is refused", async () => {
  const { tina, sam } = pages;
  assert.ok(tina && sam, 'the lecture is on');
  await tina.locator('#playground-toggle').click();
  const code = sam.locator('section.lecture .lecture-code-text');
  await code.waitFor({ timeout: 30_000 });
  assert.match(await code.textContent(), /CGVIEW_REGISTER_FUNCTION\(height/);
  assert.equal(await code.evaluate((n) => n.isContentEditable), false, 'read-only');
  await tina.locator('#playground-toggle').click();
  await code.waitFor({ state: 'detached' });

  // A follower's change of the room is the server's to refuse.
  const refused = await sam.evaluate(() => window.__cgview.lectureWrite('camera', { position: [0, 0, 9], target: [0, 0, 0], up: [0, 1, 0], fov: 40 }));
  assert.equal(refused, 'forbidden');
  // The presenter's is taken (a part no viewer reads).
  assert.equal(await tina.evaluate(() => window.__cgview.lectureWrite('probe', 1)), null);

  // Sam leaves (his page stays open): tina counts one follower.
  await button(sam, 'Leave').click();
  await tina.locator('section.lecture .lecture-followers', { hasText: '1 following' }).waitFor();
  assert.equal((await lecture(sam)).role, 'none');
  assert.equal(problems.length, 0, describeProblems());
});

test("a student replays the recorded lecture: each moment is the teacher's view then, played at the speed chosen", async () => {
  const { tina, sam, kim } = pages;
  assert.ok(shots.last && shots.plain, 'the lecture went on');
  await settle(tina);
  const last = await cameraOf(tina);
  await followerMatches(kim, 'end', "kim's view before the end");
  await button(tina, 'End lecture').click();
  await lectureIs(sam, () => window.__cgview.lecture().role === 'none', 'the lecture ended for sam');
  await lectureIs(kim, () => window.__cgview.lecture().role === 'none', 'the lecture ended for kim');
  // What the room showed its followers was theirs to read while it lasted: for its replays, tina shares it with the course.
  await button(tina, 'Share with the course').click();
  await tina.locator('section.lecture .lecture-status', { hasText: 'Shared with Geometry 101' }).waitFor();
  for (const route of [`/meshes/${ids.mesh}`, `/jobs/${ids.job}`]) assert.equal((await api(tokens.kim, 'GET', route)).status, 200, `kim reads ${route}`);
  const rooms = (await api(tokens.kim, 'GET', `/courses/${ids.course}/rooms`)).json;
  assert.equal(rooms.length, 1);
  const recording = (await api(tokens.kim, 'GET', `/rooms/${rooms[0].room}/recording`)).json;
  const fieldAt = recording.events.find((e) => e.part === 'field' && e.value !== null).t_ms;

  await button(kim, 'Replay').click();
  await lectureIs(kim, () => window.__cgview.lecture().role === 'replay' && window.__cgview.lecture().replay, 'kim replays');
  const { duration } = (await lecture(kim)).replay;
  const slider = kim.getByRole('slider', { name: 'Replay time' });

  // The end: tina's last view, field and all.
  await slider.fill(String(Math.round(duration)));
  await kim.waitForFunction((job) => window.__cgview.lastField?.jobId === job && window.__cgview.display?.mode === 'flat', ids.job, { timeout: 30_000 });
  await cameraReaches(kim, last, 'the end of the replay');
  await assertSamePicture(kim, shots.last, await screenshot(kim, 'replay-end'), "the replay's end is tina's last view");

  // Just before the field: tina's view then, without it.
  await slider.fill(String(fieldAt - 1));
  await kim.waitForFunction(() => window.__cgview.lastField === null && window.__cgview.display?.mode === 'smooth', null, { timeout: 30_000 });
  const cameraThen = recording.events.filter((e) => e.part === 'camera' && e.t_ms < fieldAt).at(-1).value;
  await cameraReaches(kim, cameraThen, 'the replay before the field');
  await assertSamePicture(kim, shots.plain, await screenshot(kim, 'replay-before-field'), "the replay's moment before the field is tina's view then");

  // Played at 4x: the clock runs four times as fast as the wall's.
  await kim.getByRole('combobox', { name: 'Speed' }).selectOption('4');
  await button(kim, 'Play').click();
  // The clock moves once a frame: each reading is taken in a frame callback, right after the replay's own, so the
  // clock and the wall are read together (a reading between frames is a frame stale, a third of the span here).
  const reading = () =>
    kim.evaluate(
      () =>
        new Promise((resolve) =>
          requestAnimationFrame(() => {
            const r = window.__cgview.lecture().replay;
            resolve([r.t, performance.now(), r.playing]);
          }),
        ),
    );
  const t0 = await reading();
  await kim.waitForFunction((t) => window.__cgview.lecture().replay.t > t + 2000, t0[0], { timeout: 10_000 });
  const t1 = await reading();
  const rate = (t1[0] - t0[0]) / (t1[1] - t0[1]);
  assert.ok(t1[2], 'playing');
  assert.ok(rate > 2.5 && rate < 5, `the replay runs at 4x: ${rate.toFixed(2)}x`);
  // Taking the camera stops it there, to look around; Play follows the lecture again.
  await orbitDrag(kim, 60, 0);
  await lectureIs(kim, () => !window.__cgview.lecture().attached && !window.__cgview.lecture().replay.playing, 'kim looks around: the replay stops');
  await button(kim, 'Follow again').click();
  await lectureIs(kim, () => window.__cgview.lecture().attached, 'kim follows the replay again');
  await button(kim, 'Close replay').click();
  await lectureIs(kim, () => window.__cgview.lecture().role === 'none', 'the replay is closed');
  assert.equal(problems.length, 0, describeProblems());
});
