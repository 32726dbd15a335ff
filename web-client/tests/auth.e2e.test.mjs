// A server that needs a token (--auth required), in the browser: the viewer
// asks for the token once, keeps it, and then lists the shared samples over
// REST, draws their thumbnails and streams a mesh over the WebSocket with it;
// the token never appears in a URL.  The header shows the user and their
// quota use (a config file gives alice a small storage quota: an upload over
// it shows the server's message); "Sign out" forgets the token; sharing a
// mesh shares it with another user, who sees it after a reload, and takes it
// back; "Share…" on a job shares it with everyone. The sign-in box is written
// for a student (paste the link the teacher sent), with no server command in
// it and no "Sign out" while nobody is signed in; a view link of a mesh or a
// field the reader may not see says so, and who to ask.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';

import { launchBrowser, repo, serverBin, startServer } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off'); // 173779 bytes
const configDir = fs.mkdtempSync(path.join(os.tmpdir(), 'cgview-auth-config-'));
const configFile = path.join(configDir, 'config.json');
// Room for one elephant, not two.
fs.writeFileSync(configFile, JSON.stringify({ users: { alice: { storage_mb: 0.2 } } }));

let server = null;
let browser = null;

before(async () => {
  server = await startServer({ tmpPrefix: 'cgview-auth-', extraArgs: ['--auth', 'required', '--config', configFile] });
  browser = await launchBrowser();
});

after(async () => {
  await browser?.close();
  await server?.stop();
  fs.rmSync(configDir, { recursive: true, force: true });
});

function addUser(name) {
  return execFileSync(serverBin, ['--data-dir', server.dataDir, 'user', 'add', name], {
    encoding: 'utf8',
    stdio: ['ignore', 'pipe', 'ignore'],
  }).trim();
}

async function api(token, method, route, body) {
  const r = await fetch(server.url + '/api/v1' + route, { method, body, headers: { Authorization: `Bearer ${token}` } });
  return { status: r.status, json: await r.json().catch(() => null) };
}

// A page signed in with the token (the form, then the reload), ready.
async function signedIn(token) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(server.url + '/');
  await page.locator('#token-form input').fill(token);
  await Promise.all([page.waitForEvent('load'), page.locator('#token-form button').click()]);
  await page.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
  return page;
}

test('the sign-in box speaks to a student, and nobody is signed out before signing in', async () => {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(server.url + '/');
  const box = page.getByRole('form', { name: 'Sign in to CGView' });
  await box.waitFor({ timeout: 30000 });
  const text = await box.innerText();
  assert.match(text, /sign-in link your teacher sent you/, text);
  assert.match(text, /Ask your teacher for a new one/, text);
  assert.doesNotMatch(text, /cgview-server|user add/, "no command for the server's admin");
  assert.ok(await box.getByLabel('Sign-in link or token').isVisible());
  assert.ok(await box.getByRole('button', { name: 'Sign in' }).isVisible());
  await page.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
  assert.equal(await page.getByRole('button', { name: 'Sign out' }).count(), 0, 'no "Sign out" with nobody signed in');
  assert.equal(await page.locator('#account').isVisible(), false, 'no account line');
  // The requests refused for want of a token are not errors to read: the box asks.
  assert.equal(await page.locator('#messages').getByRole('alert').count(), 0, await page.locator('#messages').innerText());
  assert.equal(await page.getByRole('region', { name: /Drop a mesh here/ }).isVisible(), false, 'no upload card under the box');
  await page.close();
});

test('the viewer asks for a token once, then works with it', async () => {
  const token = execFileSync(serverBin, ['--data-dir', server.dataDir, 'user', 'add', 'alice'], {
    encoding: 'utf8',
    stdio: ['ignore', 'pipe', 'ignore'],
  }).trim();
  assert.match(token, /^cgv_[0-9a-f]{16}_[0-9a-f]{64}$/);
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const urls = [];
  page.on('request', (r) => urls.push(r.url()));
  await page.goto(server.url + '/');
  await page.locator('#token-form input').fill(token);
  await Promise.all([page.waitForEvent('load'), page.locator('#token-form button').click()]);
  await page.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
  const first = page.locator('#mesh-list li.mesh').first();
  await first.waitFor({ timeout: 30000 });
  assert.equal(await page.evaluate(() => localStorage.getItem('cgview.token')), token);
  // The mesh streams over the WebSocket, which authenticated first.
  const id = await first.getAttribute('data-mesh-id');
  await first.click();
  await page.waitForFunction((meshId) => window.__cgview.lastLoaded?.id === meshId, id, { timeout: 60000 });
  assert.equal(await page.locator('#token-form').count(), 0, 'the form is not asked again');
  const secret = token.slice(21);
  assert.ok(
    urls.every((u) => !u.includes(secret)),
    'the token is in no URL',
  );
  await page.close();
});

