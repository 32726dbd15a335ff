// Big meshes in the viewer (a preview first), measured in headless chromium:
// for a 2M-triangle mesh, the time from the click to the first frame of the
// decimated preview and to the first frame of the full mesh, and the frame
// time while orbiting (median and p95 over --frames frames (30), each rendered
// with renderer.render() and waited for with a 1-pixel readPixels:
// web-client/src/viewer/frame_timer.ts) with the preview shown (while the full
// mesh is still coming) and with the full mesh.  For comparison, the same
// mesh on a server with previews off (--preview-faces 0).
//
//   node bench/frame_bench.mjs [--mesh FILE] [--frames 30]
//
// (SwiftShader draws a 2M-triangle frame in seconds on 2 cores: 100 frames
// of the full mesh take minutes.)
//
// Without --mesh it writes /tmp/cgview_man_2m.ply: CGAL's man.off (34,986
// triangles) with three midpoint subdivisions (2,239,104 triangles), made
// here (no huge file is committed).  Each configuration starts
// build/bin/cgview-server (--samples none) on an empty data directory,
// uploads the mesh and opens the viewer: run "cold" is the first request
// (the server decimates, stores the preview and Draco-encodes the mesh),
// run "warm" reloads the page (both encodings come from the server's cache),
// and a third load times the orbit, first over the preview, then over the
// full mesh.  Prints Markdown; exits non-zero when something fails.
//
// Needs: build/bin/cgview-server, the built client (cd web-client && npm run
// build), /usr/bin/chromium.  CGVIEW_SERVER, CGVIEW_SAMPLES, CHROMIUM
// override the paths.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { launchBrowser, repo, startServer } from '../web-client/tests/harness.mjs';
import { benchPage, checkPrerequisites, cleanup, givenMesh, held, meshItem, parseBenchArgs, runBench, uploadMesh } from './bench_browser_util.mjs';

const DEFAULT_MESH = '/tmp/cgview_man_2m.ply';
const samples = process.env.CGVIEW_SAMPLES ?? path.join(repo, 'build', 'samples');
const TIMEOUT_MS = 600_000;

