// A server that needs a token (--auth required), in the browser: the viewer
// asks for the token once, keeps it, and then lists the shared samples over
// REST, draws their thumbnails and streams a mesh over the WebSocket with it;
// the token never appears in a URL.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { after, before, test } from 'node:test';

import { launchBrowser, serverBin, startServer } from './harness.mjs';

let server = null;
let browser = null;

before(async () => {
  server = await startServer({ tmpPrefix: 'cgview-auth-', extraArgs: ['--auth', 'required'] });
  browser = await launchBrowser();
});

after(async () => {
  await browser?.close();
  await server?.stop();
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
  assert.ok(urls.every((u) => !u.includes(secret)), 'the token is in no URL');
  await page.close();
});
