// End-to-end test of the code playground (a user's own algorithm written,
// built and run in the browser) against the real server and Debian's
// chromium: `npm run test:e2e`, or
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/playground.e2e.test.mjs
//
// "Code" opens the panel (its editor loaded then, not with the page) on the
// template. An error typed into it (float( made flot( with the keyboard)
// comes back from "Build" listed at its line and column and marked on that
// line in the editor (underlined, a marker in the gutter); a click on the
// message selects the word, and the fix typed over it builds. "Run" runs it
// on the elephant: the job's field is drawn, and the canvas, plain orange
// before, shows a colour map. GET /api/v1/plugins lists the plugin, built;
// the build jobs stay out of the job list. The algorithm menu then lists
// the plugin's algorithm and runs it (the job names the plugin). Saved
// plugins reopen from "Open", are renamed and shared.
//
// Environment: CGVIEW_SERVER, CGVIEW_SAMPLES (default build/samples), CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { artifactsDir, hueStats, pngPixels, repo, settle, useViewer } from './harness.mjs';

const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const v = useViewer({ tmpPrefix: 'cgview-playground-', mesh: path.join(samples, 'elephant.off') });
// The template's one home (panels/playground_template.ts imports it as text).
const TEMPLATE = fs.readFileSync(new URL('../../docs/examples/height.cpp', import.meta.url), 'utf8');

// Where g++ will point: the line of `float(` in the template and its column.
const templateLines = TEMPLATE.split('\n');
const ERROR_LINE = templateLines.findIndex((l) => l.includes('= float(')) + 1;
const ERROR_COLUMN = templateLines[ERROR_LINE - 1].indexOf('float(') + 1;
/** A build on a busy 2-core machine: g++ takes seconds, more when others compile too. */
const BUILD_MS = 180_000;

const api = async (route) => {
  const r = await fetch(`${v.server.url}/api/v1${route}`);
  assert.equal(r.status, 200, `GET ${route}: ${await r.clone().text()}`);
  return r.json();
};

async function canvasHues(name) {
  const { page } = v;
  await settle(page);
  const png = await page.locator('#viewport canvas').screenshot();
  fs.writeFileSync(path.join(artifactsDir, `e2e-playground-${name}.png`), png);
  return hueStats(await pngPixels(page, png));
}

const playground = () => v.page.locator('#playground');
const button = (name) => playground().getByRole('button', { name, exact: true });
const status = () => playground().locator('.playground-status');

/** Scrolls the editor to its last line: it draws the lines in view only. */
const scrollToEnd = () =>
  playground()
    .locator('.cm-scroller')
    .evaluate((s) => s.scrollTo(0, s.scrollHeight));

/** Waits for the status line to say `pattern`, saying what it said otherwise. */
async function statusSays(pattern, timeout = BUILD_MS) {
  await v.page
    .waitForFunction((source) => new RegExp(source).test(document.querySelector('#playground .playground-status')?.textContent ?? ''), pattern.source, { timeout })
    .catch(async (e) => {
      throw new Error(`the status never said ${pattern}: "${await status().innerText()}" (${e.message})${v.describeProblems()}\n${v.server.log()}`);
    });
}

