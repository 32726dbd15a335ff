// A field coloured on a big mesh in the viewer, measured in headless
// chromium: the bytes the page receives to show the mesh (the WebSocket's
// Draco stream) and then to colour a field on it (every HTTP response after
// the mesh is drawn: the field's values, and the mesh's stored order: its
// face order, or the whole mesh again as PLY for a client that downloads it
// twice), and the time from the job's "done" in the Jobs panel to the field
// drawn (window.__cgview.lastField).
//
//   node bench/field_bench.mjs [--mesh FILE.ply] [--runs 3] [--dist DIR]
//
// --dist serves another build of the viewer (say an older commit's
// web-client/dist) from the same server, to compare clients side by side.
// Without --mesh it writes the 1M-triangle mesh of ws_bench (bunny00
// subdivided twice) with `build/bin/ws_bench --clients 0 --save-mesh`.
import { spawnSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";
import {
  launchBrowser,
  repo,
  startServer,
} from "../web-client/tests/harness.mjs";
import {
  benchPage,
  givenMesh,
  held,
  runBench,
  uploadMesh,
} from "./bench_browser_util.mjs";

const args = process.argv.slice(2);
const arg = (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 ? args[i + 1] : fallback;
};
const runs = Number(arg("--runs", "3"));
const dist = arg("--dist", null);
const DEFAULT_MESH = "/tmp/cgview_bunny_1m.ply";

function prepareMesh() {
  const given = givenMesh(arg("--mesh", null));
  if (given) return given;
  if (fs.existsSync(DEFAULT_MESH)) return DEFAULT_MESH;
  const bin = path.join(repo, "build", "bin", "ws_bench");
  const r = spawnSync(bin, ["--clients", "0", "--save-mesh", DEFAULT_MESH], {
    cwd: repo,
    encoding: "utf8",
  });
  if (r.status !== 0)
    throw new Error(`ws_bench --save-mesh failed: ${r.stderr}`);
  return DEFAULT_MESH;
}

async function once(browser, baseUrl, mesh, index) {
  const { page, problems } = await benchPage(browser);
  const cdp = await page.context().newCDPSession(page);
  await cdp.send("Network.enable");
  let wsBytes = 0;
  cdp.on("Network.webSocketFrameReceived", (e) => {
    // Binary frames come base64-encoded.
    wsBytes +=
      e.response.opcode === 2
        ? Math.floor((e.response.payloadData.length * 3) / 4)
        : e.response.payloadData.length;
  });
  const http = []; // [url, bytes] after the mesh is drawn
  let counting = false;
  cdp.on("Network.loadingFinished", (e) => {
    if (counting) http.push(e.encodedDataLength);
  });
  const urls = [];
  page.on(
    "request",
    (r) => counting && urls.push(r.url().replace(baseUrl, "")),
  );
  await page.goto(`${baseUrl}/`);
  await page.waitForFunction(() => window.__cgview?.ready === true, null, {
    timeout: 30_000,
  });
  await page.locator(`#mesh-list li.mesh[data-mesh-id="${mesh.id}"]`).click();
  await page.waitForFunction(
    (id) => window.__cgview.lastLoaded?.id === id,
    mesh.id,
    { timeout: 300_000 },
  );
  const meshBytes = wsBytes;
  counting = true;
  await page.evaluate(() => {
    window.__doneAt = null;
    const root = document.getElementById("jobs");
    new MutationObserver(() => {
      if (
        window.__doneAt === null &&
        root.querySelector('li.job[data-state="done"]')
      )
        window.__doneAt = performance.now();
    }).observe(root, { childList: true, subtree: true, attributes: true });
  });
  const form = page.locator(
    'form.algorithm-form[data-algorithm="centroid_distance"]',
  );
  await form
    .locator('input[data-param="exponent"]')
    .fill(String(1 + index / 100)); // a new job each run
  await form.locator("button.run").click();
  const drawnMs = await page.evaluate(
    () =>
      new Promise((resolve, reject) => {
        const deadline = performance.now() + 300_000;
        const tick = () => {
          if (window.__cgview.lastError)
            return reject(new Error(window.__cgview.lastError));
          if (window.__cgview.lastField && window.__doneAt !== null)
            return resolve(performance.now() - window.__doneAt);
          if (performance.now() > deadline)
            return reject(new Error("no field drawn"));
          requestAnimationFrame(tick);
        };
        tick();
      }),
  );
  await new Promise((r) => setTimeout(r, 300)); // the last loadingFinished events
  const fieldBytes = http.reduce((a, b) => a + b, 0);
  await page.close();
  if (problems.length) throw new Error(problems.join("\n"));
  return {
    meshBytes,
    fieldBytes,
    drawnMs,
    urls: urls.filter(
      (u) => !/\/jobs(\?|$)|\/me$|thumbnail|render\.png/.test(u),
    ),
  };
}

await runBench("field_bench", async () => {
  const file = prepareMesh();
  held.server = await startServer({
    tmpPrefix: "cgview-field-bench-",
    extraArgs: ["--samples", "none", ...(dist ? ["--static-dir", dist] : [])],
  });
  const baseUrl = held.server.url;
  const { mesh } = await uploadMesh(baseUrl, file);
  held.browser = await launchBrowser();
  console.log(
    `${path.basename(file)}: ${mesh.report.vertices} vertices, ${mesh.report.faces} faces; client ${dist ?? "web-client/dist"}`,
  );
  console.log(
    "| run | mesh stream | bytes to colour the field | job done → field drawn | requests |",
  );
  console.log("|---|---:|---:|---:|---|");
  for (let i = 1; i <= runs; ++i) {
    const r = await once(held.browser, baseUrl, mesh, i);
    const mb = (b) => `${(b / 1e6).toFixed(2)} MB`;
    console.log(
      `| ${i} | ${mb(r.meshBytes)} | ${mb(r.fieldBytes)} | ${r.drawnMs.toFixed(0)} ms | ${[...new Set(r.urls)].join(" ")} |`,
    );
  }
});