test('the header shows the user and their quota; over it an upload shows why; sign out asks again', async () => {
  const token = addUser('alice');
  const page = await signedIn(token);
  const usage = page.locator('#account .account-usage');
  await page.waitForFunction(() => document.querySelector('#account .account-usage')?.textContent?.startsWith('alice — '));
  assert.match(await usage.textContent(), /^alice — 0 B of 205 KiB$/);

  // One elephant fits: the header follows.
  await page.locator('#file-input').setInputFiles(elephant);
  await page.waitForFunction(() => /^alice — 170 KiB of 205 KiB$/.test(document.querySelector('#account .account-usage')?.textContent ?? ''), null, { timeout: 30000 });
  const me = await api(token, 'GET', '/me');
  assert.equal(me.json.storage_bytes_used, fs.statSync(elephant).size);
  assert.equal(me.json.storage_bytes_limit, Math.round(0.2 * 1048576));

  // A second one does not (another file: the same one again is only selected): the server's reason is shown, and nothing more is stored.
  await page
    .locator('#file-input')
    .setInputFiles({ name: 'elephant-copy.off', mimeType: 'application/octet-stream', buffer: Buffer.concat([fs.readFileSync(elephant), Buffer.from('\n')]) });
  const alert = page.locator('#messages .message.error').first();
  await alert.waitFor({ timeout: 30000 });
  assert.match(await alert.textContent(), /storage quota of 204\.8 KB exceeded: 169\.7 KB used, this upload is 169\.7 KB/);
  assert.equal((await api(token, 'GET', '/me')).json.storage_bytes_used, fs.statSync(elephant).size);

  // Sign out: the token is forgotten and the form asks for one again.
  await Promise.all([page.waitForEvent('load'), page.locator('#account .sign-out').click()]);
  await page.locator('#token-form input').waitFor({ timeout: 30000 });
  assert.equal(await page.evaluate(() => localStorage.getItem('cgview.token')), null);
  assert.equal(await page.locator('#mesh-list li.mesh').count(), 0);
  await page.close();
});

