// A development preview, not a test: drives the page against the real server
// with the jobs API of protocol/API.md stood in by playwright routes (REST)
// and a routed WebSocket that adds job_* events, so that the algorithm menu,
// the job panel and the scalar-field renderer can be seen before the server
// has the API. `node tests/jobs_mock_preview.mjs` (after `npm run build`);
// screenshots go to build/test-artifacts/jobs-mock-*.png. The real checks
// are tests/jobs.e2e.test.mjs.
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { launchBrowser, repo, sleep, startServer } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');
const artifacts = path.join(repo, 'build', 'test-artifacts');
fs.mkdirSync(artifacts, { recursive: true });
const algorithms = JSON.parse(execFileSync(path.join(repo, 'build', 'bin', 'cgview'), ['list', '--json'], { encoding: 'utf8' }));

const server = await startServer({ tmpPrefix: 'cgview-mock-' });
const browser = await launchBrowser();
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('pageerror', (e) => console.log('pageerror', e.message));
  page.on('console', (m) => m.type() === 'error' && console.log('console.error', m.text()));

  const jobs = new Map();
  const fields = new Map();
  let socket = null;
  const send = (type, job) => socket?.send(JSON.stringify({ type, job }));
  const json = (route, status, body) => route.fulfill({ status, contentType: 'application/json', body: JSON.stringify(body) });

  await page.routeWebSocket('**/api/v1/ws', (ws) => {
    ws.connectToServer(); // forwards both ways
    socket = ws;
  });
  await page.route('**/api/v1/algorithms', (route) => json(route, 200, { algorithms }));
  await page.route(/\/api\/v1\/jobs(\/.*)?(\?.*)?$/, async (route) => {
    const req = route.request();
    const url = new URL(req.url());
    const parts = url.pathname.split('/').slice(3); // jobs, id, artifacts, name
    if (parts.length === 1 && req.method() === 'GET') return json(route, 200, { jobs: [...jobs.values()] });
    if (parts.length === 1 && req.method() === 'POST') {
      const body = req.postDataJSON();
      const e = body.params?.exponent ?? 1;
      if (e > 4) return json(route, 400, { error: 'bad_request', detail: `parameter 'exponent': ${e} is over the maximum 4` });
      const meshId = body.inputs.mesh;
      const off = await (await fetch(`${server.url}/api/v1/meshes/${meshId}/download?format=off`)).text();
      const nums = off.split(/\s+/).filter(Boolean);
      const nv = Number(nums[1]);
      const pos = nums.slice(4, 4 + nv * 3).map(Number);
      let c = [0, 0, 0];
      for (let i = 0; i < nv; ++i) for (let k = 0; k < 3; ++k) c[k] += pos[i * 3 + k] / nv;
      const values = new Float32Array(nv);
      for (let i = 0; i < nv; ++i) values[i] = Math.hypot(pos[i * 3] - c[0], pos[i * 3 + 1] - c[1], pos[i * 3 + 2] - c[2]) ** e;
      let lo = Infinity,
        hi = -Infinity;
      for (const v of values) {
        lo = Math.min(lo, v);
        hi = Math.max(hi, v);
      }
      const id = `job${jobs.size + 1}`;
      fields.set(id, values);
      const job = {
        id,
        algorithm: body.algorithm,
        inputs: body.inputs,
        params: body.params,
        state: 'queued',
        progress: 0,
        stage: '',
        error: null,
        cached: false,
        created: new Date().toISOString(),
        started: null,
        finished: null,
        artifacts: [],
      };
      jobs.set(id, job);
      (async () => {
        for (const p of [0.1, 0.3, 0.5, 0.7, 0.9]) {
          await sleep(400);
          if (job.state === 'cancelled') return;
          Object.assign(job, { state: 'running', progress: p, stage: 'distances' });
          send('job_progress', { id, state: job.state, progress: job.progress, stage: job.stage });
        }
        await sleep(300);
        if (job.state === 'cancelled') return;
        Object.assign(job, {
          state: 'done',
          progress: 1,
          stage: 'done',
          finished: new Date().toISOString(),
          artifacts: [
            { name: 'distance', kind: 'scalar_field', location: 'vertex', range: [lo, hi], count: nv, hint: 'magnitude' },
            { name: 'stats', kind: 'metrics' },
            { name: 'blob', kind: 'mesh' },
          ],
        });
        send('job_done', job);
      })();
      return json(route, 201, job);
    }
    const job = jobs.get(parts[1]);
    if (!job) return json(route, 404, { error: 'not_found', detail: 'no such job' });
    if (parts.length === 2 && req.method() === 'GET') return json(route, 200, job);
    if (parts.length === 2 && req.method() === 'DELETE') {
      Object.assign(job, { state: 'cancelled', finished: new Date().toISOString() });
      send('job_cancelled', job);
      return json(route, 200, job);
    }
    if (parts[2] === 'artifacts' && parts[3] === 'stats') {
      const v = fields.get(job.id);
      return json(route, 200, { count: v.length, mean: v.reduce((a, b) => a + b, 0) / v.length, params: job.params });
    }
    if (parts[2] === 'artifacts' && parts[3] === 'blob') {
      // A mesh artifact: some other stored mesh (the smallest), as PLY.
      const meshes = (await (await fetch(`${server.url}/api/v1/meshes`)).json()).meshes;
      const small = meshes.filter((m) => m.report.vertices > 100).sort((a, b) => a.report.vertices - b.report.vertices)[0];
      const ply = await (await fetch(`${server.url}/api/v1/meshes/${small.id}/download?format=ply`)).arrayBuffer();
      return route.fulfill({ status: 200, contentType: 'application/octet-stream', body: Buffer.from(ply) });
    }
    if (parts[2] === 'artifacts') {
      const v = fields.get(job.id);
      return route.fulfill({ status: 200, contentType: 'application/octet-stream', body: Buffer.from(v.buffer) });
    }
    return json(route, 404, { error: 'not_found', detail: url.pathname });
  });

  await page.goto(server.url + '/');
  await page.waitForFunction(() => window.__cgview?.ready === true);
  await page.setInputFiles('#file-input', elephant);
  await page.waitForFunction(() => window.__cgview.lastLoaded !== null, null, { timeout: 60000 });

  const form = page.locator('form.algorithm-form[data-algorithm="centroid_distance"]');
  await form.locator('input[data-param="exponent"]').fill('9');
  await form.locator('button.run').click();
  await form.locator('.form-error').waitFor({ state: 'visible' });
  console.log('400 beside the form:', await form.locator('.form-error').innerText());

  // One job cancelled half-way, one run to the end.
  await form.locator('input[data-param="exponent"]').fill('2');
  await form.locator('button.run').click();
  await page.locator('#jobs li.job[data-state="running"]').first().waitFor();
  await page.screenshot({ path: path.join(artifacts, 'jobs-mock-running.png') });
  await page.locator('#jobs li.job[data-state="running"] button.cancel').first().click();
  await page.locator('#jobs li.job[data-state="cancelled"]').first().waitFor();

  await form.locator('input[data-param="exponent"]').fill('1');
  await form.locator('button.run').click();
  await page.waitForFunction(() => window.__cgview.lastField !== null, null, { timeout: 30000 });
  console.log('lastField', JSON.stringify(await page.evaluate(() => window.__cgview.lastField)));
  console.log('jobs panel:\n' + (await page.locator('#jobs').innerText()));
  console.log('legend:', (await page.locator('#legend').innerText()).replace(/\n/g, ' | '));
  await page.screenshot({ path: path.join(artifacts, 'jobs-mock-page.png') });
  await page.locator('#viewport canvas').screenshot({ path: path.join(artifacts, 'jobs-mock-canvas.png') });
  await page.locator('#legend select.legend-map').selectOption('coolwarm');
  await page.waitForFunction(() => window.__cgview.lastField?.map === 'coolwarm');
  await page.screenshot({ path: path.join(artifacts, 'jobs-mock-coolwarm.png') });
  await page.locator('#jobs li.job[data-state="done"] .artifact-mesh button.add').first().click();
  await page.waitForFunction(() => window.__cgview.lastExtra !== null, null, { timeout: 30000 });
  console.log('lastExtra', JSON.stringify(await page.evaluate(() => window.__cgview.lastExtra)));
  await page.screenshot({ path: path.join(artifacts, 'jobs-mock-extra.png') });
  console.log('lastError', await page.evaluate(() => window.__cgview.lastError));
} finally {
  await browser.close();
  await server.stop();
}