// ---- the 2M-triangle mesh: an OFF sample, midpoint-subdivided, as binary PLY ----
function readOff(file) {
  const words = fs.readFileSync(file, 'utf8').replace(/#[^\n]*/g, '').split(/\s+/).filter(Boolean);
  let at = 1; // after "OFF"
  const nv = Number(words[at++]);
  const nf = Number(words[at++]);
  at++;
  const positions = [];
  for (let i = 0; i < 3 * nv; ++i) positions.push(Number(words[at++]));
  const faces = [];
  for (let f = 0; f < nf; ++f) {
    const n = Number(words[at++]);
    const poly = words.slice(at, at + n).map(Number);
    at += n;
    for (let k = 1; k + 1 < n; ++k) faces.push(poly[0], poly[k], poly[k + 1]);
  }
  return { positions, faces };
}

// Each triangle into four at its edges' midpoints (shared between neighbours).
function subdivide({ positions, faces }) {
  const out = positions.slice();
  const mid = new Map();
  const midpoint = (a, b) => {
    const key = a < b ? a * 4294967296 + b : b * 4294967296 + a;
    let m = mid.get(key);
    if (m === undefined) {
      m = out.length / 3;
      for (let k = 0; k < 3; ++k) out.push((positions[3 * a + k] + positions[3 * b + k]) / 2);
      mid.set(key, m);
    }
    return m;
  };
  const f2 = [];
  for (let i = 0; i < faces.length; i += 3) {
    const [a, b, c] = [faces[i], faces[i + 1], faces[i + 2]];
    const ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    f2.push(a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca);
  }
  return { positions: out, faces: f2 };
}

function writePly(file, { positions, faces }) {
  const nv = positions.length / 3, nf = faces.length / 3;
  const head = Buffer.from(
    `ply\nformat binary_little_endian 1.0\nelement vertex ${nv}\nproperty float x\nproperty float y\nproperty float z\n` +
      `element face ${nf}\nproperty list uchar int vertex_indices\nend_header\n`,
  );
  const body = Buffer.alloc(12 * nv + 13 * nf);
  for (let i = 0; i < positions.length; ++i) body.writeFloatLE(positions[i], 4 * i);
  let o = 12 * nv;
  for (let i = 0; i < faces.length; i += 3) {
    body.writeUInt8(3, o);
    body.writeInt32LE(faces[i], o + 1);
    body.writeInt32LE(faces[i + 1], o + 5);
    body.writeInt32LE(faces[i + 2], o + 9);
    o += 13;
  }
  fs.writeFileSync(file, Buffer.concat([head, body]));
}

function prepareMesh(file) {
  const given = givenMesh(file);
  if (given) return given;
  if (!fs.existsSync(DEFAULT_MESH)) {
    let m = readOff(path.join(samples, 'man.off'));
    for (let i = 0; i < 3; ++i) m = subdivide(m);
    writePly(DEFAULT_MESH, m);
  }
  return DEFAULT_MESH;
}

// ---- one load: click the mesh, note when the preview and the full mesh are first drawn ----
// With orbitFrames, times the orbit as soon as the preview is drawn (while the
// full mesh is still coming), then again once the full mesh is drawn.
async function load(page, baseUrl, mesh, first, orbitFrames = 0) {
  const item = await meshItem(page, baseUrl, mesh, first);
  await item.click();
  return page.evaluate(
    ({ id, timeoutMs, orbitFrames }) =>
      new Promise((resolve) => {
        const deadline = performance.now() + timeoutMs;
        const r = { previewMs: null, previewFaces: null, fullMs: null, previewOrbit: null, fullOrbit: null };
        const tick = () => {
          const s = window.__cgview;
          if (s.lastError) return resolve({ error: s.lastError });
          const now = performance.now();
          if (r.previewMs === null && s.lastPreview?.id === id) {
            r.previewMs = now - window.__benchClick;
            r.previewFaces = s.lastPreview.faces;
            if (orbitFrames && s.lastLoaded?.id !== id) {
              r.previewOrbit = s.orbit(orbitFrames);
              console.log(`preview orbit: ${JSON.stringify(r.previewOrbit)}`);
            }
          }
          if (s.lastLoaded?.id === id && s.timings) {
            r.fullMs = now - window.__benchClick;
            r.fullFaces = s.lastLoaded.faces;
            if (orbitFrames) r.fullOrbit = s.orbit(orbitFrames);
            return resolve(r);
          }
          if (now > deadline) return resolve({ error: `no frame with mesh ${id} within ${timeoutMs} ms` });
          requestAnimationFrame(tick);
        };
        tick();
      }),
    { id: mesh.id, timeoutMs: TIMEOUT_MS, orbitFrames },
  );
}

async function configuration(meshFile, previewFaces, frames, orbitRun = true) {
  const server = (held.server = await startServer({
    tmpPrefix: 'cgview-frame-bench-',
    extraArgs: ['--samples', 'none', '--preview-faces', String(previewFaces)],
    timeoutMs: 60_000,
  }));
  const { mesh, uploadMs } = await uploadMesh(server.url, meshFile);
  const browser = (held.browser = await launchBrowser());
  const { page, problems } = await benchPage(browser, {
    onConsole: (m) => {
      if (m.text().includes('orbit')) console.error(m.text());
    },
  });
  const runs = {};
  for (const [name, orbit] of [['cold', 0], ['warm', 0], ...(orbitRun ? [['orbit', frames]] : [])]) {
    const res = await load(page, server.url, mesh, name === 'cold', orbit);
    if (res.error) throw new Error(`${name}: ${res.error}\n${problems.join('\n')}`);
    if (res.fullFaces !== mesh.report.faces) throw new Error(`${name}: ${res.fullFaces} faces drawn, the mesh has ${mesh.report.faces}`);
    console.error(`preview-faces ${previewFaces}, ${name}: preview ${res.previewMs?.toFixed(0) ?? '-'} ms, full ${res.fullMs.toFixed(0)} ms`);
    runs[name] = res;
  }
  if (problems.length) throw new Error(problems.join('\n'));
  const version = browser.version();
  await cleanup();
  return { mesh, uploadMs, runs, version };
}

const ms = (x) => (x === null || x === undefined ? '–' : `${Math.round(x).toLocaleString('en')} ms`);
const orbitCell = (o) => (o ? `${o.medianMs.toFixed(1)} / ${o.p95Ms.toFixed(1)} ms (${o.triangles.toLocaleString('en')} triangles drawn)` : '–');

async function main() {
  const args = parseBenchArgs(process.argv.slice(2), { name: 'frame_bench', usage: '[--mesh FILE] [--frames N]', count: 'frames', defaultCount: 30, min: 10 });
  checkPrerequisites();
  const meshFile = prepareMesh(args.mesh);
  const load0 = os.loadavg()[0];
  const withPreview = await configuration(meshFile, 200000, args.frames);
  const without = await configuration(meshFile, 0, args.frames, false); // the same full mesh: its orbit is the one above
  const { mesh } = withPreview;
  const cpus = os.cpus();
  console.log(`## Big meshes in the viewer: ${mesh.report.faces.toLocaleString('en')} triangles\n`);
  console.log(
    `Mesh: ${path.basename(meshFile)} (${mesh.report.vertices.toLocaleString('en')} vertices, ${mesh.report.faces.toLocaleString('en')} triangles; ` +
      `upload over REST ${ms(withPreview.uploadMs)}). Chromium ${withPreview.version} headless with SwiftShader, ${cpus.length} CPU cores ` +
      `(${cpus[0]?.model.trim() ?? 'unknown'}; load average ${load0.toFixed(2)} at the start). Orbit: ${args.frames} frames, 1280×800 page.\n`,
  );
  console.log('| server | run | click → preview frame | click → full mesh frame | orbit, preview shown: median / p95 | orbit, full mesh: median / p95 |');
  console.log('|---|---|---:|---:|---|---|');
  for (const [label, c] of [['preview at > 200k faces (default)', withPreview], ['previews off (--preview-faces 0)', without]]) {
    for (const name of ['cold', 'warm', 'orbit']) {
      const r = c.runs[name];
      if (!r) continue;
      const note = name === 'orbit' ? 'orbit (3rd load)' : name;
      console.log(`| ${label} | ${note} | ${ms(r.previewMs)}${r.previewFaces ? ` (${r.previewFaces.toLocaleString('en')} faces)` : ''} | ${ms(r.fullMs)} | ${orbitCell(r.previewOrbit)} | ${orbitCell(r.fullOrbit)} |`);
    }
  }
}

await runBench('frame_bench', main);
