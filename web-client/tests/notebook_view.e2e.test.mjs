// The view a notebook shows (clients/python: job.show(), cgview_client/notebook.py),
// in the browser, against a server that needs a token (--auth required): the
// output's HTML as the Python client writes it, served from another origin
// (the notebook's), holds an iframe on the viewer with a sign-in ticket in
// its hash. The viewer redeems it, draws the job's mesh coloured by its field
// signed in (no token form), opens the camera the Python link says, and the
// output shows it over its picture; no URL the browser asks for holds the
// token, and the ticket leaves the frame's address. The same output opened
// again (its ticket used) keeps its picture and hides the frame.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { hueStats, launchBrowser, pngPixels, repo, serverBin, sleep, startServer } from './harness.mjs';
import { importTs } from './ts_module.mjs';

const { decodeViewHash } = await importTs('viewer/view_state.ts');
const elephant = path.join(repo, 'build', 'samples', 'elephant.off');

let server = null;
let browser = null;
let notebook = null; // the notebook's origin: serves the output cells' HTML
const pages = new Map();
let token = '';
let meshId = '';
let jobId = '';

async function api(method, route, body, headers = {}) {
  const r = await fetch(server.url + '/api/v1' + route, { method, body, headers: { Authorization: `Bearer ${token}`, ...headers } });
  return r.json();
}

before(async () => {
  server = await startServer({ tmpPrefix: 'cgview-notebook-view-', extraArgs: ['--auth', 'required'] });
  token = execFileSync(serverBin, ['--data-dir', server.dataDir, 'user', 'add', 'alice'], { encoding: 'utf8' }).trim();
  meshId = (await api('POST', '/meshes?name=elephant.off', fs.readFileSync(elephant))).id;
  const job = await api('POST', '/jobs', JSON.stringify({ algorithm: 'centroid_distance', inputs: { mesh: meshId }, params: {} }), {
    'Content-Type': 'application/json',
  });
  jobId = job.id;
  for (let state = job.state; state !== 'done'; state = (await api('GET', `/jobs/${jobId}`)).state) {
    assert.ok(!['failed', 'cancelled'].includes(state), `the job ${state}`);
    await sleep(100);
  }
  notebook = http.createServer((req, res) => {
    const page = pages.get(req.url);
    res.writeHead(page ? 200 : 404, { 'Content-Type': 'text/html; charset=utf-8' });
    res.end(page ?? 'no such cell');
  });
  await new Promise((resolve) => notebook.listen(0, '127.0.0.1', resolve));
  browser = await launchBrowser();
});

after(async () => {
  await browser?.close();
  await new Promise((resolve) => (notebook ? notebook.close(resolve) : resolve()));
  await server?.stop();
});

/** The output cell's HTML, as the Python client writes it with alice's token, on a page of the notebook's origin; its URL. */
function outputCell(name) {
  const code = `from cgview_client import Client\nprint(Client().job(${JSON.stringify(jobId)}).show(width=900, height=600).html())`;
  const html = execFileSync('python3', ['-c', code], {
    encoding: 'utf8',
    env: { ...process.env, PYTHONPATH: path.join(repo, 'clients', 'python'), CGVIEW_URL: server.url, CGVIEW_TOKEN: token },
  });
  pages.set(`/${name}.html`, `<!doctype html><html><head><title>${name}</title></head><body>${html}</body></html>`);
  return `http://127.0.0.1:${notebook.address().port}/${name}.html`;
}

test('the output opens the viewer signed in with its ticket on the job’s field, and no URL holds the token', async () => {
  const url = outputCell('cell');
  assert.ok(!pages.get('/cell.html').includes(token), 'the output holds the token');
  const context = await browser.newContext({ viewport: { width: 1280, height: 900 } });
  const page = await context.newPage();
  const asked = [];
  page.on('request', (r) => asked.push(r.url()));
  page.on('websocket', (ws) => asked.push(ws.url()));
  await page.goto(url);
  const iframe = await page.waitForSelector('.cgview-view iframe', { state: 'attached' });
  const src = await iframe.getAttribute('src');
  const view = decodeViewHash(new URL(src).hash.split('&')[0]);
  assert.equal(view.mesh, meshId);
  assert.equal(view.field.job, jobId);
  assert.match(new URL(src).hash, /&ticket=cgt_[0-9a-f]{16}_[0-9a-f]{64}$/);

  const frame = await iframe.contentFrame();
  await frame.waitForFunction(() => window.__cgview?.ready === true && window.__cgview.viewRestored && window.__cgview.lastField, null, {
    timeout: 90_000,
  });
  const hooks = await frame.evaluate(() => ({ restored: window.__cgview.viewRestored, field: window.__cgview.lastField }));
  assert.ok(!hooks.restored.error, hooks.restored.error);
  for (const key of ['position', 'target']) {
    hooks.restored.camera[key].forEach((v, i) => assert.ok(Math.abs(v - view.camera[key][i]) < 1e-6, `camera ${key}`));
  }
  assert.equal(hooks.field.jobId, jobId);
  assert.equal(hooks.field.meshId, meshId);
  assert.equal(hooks.field.map, view.field.map);
  // Signed in with the ticket's session: no form, the user's token storage untouched, the ticket out of the address.
  assert.equal(await frame.locator('#token-form').count(), 0);
  const stored = await frame.evaluate(() => ({ session: sessionStorage.getItem('cgview.session'), token: localStorage.getItem('cgview.token'), href: location.href }));
  assert.ok(stored.session, 'no session kept for the tab');
  assert.equal(stored.token, null);
  assert.ok(!stored.href.includes('ticket'), stored.href);
  // The output shows the frame once the viewer said it is ready, over the picture.
  await page.waitForFunction(() => document.querySelector('.cgview-view iframe').style.visibility === 'visible', null, { timeout: 30_000 });
  const shot = await pngPixels(page, await iframe.screenshot());
  assert.ok(hueStats(shot).distinct >= 3, `the field's colours are not drawn: ${JSON.stringify(hueStats(shot).buckets)}`);
  const secret = token.split('_').at(-1);
  assert.ok(asked.length > 3);
  for (const u of asked) assert.ok(!u.includes(secret) && !u.includes(token), `a URL holds the token: ${u}`);
  await context.close();
});

test('the same output opened again keeps its picture: its ticket was used', async () => {
  const url = outputCell('again');
  const first = await browser.newContext();
  const page1 = await first.newPage();
  await page1.goto(url);
  await page1.waitForFunction(() => document.querySelector('.cgview-view iframe')?.style.visibility === 'visible', null, { timeout: 90_000 });
  await first.close();
  // Another browser (no session of the first's tab): the ticket is spent.
  const context = await browser.newContext();
  const page = await context.newPage();
  await page.goto(url);
  const frame = await (await page.waitForSelector('.cgview-view iframe', { state: 'attached' })).contentFrame();
  await frame.waitForSelector('#token-form', { timeout: 60_000 });
  await sleep(500); // the frame's word has come (ready: false)
  assert.equal(await page.evaluate(() => document.querySelector('.cgview-view iframe').style.visibility), 'hidden');
  const img = await page.evaluate(() => {
    const i = document.querySelector('.cgview-view img');
    return { width: i.naturalWidth, height: i.naturalHeight, shown: i.getBoundingClientRect().width };
  });
  assert.deepEqual([img.width, img.height], [900, 600]);
  assert.ok(img.shown > 0);
  await context.close();
});
