#!/usr/bin/env node
// Browser tests of the dashboard: Playwright (playwright-core from web/node_modules) drives Debian's
// Chromium against `dashbench serve` on a copy of data/demo.db, in a fresh profile.
//   node tests/browser/run.mjs --dashbench BUILD/dashbench [--artifacts DIR] [--keep]
// Checks: the token link signs the browser in; the Launch page validates inline, launches a tiny
// batch and watches it finish; the Runs page filters (and shows filter errors) and chooses columns;
// every Compare plot has data points; a run's 3D view draws and scrubs and plays; the Query page
// refuses writes; the Dispatch page answers; no page logs a console error. Screenshots of each page
// go to the artifacts folder. Exit: 0 passed, 1 failed, 77 skipped (Chromium cannot start here).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { ARTIFACTS, KEEP, loadPlaywright, launchBrowser, startServer, stopServer, step, expect, shot, results, finish } from './harness.mjs';

async function main() {
  const playwright = loadPlaywright();
  fs.mkdirSync(ARTIFACTS, { recursive: true });
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'dashbench-browser-'));
  const context = await launchBrowser(playwright, path.join(tmp, 'profile'));
  let server = null;
  try {
    server = await startServer(tmp);
    const token = fs.readFileSync(path.join(tmp, 'token'), 'utf8').trim();
    const page = context.pages()[0] || (await context.newPage());
    page.setDefaultTimeout(30000);
    const consoleErrors = [];
    // While a step provokes a refusal on purpose (a bad filter, SQL that writes), Chromium's own
    // "Failed to load resource: ... 4xx" line is expected; anything else is still an error.
    let provoking = false;
    page.on('console', (m) => {
      if (m.type() !== 'error') return;
      if (provoking && /Failed to load resource: the server responded with a status of 4\d\d/.test(m.text())) return;
      consoleErrors.push(`${page.url()}: ${m.text()}`);
    });
    page.on('pageerror', (e) => consoleErrors.push(`${page.url()}: ${e.message}`));
    const url = server.url;
    const api = async (p) => (await page.request.get(`${url}${p}`)).json();

    await step('the token link signs the browser in', async () => {
      await page.goto(`${url}/#token=${token}`);
      await page.waitForFunction(() => location.hash === '#/runs');
      const saved = await page.evaluate(() => localStorage.getItem('dashbench.token'));
      expect(saved === token, 'the token was not saved');
      await page.waitForSelector('#token-button:has-text("Token ✓")');
    });

    let batchId = null;
    await step('Launch: inline validation, then a tiny batch runs to the end', async () => {
      await page.goto(`${url}/#/launch`);
      await page.waitForSelector('[data-testid=run-count][data-runs]');
      const objects = page.locator('input[data-param=objects]');
      await objects.fill('999');
      await page.waitForSelector('.field.invalid:has(input[data-param=objects]) .error-text:has-text("out of range")');
      expect(await page.locator('[data-testid=submit]').isDisabled(), 'submit stays disabled on an invalid spec');
      await page.locator('input[data-param=robots]').fill('2');
      await objects.fill('2');
      await page.locator('[data-testid=planner-row] input[type=checkbox]').first().check();
      await page.locator('[data-testid=seed-count]').fill('2');
      await page.locator('[data-testid=time-limit]').fill('20');
      await page.locator('[data-testid=batch-name]').fill('browser');
      await page.waitForSelector('[data-testid=run-count][data-runs="2"]');
      await page.waitForSelector('[data-testid=submit]:not([disabled])');
      await page.locator('[data-testid=submit]').click();
      const result = await page.waitForSelector('[data-testid=launch-result][data-batch]');
      batchId = await result.getAttribute('data-batch');
      await page.waitForSelector(`tr[data-batch="${batchId}"]`);
      await page.waitForSelector(`tr[data-batch="${batchId}"][data-status=finished]`, { timeout: 120000 });
      const label = await page.locator(`tr[data-batch="${batchId}"] .progress-label`).textContent();
      expect(/2\/2 done/.test(label), `progress label: ${label}`);
      await shot(page, 'launch');
    });

    await step('Runs: text filter, filter errors, column chooser', async () => {
      await page.goto(`${url}/#/runs`);
      await page.waitForSelector('[data-testid=runs-total][data-total]');
      const filter = page.locator('[data-testid=filter]');
      provoking = true;
      await filter.fill('robot = 2');
      await filter.press('Enter');
      await page.waitForSelector('[data-testid=filter-error]:has-text("unknown field")');
      provoking = false;
      await filter.fill('status = solved and robots = 2 and config = lazy-dash');
      await filter.press('Enter');
      await page.waitForFunction(() => {
        const rows = [...document.querySelectorAll('[data-testid=runs-table] tbody tr')];
        return document.querySelector('[data-testid=filter-error]').textContent === '' && rows.length > 0 && rows.every((r) => r.dataset.status === 'solved');
      });
      const total = Number(await page.locator('[data-testid=runs-total]').getAttribute('data-total'));
      const expected = (await api(`/api/runs?q=${encodeURIComponent('status = solved and robots = 2 and config = lazy-dash')}`)).total;
      expect(total === expected && total > 0, `the table shows ${total} runs, the API ${expected}`);
      if (batchId) {
        await filter.fill(`batch = "${batchId}"`);
        await filter.press('Enter');
        await page.waitForSelector('[data-testid=runs-total][data-total="2"]');
      }
      await page.locator('button:has-text("Columns")').click();
      await page.locator('[data-testid=columns-panel] input[data-column=makespan]').uncheck();
      await page.locator('[data-testid=columns-panel] input[data-column=time_task_query]').check();
      await page.waitForSelector('[data-testid=runs-table] th[data-column=time_task_query]');
      expect((await page.locator('[data-testid=runs-table] th[data-column=makespan]').count()) === 0, 'makespan column still shown');
      await page.locator('button:has-text("Columns")').click();
      await filter.fill('robots = 2 and objects >= 4');
      await filter.press('Enter');
      const wanted = (await api(`/api/runs?q=${encodeURIComponent('robots = 2 and objects >= 4')}`)).total;
      expect(wanted >= 12, `the demo database has ${wanted} runs with 2 robots and 4 or more objects`);
      await page.waitForFunction((n) => document.querySelector('[data-testid=runs-total]').dataset.total === String(n), wanted);
      const csv = await page.locator('[data-testid=csv]').getAttribute('href');
      const res = await page.request.get(`${url}${csv}`);
      const lines = (await res.text()).trim().split('\n');
      expect(res.ok() && lines[0].includes('time_task_query') && lines.length === wanted + 1, `CSV export of the shown runs and columns: ${lines.length} lines`);
      await shot(page, 'runs');
    });

    await step('Compare: every plot has data points', async () => {
      const two = (await api('/api/runs?limit=2&q=status%20%3D%20solved')).runs.map((r) => r.uuid);
      await page.evaluate((uuids) => sessionStorage.setItem('dashbench.selected', JSON.stringify(uuids)), two);
      await page.goto(`${url}/#/compare`);
      for (const id of ['chart-task-sizes', 'chart-motion-sizes', 'chart-times', 'chart-success', 'chart-builder', 'chart-ratio', 'chart-solved-time', 'chart-time-to-solve']) {
        await page.waitForFunction((sel) => Number(document.querySelector(`[data-testid=${sel}]`)?.dataset.points) > 0, id, { timeout: 30000 });
        expect((await page.locator(`[data-testid=${id}] canvas`).count()) >= 1, `${id} has no canvas`);
      }
      await page.selectOption('[data-testid=builder-style]', 'box');
      await page.waitForFunction(() => document.querySelector('[data-testid=chart-builder]')._chart?.config.type === 'boxplot');
      await page.waitForSelector('[data-testid=diff-table] tbody tr');
      await shot(page, 'compare');
    });

    await step('Run detail: timeline, phases, total time with the wall time beside it, 3D view scrubs and plays', async () => {
      // A run of the batch above: the sum of the phases with the wall time beside it.
      const timed = (await api(`/api/runs?limit=1&q=${encodeURIComponent('wall_time > 0')}`)).runs[0];
      expect(timed, 'the batch above left no run with a wall time');
      await page.goto(`${url}/#/run/${timed.uuid}`);
      const total = await (await page.waitForSelector('[data-testid=run-total-time]')).textContent();
      expect(/^[\d.]+ (µs|ms|s|min).* \(the sum of the phases; wall time [\d.]+ (µs|ms|s)/.test(total), `total time: "${total}"`);
      const run = (await api(`/api/runs?limit=1&q=${encodeURIComponent('has_plan = 1')}`)).runs[0];
      expect(run, 'the demo database has no run with a plan');
      const opened = Date.now();
      await page.goto(`${url}/#/run/${run.uuid}`);
      await page.waitForSelector('[data-testid=viewer][data-ready="1"]', { timeout: 60000 });
      // Issue 41 item 11: how long the first 3D view takes (printed, not asserted: a speed, not a unit test).
      console.log(`first 3D view of the run page ready ${((Date.now() - opened) / 1000).toFixed(2)} s after the navigation`);
      expect((await page.getAttribute('[data-testid=viewer]', 'data-has-plan')) === '1', 'no plan loaded');
      await page.waitForFunction(() => Number(document.querySelector('[data-testid=chart-timeline]').dataset.points) > 0);
      await page.waitForFunction(() => Number(document.querySelector('[data-testid=chart-phases]').dataset.points) > 0);
      const viewer = page.locator('[data-testid=viewer]');
      const tcp0 = await viewer.getAttribute('data-tcp0');
      const scrubber = page.locator('[data-testid=scrubber]');
      await scrubber.evaluate((el) => {
        el.value = '500';
        el.dispatchEvent(new Event('input', { bubbles: true }));
      });
      const t = Number(await viewer.getAttribute('data-time'));
      expect(t > 0, `scrubbing did not move the time (${t})`);
      expect((await viewer.getAttribute('data-tcp0')) !== tcp0, 'scrubbing did not move the first arm');
      const colours = await page.evaluate(() => {
        const gl = document.querySelector('[data-testid=viewer] canvas');
        const c = document.createElement('canvas');
        c.width = 200;
        c.height = 120;
        const ctx = c.getContext('2d');
        ctx.drawImage(gl, 0, 0, 200, 120);
        const data = ctx.getImageData(0, 0, 200, 120).data;
        const seen = new Set();
        for (let i = 0; i < data.length; i += 4) seen.add(`${data[i] >> 4},${data[i + 1] >> 4},${data[i + 2] >> 4}`);
        return seen.size;
      });
      expect(colours > 8, `the 3D view looks empty (${colours} colours)`);
      await scrubber.evaluate((el) => {
        el.value = '0';
        el.dispatchEvent(new Event('input', { bubbles: true }));
      });
      await page.locator('[data-testid=play]').click();
      await page.waitForFunction(() => Number(document.querySelector('[data-testid=viewer]').dataset.time) > 0.2, null, { timeout: 15000 });
      await page.locator('[data-testid=play]').click();
      await scrubber.evaluate((el) => {
        el.value = '650';
        el.dispatchEvent(new Event('input', { bubbles: true }));
      });
      await page.locator('[data-testid=tag-input]').fill('browser-test');
      await page.locator('[data-testid=tag-add]').click();
      await page.waitForSelector('[data-testid=tags] .chip:has-text("browser-test")');
      await shot(page, 'run');
    });

    await step('Query: examples run, writes are refused', async () => {
      await page.goto(`${url}/#/query`);
      await page.locator('.examples a').first().click();
      await page.waitForSelector('[data-testid=query-result] tbody tr');
      provoking = true;
      await page.locator('[data-testid=sql]').fill('DELETE FROM dash_runs');
      await page.locator('[data-testid=run-query]').click();
      await page.waitForSelector('[data-testid=query-status]:has-text("refused")');
      provoking = false;
      await page.locator('[data-testid=sql]').fill('SELECT uuid, family, params, status, total_time FROM dash_runs ORDER BY id LIMIT 12');
      await page.locator('[data-testid=run-query]').click();
      await page.waitForSelector('[data-testid=query-status]:has-text("12 rows")');
      await shot(page, 'query');
    });

    await step('Dispatch: lists controllers or says the API is missing', async () => {
      await page.goto(`${url}/#/dispatch`);
      await page.waitForSelector('[data-testid=controllers] :is(table, div), [data-testid=dispatch-missing]');
      await shot(page, 'dispatch');
    });

    await step('no page logged a console error', async () => {
      expect(consoleErrors.length === 0, `console errors:\n${consoleErrors.join('\n')}`);
    });
  } catch (e) {
    results.push({ name: 'setup', ok: false, error: e });
    console.log(`FAIL setup: ${e.stack || e}`);
  } finally {
    await context.close().catch(() => {});
    await stopServer(server);
    if (!KEEP) fs.rmSync(tmp, { recursive: true, force: true });
  }
  finish();
}

main();
