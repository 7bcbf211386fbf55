#!/usr/bin/env node
// Browser test of the Dispatch page: Playwright (playwright-core from web/node_modules) drives
// Debian's Chromium against `dashbench serve` (a copy of data/demo.db) and two `dashbench controller
// --driver sim` agents, all on loopback.
//   node tests/browser/dispatch.mjs --dashbench BUILD/dashbench [--artifacts DIR] [--keep]
// Checks: both controllers show up ready; a 2-robot sorting plan from the database passes the
// pre-flight check from the page, starts, shows live progress per arm (numbers, and the 3D view's
// planned ghosts), and finishes with every arm SUCCESSFUL; the history records it; with one arm
// away from the plan's start the check refuses; with it put back, Abort stops a running dispatch and
// every arm reports CANCELLED (Abort by the Esc key); during a long live dispatch with the 3D view
// drawn by software WebGL (SwiftShader), a click on "Abort every arm" a few seconds in stops every
// arm within 1 s of the click, and the live view is on screen without scrolling; on the run's own page, "Dispatch this plan" passes its pre-flight
// check (the table shows every check), enables Dispatch and starts a dispatch that succeeds; by
// dependencies (execution tpg, one arm slowed to 0.7), the arms table shows each arm's step and what
// it waits for, the dispatch succeeds, and the Run page plots its planned and executed makespan. No
// console errors.
// Exit: 0 passed, 1 failed, 77 skipped (Chromium cannot start here).
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const SKIP = 77;
const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..');
const CHROMIUM = process.env.DASHBENCH_CHROMIUM || '/usr/bin/chromium';
const CHROMIUM_ARGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run', '--enable-unsafe-swiftshader'];

function option(name, fallback) {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 && i + 1 < process.argv.length ? process.argv[i + 1] : fallback;
}
const DASHBENCH = option('dashbench', path.join(ROOT, 'build', 'dashbench'));
const ARTIFACTS = path.resolve(option('artifacts', path.join(ROOT, 'build', 'test-artifacts')));
const KEEP = process.argv.includes('--keep');

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

function expect(condition, message) {
  if (!condition) throw new Error(message);
}

function loadPlaywright() {
  const requireWeb = createRequire(path.join(ROOT, 'web', 'package.json'));
  try {
    return requireWeb('playwright-core');
  } catch (e) {
    console.error(`FAIL: web/node_modules has no playwright-core (${e.message}); run \`npm ci\` in web/`);
    process.exit(1);
  }
}

async function launchBrowser(playwright, profile) {
  if (!fs.existsSync(CHROMIUM)) {
    console.log(`SKIP: ${CHROMIUM} does not exist: install Debian's chromium (./dashbench test does)`);
    process.exit(SKIP);
  }
  try {
    return await playwright.chromium.launchPersistentContext(profile, { executablePath: CHROMIUM, headless: true, args: CHROMIUM_ARGS, viewport: { width: 1440, height: 1000 }, timeout: 60000 });
  } catch (e) {
    console.log(`SKIP: Chromium cannot start here: ${String(e.message).split('\n')[0]}`);
    process.exit(SKIP);
  }
}

