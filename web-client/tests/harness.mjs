// What tests/e2e.test.mjs and bench/browser_bench.mjs share: the paths of the
// server, the built client and chromium, and starting and stopping the real
// server and a headless chromium.
//
// Environment: CGVIEW_SERVER (default build/bin/cgview-server),
// CHROMIUM (default /usr/bin/chromium).
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

export const webClient = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
export const repo = path.resolve(webClient, '..');
export const dist = path.join(webClient, 'dist');
export const serverBin = process.env.CGVIEW_SERVER ?? path.join(repo, 'build', 'bin', 'cgview-server');
export const chromiumBin = process.env.CHROMIUM ?? '/usr/bin/chromium';

export const CHROMIUM_ARGS = [
  '--use-angle=swiftshader',
  '--enable-unsafe-swiftshader',
  '--no-sandbox',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
  '--headless=new',
];

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// Servers still running and data directories not yet removed: the safety net
// below deals with them if the process exits without stop().
const leftovers = new Set();

process.on('exit', () => {
  for (const { proc, dataDir } of leftovers) {
    if (proc.exitCode === null && proc.signalCode === null) proc.kill('SIGKILL');
    fs.rmSync(dataDir, { recursive: true, force: true });
  }
});

// Starts the server on a port of its choosing with an empty data directory and
// the built client; resolves once it has said where it serves and
// GET /api/v1/health answers ok.
export async function startServer({ tmpPrefix = 'cgview-', extraArgs = [], timeoutMs = 30_000 } = {}) {
  const dataDir = fs.mkdtempSync(path.join(os.tmpdir(), tmpPrefix));
  const proc = spawn(
    serverBin,
    ['--host', '127.0.0.1', '--port', '0', '--data-dir', dataDir, '--static-dir', dist, ...extraArgs],
    { cwd: repo, stdio: ['ignore', 'pipe', 'pipe'] },
  );
  const entry = { proc, dataDir };
  leftovers.add(entry);
  let serverLog = '';
  const log = () => serverLog;
  const exited = () => proc.exitCode !== null || proc.signalCode !== null;

  let stopping = null;
  const stop = () => {
    stopping ??= new Promise((resolve) => {
      if (exited()) return resolve();
      const killer = setTimeout(() => proc.kill('SIGKILL'), 5000);
      proc.once('exit', () => {
        clearTimeout(killer);
        resolve();
      });
      proc.kill('SIGTERM');
    }).then(() => {
      fs.rmSync(dataDir, { recursive: true, force: true });
      leftovers.delete(entry);
    });
    return stopping;
  };

  try {
    const url = await new Promise((resolve, reject) => {
      const timer = setTimeout(
        () => reject(new Error(`cgview-server did not say where it serves within ${timeoutMs / 1000} s:\n${serverLog}`)),
        timeoutMs,
      );
      const onData = (chunk) => {
        serverLog += chunk.toString();
        if (serverLog.length > 20000) serverLog = serverLog.slice(-20000);
        const m = /CGView serving (http:\/\/[^/\s]+)\//.exec(serverLog);
        if (m) {
          clearTimeout(timer);
          resolve(m[1]);
        }
      };
      proc.stdout.on('data', onData);
      proc.stderr.on('data', onData);
      proc.once('error', (e) => {
        clearTimeout(timer);
        reject(e);
      });
      proc.once('exit', (code, signal) => {
        clearTimeout(timer);
        reject(new Error(`cgview-server exited (${code ?? signal}):\n${serverLog}`));
      });
    });
    await waitForHealth(url, timeoutMs, exited, log);
    return { url, port: Number(new URL(url).port), dataDir, log, stop };
  } catch (e) {
    await stop();
    throw e;
  }
}

async function waitForHealth(url, timeoutMs, exited, log) {
  const deadline = Date.now() + timeoutMs;
  let last = '';
  while (Date.now() < deadline) {
    if (exited()) throw new Error(`cgview-server exited before it was healthy:\n${log()}`);
    try {
      const r = await fetch(`${url}/api/v1/health`);
      const body = await r.json();
      if (r.status === 200 && body.status === 'ok') return body;
      last = `HTTP ${r.status} ${JSON.stringify(body)}`;
    } catch (e) {
      last = e.message;
    }
    await sleep(100);
  }
  throw new Error(`GET /api/v1/health did not answer ok within ${timeoutMs} ms (last: ${last}):\n${log()}`);
}

// Debian's chromium, headless, software WebGL through SwiftShader.
export function launchBrowser() {
  return chromium.launch({ executablePath: chromiumBin, args: CHROMIUM_ARGS, headless: true });
}