test('the editor is not in the first load; "Code" opens the panel on the template', async () => {
  const { page } = v;
  assert.equal(await page.locator('.cm-editor').count(), 0, 'no editor before the panel is opened');
  const scripts = await page.evaluate(() => performance.getEntriesByType('resource').map((e) => e.name));
  assert.ok(!scripts.some((s) => /plugins-[^/]*\.js$/.test(s)), `the panel's chunk is not loaded with the page: ${scripts}`);
  const before = await canvasHues('before');
  assert.ok(before.orange > 0.5, `the plain orange mesh first: ${JSON.stringify(before)}`);

  const toggle = page.getByRole('button', { name: 'Code', exact: true });
  await toggle.click();
  assert.equal(await toggle.getAttribute('aria-pressed'), 'true');
  await playground().locator('.cm-content').waitFor({ timeout: 30000 });
  assert.ok(await page.locator('#viewport canvas').isVisible(), 'the view stays beside the panel');
  const box = await page.locator('#viewport canvas').boundingBox();
  assert.ok(box.width >= 240, `the view keeps some width: ${JSON.stringify(box)}`);
  // The editor draws the lines in view only: the template's first ones.
  const text = await playground().locator('.cm-content').innerText();
  assert.ok(text.startsWith(templateLines[0]), `the template's first line: ${text.slice(0, 200)}`);
  assert.match(text, /#include "registry\/registry\.h"/);
  assert.equal(await playground().getByRole('textbox', { name: 'Plugin name' }).inputValue(), 'height');
  assert.match(await playground().innerText(), /on elephant\.off/, 'Run says the mesh it runs on');
});

test('an error typed into the editor is listed at its line after Build and marked on that line', async () => {
  const { page } = v;
  // The editor draws the lines in view only: scrolled down to the line of `float(`.
  await scrollToEnd();
  // The keyboard, as a student: a double-click selects the word, typing replaces it.
  const line = playground().locator('.cm-line', { hasText: 'height.values[i] = float(' });
  await line.locator('span', { hasText: /^float$/ }).dblclick();
  await page.keyboard.type('flot');
  await playground().locator('.cm-line', { hasText: 'height.values[i] = flot(' }).waitFor();

  await button('Build').click();
  await statusSays(/^Does not build/);
  const item = playground().locator('.playground-diagnostic[data-severity="error"]').first();
  assert.equal(await item.count(), 1, `an error listed (status: "${await status().innerText()}")\n${v.server.log()}`);
  const said = await item.innerText();
  assert.ok(said.startsWith(`height.cpp:${ERROR_LINE}:${ERROR_COLUMN} error:`), `the message names the line and column (${ERROR_LINE}:${ERROR_COLUMN}): ${said}`);
  assert.match(said, /flot/);
  assert.equal(await item.getAttribute('data-line'), String(ERROR_LINE));
  assert.match(await status().innerText(), /Does not build: 1 error/);

  // Marked in the editor: the word underlined on that line, a marker in the gutter beside it.
  const mark = playground().locator('.cm-lintRange-error');
  await mark.first().waitFor();
  assert.equal(await mark.count(), 1);
  assert.equal(await mark.innerText(), 'flot');
  // Its line, by the number the gutter shows beside it (lines out of view are not drawn, so not counted).
  const markBox = await mark.boundingBox();
  const numberBox = await playground()
    .locator('.cm-lineNumbers .cm-gutterElement', { hasText: new RegExp(`^${ERROR_LINE}$`) })
    .boundingBox();
  const markMiddle = markBox.y + markBox.height / 2;
  assert.ok(
    markMiddle >= numberBox.y && markMiddle <= numberBox.y + numberBox.height,
    `the underline is on line ${ERROR_LINE}, the compiler's: ${JSON.stringify({ markBox, numberBox })}`,
  );
  const marker = playground().locator('.cm-gutter-lint .cm-lint-marker-error');
  assert.equal(await marker.count(), 1, 'one marker in the gutter');
  const markerBox = await marker.boundingBox();
  const lineBox = await playground().locator('.cm-line', { hasText: 'height.values[i] = flot(' }).boundingBox();
  const middle = markerBox.y + markerBox.height / 2;
  assert.ok(middle >= lineBox.y && middle <= lineBox.y + lineBox.height, `the marker is beside the line: ${JSON.stringify({ markerBox, lineBox })}`);

  await page.screenshot({ path: path.join(artifactsDir, 'e2e-playground-error.png') });

  // The server says the same.
  const { plugins } = await api('/plugins');
  assert.equal(plugins.length, 1, JSON.stringify(plugins));
  assert.equal(plugins[0].name, 'height');
  assert.equal(plugins[0].build.state, 'failed');
  assert.deepEqual(
    plugins[0].build.diagnostics.filter((d) => d.severity === 'error').map((d) => [d.line, d.column]),
    [[ERROR_LINE, ERROR_COLUMN]],
  );
});

test('fixed and built again, Run draws its colour map on the elephant', async () => {
  const { page } = v;
  // A click on the message selects the word at fault; the fix is typed over it.
  await playground().locator('.playground-diagnostic').first().click();
  await page.keyboard.type('float');
  await playground().locator('.cm-line', { hasText: 'height.values[i] = float(' }).waitFor();
  await button('Build').click();
  await statusSays(/^Built: height/);
  assert.equal(await playground().locator('.playground-diagnostic').count(), 0, 'no messages left');
  assert.equal(await playground().locator('.cm-lintRange-error').count(), 0, 'no underline left');
  // The parameters' form, from the built algorithm's schema.
  const axis = playground().locator('select[data-param="axis"]');
  await axis.waitFor();
  assert.deepEqual(await axis.locator('option').allInnerTexts(), ['x', 'y', 'z']);
  await axis.selectOption({ label: 'y' });

  await button('Run').click();
  await statusSays(/^height done/);
  await page
    .waitForFunction(() => window.__cgview.lastField?.artifact === 'height', null, { timeout: 60000 })
    .catch(async (e) => {
      throw new Error(`no field drawn (page error: ${await page.evaluate(() => window.__cgview.lastError)}): ${e.message}${v.describeProblems()}`);
    });
  const field = await page.evaluate(() => window.__cgview.lastField);
  assert.equal(field.meshId, v.meshId);
  assert.equal(field.location, 'vertex');
  assert.equal(field.count, 2775, 'one value per vertex of the elephant');
  const hues = await canvasHues('run');
  await page.screenshot({ path: path.join(artifactsDir, 'e2e-playground-page.png') });
  assert.ok(hues.saturated > 2000, `coloured pixels: ${JSON.stringify(hues)}`);
  assert.ok(hues.distinct >= 3, `several hues: ${JSON.stringify(hues)}`);
  assert.ok(hues.orange < 0.5, `no longer the plain orange: ${JSON.stringify(hues)}`);

  const { plugins } = await api('/plugins');
  assert.equal(plugins.length, 1);
  assert.equal(plugins[0].build.state, 'ok');
  assert.deepEqual(plugins[0].build.algorithms, ['height']);
  const { jobs } = await api('/jobs');
  const run = jobs.find((j) => j.id === field.jobId);
  assert.equal(run?.algorithm, 'height', JSON.stringify(run));
  assert.equal(run.state, 'done');
  assert.equal(run.params.axis, 'y', 'the form sent its value');
  // The build jobs stay out of the job list; the run is in it.
  const listed = await page.locator('#jobs li.job').evaluateAll((li) => li.map((l) => l.dataset.jobId));
  assert.ok(listed.includes(field.jobId), `the run is listed: ${listed}`);
  for (const j of jobs.filter((j) => j.algorithm === 'plugin_build')) assert.ok(!listed.includes(j.id), `build job ${j.id} not listed`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test("the algorithm menu lists the plugin's algorithm and runs it", async () => {
  const { page } = v;
  const menu = page.locator('#algorithm-menu');
  const names = await menu.locator('option').evaluateAll((os) => os.map((o) => o.value));
  assert.ok(names.includes('height'), `the menu lists height: ${names}`);
  await menu.selectOption('height');
  const form = page.locator('form.algorithm-form[data-algorithm="height"]');
  await form.locator('select[data-param="axis"]').selectOption({ label: 'x' });
  const before = (await api('/jobs')).jobs.length;
  const shown = await page.evaluate(() => window.__cgview.lastField.jobId);
  await form.locator('button.run').click();
  await page.waitForFunction(
    (old) => {
      const f = window.__cgview.lastField;
      return f?.artifact === 'height' && f.jobId !== old && document.querySelector(`#jobs li.job[data-job-id="${f.jobId}"][data-state="done"]`);
    },
    shown,
    { timeout: 60000 },
  );
  const { jobs } = await api('/jobs');
  assert.equal(jobs.length, before + 1);
  const job = jobs.find((j) => j.algorithm === 'height' && j.params.axis === 'x');
  assert.equal(job?.state, 'done', JSON.stringify(job));
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('New, Open, Rename and Share', async () => {
  const { page } = v;
  await button('New').click();
  await statusSays(/new file/);
  assert.equal(await playground().locator('select[data-param="axis"]').count(), 0, 'no form for a file not built');
  const chooser = playground().getByRole('combobox', { name: 'Open a plugin' });
  const id = (await api('/plugins')).plugins[0].id;
  await chooser.selectOption(id);
  await statusSays(/^Built: height/, 30000);
  await scrollToEnd();
  await playground().locator('.cm-line', { hasText: 'height.values[i] = float(' }).waitFor({ timeout: 10000 }); // the saved text, fixed

  const name = playground().getByRole('textbox', { name: 'Plugin name' });
  await name.fill('my_height');
  await button('Rename').click();
  await statusSays(/^Renamed my_height/, 30000);
  assert.equal((await api(`/plugins/${id}`)).name, 'my_height');
  assert.ok(await chooser.locator(`option[value="${id}"]`).evaluate((o) => o.textContent.startsWith('my_height')));

  await button('Share…').click();
  const form = page.locator('#share-form[data-kind="plugins"]');
  await form.locator('input[name="everyone"]').check();
  await form.locator('button.share-submit').click();
  await form.locator('.share-status', { hasText: 'Shared with everyone' }).waitFor({ timeout: 15000 });
  await form.locator('button.share-close').click();

  // Closed and opened again, the panel is as it was.
  await page.getByRole('button', { name: 'Code', exact: true }).click();
  assert.equal(await playground().isVisible(), false);
  await page.getByRole('button', { name: 'Code', exact: true }).click();
  assert.equal(await name.inputValue(), 'my_height');
  assert.deepEqual(v.problems, [], v.describeProblems());
});
