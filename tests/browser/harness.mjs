// What the browser tests share: options, Playwright (playwright-core from web/node_modules) driving
// Debian's Chromium in a fresh profile, `dashbench serve` on a copy of data/demo.db on loopback,
// steps that report PASS / FAIL, and screenshots. Exit codes: 0 passed, 1 failed, 77 skipped
// (Chromium cannot start here).
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

export const SKIP = 77;
export const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
const CHROMIUM = process.env.DASHBENCH_CHROMIUM || '/usr/bin/chromium';
const CHROMIUM_ARGS = [
  '--headless',
  '--no-sandbox',
  '--disable-gpu',
  '--disable-dev-shm-usage',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync',
  '--no-first-run',
  // Software WebGL (SwiftShader) for the 3D view: newer Chromium no longer falls back to it by itself.
  '--enable-unsafe-swiftshader',
];

export function option(name, fallback) {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 && i + 1 < process.argv.length ? process.argv[i + 1] : fallback;
}
export const DASHBENCH = option('dashbench', path.join(ROOT, 'build', 'dashbench'));
export const ARTIFACTS = path.resolve(option('artifacts', path.join(ROOT, 'build', 'test-artifacts')));
export const KEEP = process.argv.includes('--keep');

export function sleep(ms) {
  return new Promise((r) => setTimeout(r, ms));
}

export function loadPlaywright() {
  const requireWeb = createRequire(path.join(ROOT, 'web', 'package.json'));
  try {
    return requireWeb('playwright-core');
  } catch (e) {
    console.error(`FAIL: web/node_modules has no playwright-core (${e.message}); run \`npm ci\` in web/`);
    process.exit(1);
  }
}

export async function launchBrowser(playwright, profile, { width = 1440, height = 1000, downloads = false } = {}) {
  if (!fs.existsSync(CHROMIUM)) {
    console.log(`SKIP: ${CHROMIUM} does not exist: install Debian's chromium (./dashbench test does)`);
    process.exit(SKIP);
  }
  try {
    return await playwright.chromium.launchPersistentContext(profile, {
      executablePath: CHROMIUM,
      headless: true,
      args: CHROMIUM_ARGS,
      viewport: { width, height },
      timeout: 60000,
      acceptDownloads: downloads,
    });
  } catch (e) {
    console.log(`SKIP: Chromium cannot start here: ${String(e.message).split('\n')[0]}`);
    process.exit(SKIP);
  }
}

/// Starts `dashbench serve` on a free port on a copy of `db` (data/demo.db by default); resolves
/// {child, url, db, log} once it prints its URL.
export function startServer(tmp, { db: source = path.join(ROOT, 'data', 'demo.db'), workers = 2 } = {}) {
  const db = path.join(tmp, 'results.db');
  if (!fs.existsSync(source)) throw new Error(`${source} is missing (see docs/dashboard.md)`);
  fs.copyFileSync(source, db);
  const args = ['serve', '--port', '0', '--db', db, '--token-file', path.join(tmp, 'token'), '--web', path.join(ROOT, 'web'), '--max-workers', String(workers)];
  const child = spawn(DASHBENCH, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  let log = '';
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`the server did not start in 60 s:\n${log}`)), 60000);
    const onData = (d) => {
      log += d.toString();
      const m = log.match(/open (http:\/\/127\.0\.0\.1:\d+)/);
      if (m) {
        clearTimeout(timer);
        resolve({ child, url: m[1], db, log: () => log });
      }
    };
    child.stdout.on('data', onData);
    child.stderr.on('data', (d) => (log += d.toString()));
    child.on('exit', (code) => reject(new Error(`the server exited (${code}):\n${log}`)));
  });
}

export async function stopServer(server) {
  if (!server || server.child.exitCode !== null) return;
  server.child.kill('SIGINT');
  for (let i = 0; i < 100 && server.child.exitCode === null; i++) await sleep(100);
  if (server.child.exitCode === null) server.child.kill('SIGKILL');
}

export const results = [];
export async function step(name, fn) {
  const t0 = Date.now();
  try {
    await fn();
    results.push({ name, ok: true, seconds: (Date.now() - t0) / 1000 });
    console.log(`PASS ${name} (${((Date.now() - t0) / 1000).toFixed(1)} s)`);
  } catch (e) {
    results.push({ name, ok: false, seconds: (Date.now() - t0) / 1000, error: e });
    console.log(`FAIL ${name} (${((Date.now() - t0) / 1000).toFixed(1)} s): ${e.stack || e}`);
  }
}

export function expect(condition, message) {
  if (!condition) throw new Error(message);
}

export async function shot(page, name, { fullPage = true } = {}) {
  await page.screenshot({ path: path.join(ARTIFACTS, `${name}.png`), fullPage });
}

/// Collects console errors and page errors; while `provoking()` is true, Chromium's own line about a
/// 4xx answer (a refusal the step asked for) is expected.
export function watchConsole(page, provoking = () => false) {
  const errors = [];
  page.on('console', (m) => {
    if (m.type() !== 'error') return;
    if (provoking() && /Failed to load resource: the server responded with a status of 4\d\d/.test(m.text())) return;
    errors.push(`${page.url()}: ${m.text()}`);
  });
  page.on('pageerror', (e) => errors.push(`${page.url()}: ${e.message}`));
  return errors;
}

export function finish() {
  const failed = results.filter((r) => !r.ok);
  console.log(`${results.length - failed.length} passed, ${failed.length} failed; screenshots in ${ARTIFACTS}`);
  process.exit(failed.length ? 1 : 0);
}