test('a mesh shared in the viewer shows for the other user after a reload, and goes when unshared', async () => {
  const carol = addUser('carol');
  const dave = addUser('dave');
  const up = await api(carol, 'POST', '/meshes?name=elephant.off', fs.readFileSync(elephant));
  assert.equal(up.status, 201);
  const id = up.json.id;
  const row = (page) => page.locator(`#mesh-list li.mesh[data-mesh-id="${id}"]`);

  const other = await signedIn(dave);
  await other.locator('#mesh-list li.mesh').first().waitFor({ timeout: 30000 }); // the samples
  assert.equal(await row(other).count(), 0, "dave does not see carol's mesh yet");

  const owner = await signedIn(carol);
  await row(owner).waitFor({ timeout: 30000 });
  // Samples belong to the system: no Share… on them for carol.
  assert.equal(await owner.locator('#mesh-list li.mesh:not([data-mesh-id="' + id + '"]) .share').count(), 0);
  await row(owner).locator('.share').click();
  await owner.locator('#share-form input[name="users"]').fill('dave');
  await owner.locator('#share-form .share-submit').click();
  await owner.waitForFunction(() => document.querySelector('#share-form .share-status')?.textContent === 'Shared with dave.');
  assert.deepEqual((await api(dave, 'GET', '/meshes/' + id)).status, 200);

  await other.reload();
  await row(other).waitFor({ timeout: 30000 });
  assert.equal(await row(other).locator('.share').count(), 0, 'a reader may not share it on');

  // A user who does not exist: the server's reason.
  await owner.locator('#share-form input[name="users"]').fill('nobody');
  await owner.locator('#share-form .share-submit').click();
  await owner.waitForFunction(() => /no user 'nobody'/.test(document.querySelector('#share-form .share-status')?.textContent ?? ''));

  await owner.locator('#share-form input[name="users"]').fill('dave');
  await owner.locator('#share-form .unshare-submit').click();
  await owner.waitForFunction(() => document.querySelector('#share-form .share-status')?.textContent === 'Not shared.');
  await other.reload();
  await other.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
  await other.locator('#mesh-list li.mesh').first().waitFor({ timeout: 30000 });
  assert.equal(await row(other).count(), 0, 'unshared: gone for dave');

  // A job: shared with everyone from its Share… button.
  const job = await api(carol, 'POST', '/jobs', JSON.stringify({ algorithm: 'centroid_distance', inputs: { mesh: id } }));
  assert.equal(job.status, 201);
  assert.equal(job.json.owner, 'carol');
  assert.equal((await api(dave, 'GET', '/jobs/' + job.json.id)).status, 404);
  await owner.locator('#share-form .share-close').click();
  const jobRow = owner.locator(`#jobs li.job[data-job-id="${job.json.id}"]`);
  await jobRow.locator('.share').click({ timeout: 30000 });
  await owner.locator('#share-form input[name="everyone"]').check();
  await owner.locator('#share-form .share-submit').click();
  await owner.waitForFunction(() => document.querySelector('#share-form .share-status')?.textContent === 'Shared with everyone.');
  assert.equal((await api(dave, 'GET', '/jobs/' + job.json.id)).status, 200);
  await other.close();
  await owner.close();
});

test('a view link of a mesh, or a field, the reader may not see says so and who to ask', async () => {
  const erin = addUser('erin');
  const frank = addUser('frank');
  const up = await api(erin, 'POST', '/meshes?name=elephant.off', fs.readFileSync(elephant));
  assert.equal(up.status, 201);
  const mesh = up.json.id;
  const job = await api(erin, 'POST', '/jobs', JSON.stringify({ algorithm: 'centroid_distance', inputs: { mesh } }));
  assert.equal(job.status, 201);
  const camera = { position: [0, 0, 3], target: [0, 0, 0], up: [0, 1, 0], fov: 40 };
  const link = (state) => `${server.url}/#view=${Buffer.from(JSON.stringify({ v: 1, camera, ...state })).toString('base64url')}`;

  const page = await signedIn(frank);
  await page.locator('#mesh-list li.mesh').first().waitFor({ timeout: 30000 });
  await page.goto(link({ mesh }));
  await page.reload(); // a new hash alone does not reload the page
  await page.waitForFunction(() => window.__cgview?.viewRestored != null, null, { timeout: 30000 });
  const alert = page.locator('#messages').getByRole('alert').filter({ hasText: 'Cannot open the view link' });
  await alert.waitFor({ timeout: 10000 });
  assert.match(await alert.innerText(), /it shows a mesh \([0-9a-f]+\) that does not exist or is not shared with you: ask its owner to share it/);
  assert.doesNotMatch(await alert.innerText(), /no longer exists/);
  await alert.getByRole('button', { name: 'Dismiss' }).click();

  // A mesh frank sees (a sample) with erin's field on it: the mesh is shown, and the page says why the field is not.
  const sample = await page.locator('#mesh-list li.mesh').first().getAttribute('data-mesh-id');
  await page.goto(link({ mesh: sample, field: { job: job.json.id, artifact: 'distance', map: 'viridis', range: [0, 1] } }));
  await page.reload();
  await page.waitForFunction((id) => window.__cgview?.lastLoaded?.id === id, sample, { timeout: 60000 });
  const fieldAlert = page.locator('#messages').getByRole('alert').filter({ hasText: 'shows a field of a job' });
  await fieldAlert.waitFor({ timeout: 10000 });
  assert.match(await fieldAlert.innerText(), /does not exist or is not shared with you: ask its owner to share it/);
  assert.equal(await page.evaluate(() => window.__cgview.lastField), null, 'no field drawn');
  await page.close();
});