/// A child process whose output is kept (for failure messages).
function startChild(args, name) {
  const child = spawn(DASHBENCH, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  const proc = { child, name, log: '' };
  child.stdout.on('data', (d) => (proc.log += d.toString()));
  child.stderr.on('data', (d) => (proc.log += d.toString()));
  return proc;
}

async function stopChild(proc) {
  if (!proc || proc.child.exitCode !== null || proc.child.signalCode !== null) return;
  proc.child.kill('SIGINT');
  for (let i = 0; i < 100 && proc.child.exitCode === null && proc.child.signalCode === null; i++) await sleep(100);
  if (proc.child.exitCode === null && proc.child.signalCode === null) proc.child.kill('SIGKILL');
}

/// `dashbench serve` on a free port over a copy of the demo database; resolves once it prints its URL.
async function startServer(tmp) {
  const db = path.join(tmp, 'results.db');
  const demo = path.join(ROOT, 'data', 'demo.db');
  if (!fs.existsSync(demo)) throw new Error(`${demo} is missing (see the README's Dashboard section)`);
  fs.copyFileSync(demo, db);
  const proc = startChild(['serve', '--port', '0', '--db', db, '--token-file', path.join(tmp, 'token'), '--web', path.join(ROOT, 'web'), '--max-workers', '1', '--dispatch-state-timeout', '1.5'], 'server');
  for (let i = 0; i < 600; i++) {
    const m = proc.log.match(/open (http:\/\/127\.0\.0\.1:\d+)/);
    if (m) return { ...proc, url: m[1] };
    if (proc.child.exitCode !== null) break;
    await sleep(100);
  }
  throw new Error(`the server did not start:\n${proc.log}`);
}

const results = [];
async function step(name, fn) {
  const t0 = Date.now();
  try {
    await fn();
    results.push({ name, ok: true });
    console.log(`PASS ${name} (${((Date.now() - t0) / 1000).toFixed(1)} s)`);
  } catch (e) {
    results.push({ name, ok: false });
    console.log(`FAIL ${name} (${((Date.now() - t0) / 1000).toFixed(1)} s): ${e.stack || e}`);
  }
}

async function main() {
  const playwright = loadPlaywright();
  fs.mkdirSync(ARTIFACTS, { recursive: true });
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'dashbench-dispatch-'));
  const context = await launchBrowser(playwright, path.join(tmp, 'profile'));
  let server = null;
  let agents = [];
  const page = context.pages()[0] || (await context.newPage());
  try {
    server = await startServer(tmp);
    const url = server.url;
    const tokenFile = path.join(tmp, 'token');
    const token = fs.readFileSync(tokenFile, 'utf8').trim();
    page.setDefaultTimeout(30000);
    const consoleErrors = [];
    page.on('console', (m) => {
      if (m.type() !== 'error') return;
      consoleErrors.push(`${page.url()}: ${m.text()}`);
    });
    page.on('pageerror', (e) => consoleErrors.push(`${page.url()}: ${e.message}`));
    const auth = { Authorization: `Bearer ${token}` };
    const apiGet = async (p) => (await page.request.get(`${url}${p}`, { headers: auth })).json();

    // The shortest solved 2-robot sorting plan in the demo database, and where each arm starts.
    const candidates = (await apiGet(`/api/runs?limit=200&q=${encodeURIComponent('family = sorting and robots = 2 and status = solved and has_plan = 1')}`)).runs;
    expect(candidates.length > 0, 'the demo database has no solved 2-robot sorting run with a plan');
    candidates.sort((a, b) => a.makespan - b.makespan);
    const run = candidates[0];
    const plan = await apiGet(`/api/runs/${run.uuid}/plan`);
    const scene = await apiGet(`/api/runs/${run.uuid}/scene`);
    const robots = Object.keys(plan.robots);
    expect(robots.length === 2, `expected 2 robots, got ${robots.join(',')}`);
    const modelOf = Object.fromEntries(scene.robots.map((r) => [r.id, r.model]));
    const startAgents = () =>
      robots.map((id) =>
        startChild(['controller', '--server', url, '--robot', id, '--token-file', tokenFile, '--driver', 'sim', '--model', modelOf[id], '--sim-start', plan.robots[id].points[0].q.join(','), '--quiet'], id),
      );
    const agentLogs = () => agents.map((a) => `--- ${a.name}:\n${a.log}`).join('\n');
    agents = startAgents();
    // Restarts agent `i` at `q` and waits for the registry to have it (its n-th reconnection) ready.
    const reconnects = robots.map(() => 0);
    const restart = async (i, q, extra = []) => {
      await stopChild(agents[i]);
      const id = robots[i];
      agents[i] = startChild(['controller', '--server', url, '--robot', id, '--token-file', tokenFile, '--driver', 'sim', '--model', modelOf[id], '--sim-start', q.join(','), '--quiet', ...extra], id);
      reconnects[i] += 1;
      for (let n = 0; ; n++) {
        const c = (await apiGet('/api/controllers')).controllers.find((x) => x.robot === id);
        if (c && c.reconnects >= reconnects[i] && c.connected && c.ready) break;
        expect(n < 300, `${id} did not reconnect: ${JSON.stringify(c)}\n${agentLogs()}`);
        await sleep(100);
      }
    };
    console.log(`plan: run ${run.uuid} (${run.family}, makespan ${Number(run.makespan).toFixed(1)} s), robots ${robots.join(', ')}`);

    let firstId = '';
    await step('Dispatch: both sim controllers show up ready', async () => {
      await page.goto(`${url}/#token=${token}`);
      await page.waitForFunction(() => location.hash === '#/runs');
      await page.goto(`${url}/#/dispatch`);
      await page.waitForFunction(
        (ids) => {
          const rows = [...document.querySelectorAll('[data-testid=controllers] tbody tr')].map((tr) => tr.textContent);
          return ids.every((id) => rows.some((t) => t.startsWith(id) && t.includes('sim') && /yesyes/.test(t)));
        },
        robots,
        { timeout: 30000 },
      ).catch((e) => {
        throw new Error(`${e.message}\n${agentLogs()}`);
      });
    });

    await step('Dispatch: pre-flight from the page, Start, live progress, success per arm, history', async () => {
      await page.locator('[data-testid=dispatch-run]').fill(run.uuid);
      await page.locator('[data-testid=time-scale]').fill('1');
      await page.locator('[data-testid=dispatch-user]').fill('browser');
      await page.locator('[data-testid=preflight]').click();
      await page.waitForSelector('[data-testid=preflight-result][data-passed]', { timeout: 60000 });
      const passed = await page.getAttribute('[data-testid=preflight-result]', 'data-passed');
      expect(passed === '1', `pre-flight refused: ${await page.locator('[data-testid=preflight-result]').textContent()}`);
      expect(!(await page.locator('[data-testid=start]').isDisabled()), 'Start stays disabled after a passed check');
      await page.locator('[data-testid=start]').click();
      await page.waitForSelector('[data-testid=dispatch-started]', { timeout: 60000 });
      await page.waitForSelector('[data-testid=dispatch-status][data-state=running]');
      firstId = await page.getAttribute('[data-testid=dispatch-status]', 'data-id');
      // Live: every arm's progress moves, the 3D view shows both arms with their planned ghosts.
      await page.waitForFunction(() => {
        const rows = [...document.querySelectorAll('[data-testid=arms-table] tbody tr')];
        return rows.length === 2 && rows.every((r) => Number(r.dataset.progress) > 0.02);
      });
      await page.waitForSelector('[data-testid=dispatch-viewer][data-live="2"]', { timeout: 30000 });
      const error = Number(await page.getAttribute('[data-testid=dispatch-viewer]', 'data-live-error'));
      expect(error < 0.1, `the arms are ${error} rad from their plan`);
      const numbers = await page.locator('[data-testid=arms-table] tbody tr').first().textContent();
      expect(/%/.test(numbers) && /rad/.test(numbers), `no progress or joint error shown: ${numbers}`);
      await page.screenshot({ path: path.join(ARTIFACTS, 'dispatch-running.png'), fullPage: true });
      await page.waitForSelector('[data-testid=dispatch-status][data-final="1"]', { timeout: (Number(run.makespan) + 60) * 1000 });
      const state = await page.getAttribute('[data-testid=dispatch-status]', 'data-state');
      expect(state === 'succeeded', `the dispatch ended ${state}: ${await page.locator('[data-testid=dispatch-status]').textContent()}\n${agentLogs()}`);
      for (const id of robots) {
        await page.waitForSelector(`[data-testid=arms-table] tr[data-robot="${id}"][data-result=SUCCESSFUL]`);
      }
      await page.waitForSelector(`[data-testid=dispatch-history] tr[data-dispatch="${firstId}"][data-state=succeeded]`);
      const row = await page.locator(`[data-testid=dispatch-history] tr[data-dispatch="${firstId}"]`).textContent();
      expect(row.includes('browser') && robots.every((id) => row.includes(`${id}: SUCCESSFUL`)), `history row: ${row}`);
      const record = await apiGet(`/api/dispatches/${firstId}`);
      expect(record.run_id === run.uuid && record.requested_by === 'browser' && record.client === '127.0.0.1', `record: ${JSON.stringify(record)}`);
      await page.screenshot({ path: path.join(ARTIFACTS, 'dispatch-done.png'), fullPage: true });
    });

    await step('Dispatch: an arm away from the start is refused; Abort stops every arm', async () => {
      const start = plan.robots[robots[1]].points[0].q;
      await restart(1, start.map((v, j) => (j === 2 ? v + 0.2 : v)));
      await page.locator('[data-testid=preflight]').click();
      await page.waitForSelector('[data-testid=preflight-result][data-passed]', { timeout: 60000 });
      const refusal = await page.locator('[data-testid=preflight-result]').textContent();
      expect(/not at the plan's start/.test(refusal) && refusal.includes(robots[1]), `refusal: ${refusal}`);
      expect(await page.locator('[data-testid=start]').isDisabled(), 'Start enabled after a failed check');
      // Put the arm back, check, start, abort from the page.
      await restart(1, start);
      await page.locator('[data-testid=preflight]').click();
      await page.waitForSelector('[data-testid=preflight-result][data-passed]', { timeout: 60000 });
      expect((await page.getAttribute('[data-testid=preflight-result]', 'data-passed')) === '1', `pre-flight: ${await page.locator('[data-testid=preflight-result]').textContent()}`);
      await page.locator('[data-testid=start]').click();
      await page.waitForFunction((first) => {
        const s = document.querySelector('[data-testid=dispatch-status]');
        return s.dataset.state === 'running' && s.dataset.id !== first;
      }, firstId, { timeout: 60000 });
      await page.waitForFunction(() => [...document.querySelectorAll('[data-testid=arms-table] tbody tr')].some((r) => Number(r.dataset.progress) > 0.01));
      await page.keyboard.press('Escape');
      await page.waitForSelector('[data-testid=abort-result]:has-text("aborted")');
      await page.waitForSelector('[data-testid=dispatch-status][data-final="1"]', { timeout: 30000 });
      const state = await page.getAttribute('[data-testid=dispatch-status]', 'data-state');
      expect(state === 'aborted', `ended ${state}`);
      for (const id of robots) await page.waitForSelector(`[data-testid=arms-table] tr[data-robot="${id}"][data-result=CANCELLED]`);
      const reason = await page.locator('[data-testid=dispatch-reason]').textContent();
      expect(/abort from the dashboard \(browser\) by the Esc key/.test(reason), `reason: ${reason}`);
      const secondId = await page.getAttribute('[data-testid=dispatch-status]', 'data-id');
      await page.waitForSelector(`[data-testid=dispatch-history] tr[data-dispatch="${secondId}"][data-state=aborted]`);
      await page.screenshot({ path: path.join(ARTIFACTS, 'dispatch-aborted.png'), fullPage: true });
    });

    await step('Dispatch: with software WebGL, Abort clicked 3 s into a live dispatch stops every arm within 1 s', async () => {
      for (let i = 0; i < robots.length; i++) await restart(i, plan.robots[robots[i]].points[0].q);
      // A fresh page, as someone opens it to dispatch: the 3D view is built while the arms move.
      const scale = Math.max(1, Math.ceil(40 / Math.max(0.1, Number(run.makespan)))); // 40 s or more of motion
      // The page's long tasks (main thread busy over 50 ms), to say what held a slow click up.
      await page.addInitScript(() => {
        window.longTasks = [];
        new PerformanceObserver((list) => {
          for (const e of list.getEntries()) window.longTasks.push([Math.round(performance.timeOrigin + e.startTime), Math.round(e.duration)]);
        }).observe({ type: 'longtask', buffered: true });
      });
      await page.goto('about:blank');
      await page.goto(`${url}/#/dispatch?run=${run.uuid}&scale=${scale}`);
      await page.waitForSelector('[data-testid=dispatch-status][data-id]');
      const before = await page.getAttribute('[data-testid=dispatch-status]', 'data-id');
      await page.locator('[data-testid=preflight]').click();
      await page.waitForSelector('[data-testid=preflight-result][data-passed]', { timeout: 60000 });
      expect((await page.getAttribute('[data-testid=preflight-result]', 'data-passed')) === '1', `pre-flight: ${await page.locator('[data-testid=preflight-result]').textContent()}`);
      await page.locator('[data-testid=start]').click();
      // Watch the arms: the live view (after the status line on both the old and the new layout) in view.
      await page.evaluate(() => document.querySelector('[data-testid=dispatch-status]').scrollIntoView({ block: 'start' }));
      const status = async () => (await fetch(`${url}/api/dispatch`, { headers: auth })).json();
      let s = null;
      for (let n = 0; ; n++) {
        s = await status();
        if (s.id !== before && s.state === 'running' && s.elapsed > 0) break;
        expect(n < 600, `the dispatch did not start moving: ${JSON.stringify(s)}`);
        await sleep(100);
      }
      const id = s.id;
      await sleep(3000);
      // A person's click: the mouse pressed where the button is, with none of Playwright's waits for
      // the page to settle (two animation frames with the button in one place) before it.
      const t0 = Date.now();
      const clicked = (async () => {
        const box = await page.locator('[data-testid=abort]').boundingBox({ timeout: 120000 });
        await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
      })().catch((e) => e); // a page too busy to answer is a failure below, not a crash
      let stoppedAfter = -1;
      for (;;) {
        s = await status();
        if (s.id === id && s.final && (s.arms || []).every((a) => a.done)) {
          stoppedAfter = Date.now() - t0;
          break;
        }
        if (Date.now() - t0 > 120000) break;
        await sleep(20);
      }
      const clickError = await clicked;
      const clickedAfter = Date.now() - t0;
      expect(!(clickError instanceof Error), `the click on Abort did not happen: ${clickError && clickError.message}`);
      const renderer = await page.evaluate(() => {
        const canvas = document.querySelector('[data-testid=dispatch-viewer] canvas');
        const gl = canvas && canvas.getContext('webgl2');
        const info = gl && gl.getExtension('WEBGL_debug_renderer_info');
        return gl ? String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER)) : 'no WebGL canvas';
      });
      const drawn = await page.evaluate(() => ({ ...document.querySelector('[data-testid=dispatch-viewer]').dataset }));
      console.log(`  3D view drawn by: ${renderer}; ${drawn.frames} frames, the last held the page ${drawn.drawMs} ms`);
      console.log(`  every arm stopped ${stoppedAfter} ms after the click (the click returned after ${clickedAfter} ms); the dispatch was ${s.state}`);
      const longTasks = await page.evaluate(() => window.longTasks || []);
      const near = longTasks.filter(([start, ms]) => start + ms >= t0 - 2000 && start <= t0 + Math.max(stoppedAfter, 0)).map(([start, ms]) => `${start - t0} ms: ${ms} ms`);
      console.log(`  ${longTasks.length} long tasks on the page, the longest ${Math.max(0, ...longTasks.map((t) => t[1]))} ms; around the click: ${near.join(', ') || 'none'}`);
      expect(/SwiftShader/.test(renderer), `the 3D view is not drawn by SwiftShader: ${renderer}`);
      expect(stoppedAfter >= 0, `the arms had not stopped 120 s after the click: ${JSON.stringify(s)}`);
      expect(s.state === 'aborted' && s.arms.every((a) => a.result.name === 'CANCELLED'), `ended ${s.state}: ${JSON.stringify(s.arms.map((a) => a.result))}`);
      expect(stoppedAfter <= 1000, `the arms stopped ${stoppedAfter} ms after the click on Abort (at most 1000 ms)`);
      await page.screenshot({ path: path.join(ARTIFACTS, 'dispatch-abort-live.png') });
    });

    await step('Dispatch: the live view is on screen without scrolling past the pre-flight checks', async () => {
      const fold = await page.evaluate(() => {
        window.scrollTo(0, 0);
        const r = document.querySelector('[data-testid=dispatch-viewer]').getBoundingClientRect();
        return { top: r.top, height: innerHeight };
      });
      expect(fold.top < fold.height - 200, `the live view starts ${fold.top} px down a ${fold.height} px window: scroll needed to watch the arms`);
    });

    await step('Run page: "Dispatch this plan" checks, shows the checks, enables Dispatch and starts it', async () => {
      // Both arms back at the plan's start (the abort left them mid-plan).
      for (let i = 0; i < robots.length; i++) await restart(i, plan.robots[robots[i]].points[0].q);
      await page.goto(`${url}/#/run/${run.uuid}`);
      const panel = page.locator('[data-testid=run-dispatch-slot] [data-testid=run-dispatch]');
      await panel.waitFor();
      expect(await page.locator('[data-testid=run-dispatch-start]').isDisabled(), 'Dispatch enabled before any check');
      await page.locator('[data-testid=run-dispatch-user]').fill('run page');
      await page.locator('[data-testid=run-dispatch-check]').click();
      await page.waitForSelector('[data-testid=run-dispatch-preflight][data-passed]', { timeout: 60000 });
      const checks = page.locator('[data-testid=run-dispatch-preflight]');
      expect((await checks.getAttribute('data-passed')) === '1', `pre-flight: ${await checks.textContent()}\n${agentLogs()}`);
      const rows = await checks.locator('tbody tr').allTextContents();
      expect(rows.length > 0 && rows.every((r) => r.includes('✓')), `the check table: ${rows.join(' | ')}`);
      expect(robots.every((id) => rows.some((r) => r.includes(id))), `no check row per arm: ${rows.join(' | ')}`);
      expect(!(await page.locator('[data-testid=run-dispatch-start]').isDisabled()), 'Dispatch stays disabled after a passed check');
      await page.screenshot({ path: path.join(ARTIFACTS, 'run-dispatch-checked.png'), fullPage: true });
      await page.locator('[data-testid=run-dispatch-start]').click();
      await page.waitForSelector('[data-testid=run-dispatch-started]', { timeout: 60000 });
      const started = await page.locator('[data-testid=run-dispatch-started]').textContent();
      const id = (started.match(/dispatch (\S+) started/) || [])[1];
      expect(id && id !== firstId, `started: ${started}`);
      let record = null;
      for (let n = 0; ; n++) {
        record = await apiGet(`/api/dispatches/${id}`);
        if (record.state === 'succeeded' || ['failed', 'aborted', 'refused'].includes(record.state)) break;
        expect(n < (Number(run.makespan) + 60) * 10, `dispatch ${id} still ${record.state}`);
        await sleep(100);
      }
      expect(record.state === 'succeeded' && record.run_id === run.uuid && record.requested_by === 'run page', `record: ${JSON.stringify(record)}\n${agentLogs()}`);
    });

    await step('Dispatch by dependencies: each arm\'s step and what it waits for, live; success; the Run page plots planned against executed makespan', async () => {
      // The second arm slowed to 0.7 of the plan's speed: by the clock it would leave its path; by
      // dependencies the first arm waits for it where the graph says.
      await restart(0, plan.robots[robots[0]].points[0].q);
      await restart(1, plan.robots[robots[1]].points[0].q, ['--sim-speed', '0.7']);
      await page.goto('about:blank');
      await page.goto(`${url}/#/dispatch?run=${run.uuid}&execution=tpg`);
      await page.waitForSelector('[data-testid=dispatch-status][data-id]');
      const before = await page.getAttribute('[data-testid=dispatch-status]', 'data-id');
      expect((await page.locator('[data-testid=execution]').inputValue()) === 'tpg', 'the execution in the link is not chosen');
      await page.locator('[data-testid=preflight]').click();
      await page.waitForSelector('[data-testid=preflight-result][data-passed]', { timeout: 60000 });
      const checks = await page.locator('[data-testid=preflight-result]').textContent();
      expect((await page.getAttribute('[data-testid=preflight-result]', 'data-passed')) === '1' && checks.includes('tpg_graph'), `pre-flight: ${checks}`);
      await page.locator('[data-testid=start]').click();
      await page.waitForFunction((first) => {
        const s = document.querySelector('[data-testid=dispatch-status]');
        return s.dataset.state === 'running' && s.dataset.id !== first;
      }, before, { timeout: 60000 });
      const id = await page.getAttribute('[data-testid=dispatch-status]', 'data-id');
      const head = await page.locator('[data-testid=arms-table] thead').textContent();
      expect(head.includes('step') && head.includes('waiting for'), `arms table head: ${head}`);
      // Some arm waits for the other, and says for what ("waits for ur5e_1 step 7 (motion)").
      await page.waitForFunction(() => [...document.querySelectorAll('[data-testid=arm-waiting]')].some((c) => /^waits for \S+ step \d+ \(\w+\)/.test(c.textContent)), null, { timeout: 60000 });
      const waiting = (await page.locator('[data-testid=arm-waiting]').allTextContents()).join(' | ');
      console.log(`  seen: ${waiting}; steps ${(await page.locator('[data-testid=arm-step]').allTextContents()).join(' | ')}`);
      await page.screenshot({ path: path.join(ARTIFACTS, 'dispatch-tpg-running.png'), fullPage: true });
      await page.waitForSelector('[data-testid=dispatch-status][data-final="1"]', { timeout: (3 * Number(run.makespan) + 60) * 1000 });
      const state = await page.getAttribute('[data-testid=dispatch-status]', 'data-state');
      expect(state === 'succeeded', `the dispatch by dependencies ended ${state}: ${await page.locator('[data-testid=dispatch-status]').textContent()}\n${agentLogs()}`);
      for (const robot of robots) await page.waitForSelector(`[data-testid=arms-table] tr[data-robot="${robot}"][data-result=SUCCESSFUL]`);
      const record = await apiGet(`/api/dispatches/${id}`);
      expect(record.execution === 'tpg' && record.arms.every((a) => Array.isArray(a.segments) && a.segments.length > 0 && a.segments.every((g) => g.executed[1] !== null)), `record: ${JSON.stringify(record).slice(0, 400)}`);
      await page.goto(`${url}/#/run/${run.uuid}`);
      const row = page.locator(`[data-testid=run-dispatch-makespans] tr[data-dispatch="${id}"]`);
      await row.waitFor({ timeout: 30000 });
      const planned = Number(await row.getAttribute('data-planned'));
      const executed = Number(await row.getAttribute('data-executed'));
      expect((await row.getAttribute('data-execution')) === 'tpg' && executed > planned && planned > 0, `makespan row: ${await row.textContent()}`);
      expect((await page.locator('[data-testid=run-dispatch-makespans] tr[data-execution=timed]').count()) > 0, 'the timed dispatches of this plan are not plotted');
      console.log(`  planned ${planned.toFixed(2)} s, executed ${executed.toFixed(2)} s by dependencies with one arm at 0.7 speed`);
      await page.screenshot({ path: path.join(ARTIFACTS, 'run-makespans.png'), fullPage: true });
    });

    await step('no console error', async () => {
      expect(consoleErrors.length === 0, `console errors:\n${consoleErrors.join('\n')}`);
    });
  } catch (e) {
    results.push({ name: 'setup', ok: false });
    console.log(`FAIL setup: ${e.stack || e}`);
  } finally {
    await context.close().catch(() => {});
    await Promise.all(agents.map(stopChild));
    await stopChild(server);
    if (!KEEP) fs.rmSync(tmp, { recursive: true, force: true });
  }
  const failed = results.filter((r) => !r.ok);
  console.log(`${results.length - failed.length} passed, ${failed.length} failed; screenshots in ${ARTIFACTS}`);
  process.exit(failed.length ? 1 : 0);
}

main();
