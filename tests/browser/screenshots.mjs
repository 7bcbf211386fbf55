#!/usr/bin/env node
// The screenshots in docs/dashboard.md: every page of the dashboard at 1440 x 900 on a copy of
// data/demo.db, in headless Chromium.
//   node tests/browser/screenshots.mjs --dashbench BUILD/dashbench --out docs/img
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { ROOT, option, loadPlaywright, launchBrowser, startServer, stopServer } from './harness.mjs';

const OUT = path.resolve(option('out', path.join(ROOT, 'docs', 'img')));

async function main() {
  const playwright = loadPlaywright();
  fs.mkdirSync(OUT, { recursive: true });
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'dashbench-shots-'));
  const context = await launchBrowser(playwright, path.join(tmp, 'profile'), { width: 1440, height: 900 });
  let server = null;
  try {
    server = await startServer(tmp);
    const token = fs.readFileSync(path.join(tmp, 'token'), 'utf8').trim();
    const url = server.url;
    const page = context.pages()[0] || (await context.newPage());
    page.setDefaultTimeout(60000);
    const api = async (p) => (await page.request.get(`${url}${p}`)).json();
    const shot = async (name, fullPage = false) => {
      await page.waitForTimeout(300);
      await page.screenshot({ path: path.join(OUT, `${name}.png`), fullPage });
      console.log(`wrote ${path.join(OUT, `${name}.png`)}`);
    };
    const drawn = (id) => page.waitForFunction((sel) => Number(document.querySelector(`[data-testid=${sel}]`)?.dataset.points) > 0, id);
    await page.goto(`${url}/#token=${token}`);
    await page.waitForFunction(() => location.hash === '#/runs');

    await page.goto(`${url}/#/launch`);
    await page.waitForSelector('[data-testid=run-count][data-runs]');
    await shot('launch');

    await page.goto(`${url}/#/runs?q=${encodeURIComponent('family = sorting and (robots = 4 or objects = 6)')}&sort=total_time&order=desc`);
    await page.waitForSelector('[data-testid=runs-total][data-total]');
    await shot('runs');

    await page.goto(`${url}/#/compare?family=sorting&x=objects&split=robots`);
    for (const id of ['chart-task-sizes', 'chart-times', 'chart-success', 'chart-builder', 'chart-solved-time']) await drawn(id);
    await page.setViewportSize({ width: 1440, height: 900 });
    await shot('compare', true);

    const [a, b] = (await api(`/api/runs?limit=2&sort=id&order=asc&q=${encodeURIComponent('has_plan = 1 and robots = 4 and objects = 4')}`)).runs;
    await page.goto(`${url}/#/run/${a.uuid}`);
    await page.waitForSelector('[data-testid=viewer][data-ready="1"]');
    await drawn('chart-timeline');
    await page.locator('[data-testid=scrubber]').evaluate((el) => {
      el.value = '450';
      el.dispatchEvent(new Event('input', { bubbles: true }));
    });
    await shot('run');
    if (b) {
      await page.goto(`${url}/#/run/${a.uuid}?overlay=${b.uuid}`);
      await page.waitForSelector('[data-testid=viewer-overlay][data-ready="1"]');
      await drawn('chart-timeline');
      await page.locator('[data-testid=scrubber]').evaluate((el) => {
        el.value = '450';
        el.dispatchEvent(new Event('input', { bubbles: true }));
      });
      await page.locator('[data-testid=viewer]').scrollIntoViewIfNeeded();
      await shot('run-overlay');
    }

    // planner_settings holds every effective parameter of a batch run: the query picks one setting.
    const sql = "SELECT family, planner, coalesce(json_extract(planner_settings, '$.task_only'), 0) AS task_only, status, count(*) AS runs, round(avg(total_time), 3) AS mean_s, round(avg(time_validation), 3) AS validation_s FROM dash_runs GROUP BY 1, 2, 3, 4 ORDER BY 1, 2, 3, 4";
    await page.goto(`${url}/#/query?sql=${encodeURIComponent(sql)}`);
    await page.waitForSelector('[data-testid=query-status].ok');
    await shot('query');

    await page.goto(`${url}/#/dispatch`);
    await page.waitForSelector('[data-testid=controllers] :is(table, div), [data-testid=dispatch-missing]');
    await shot('dispatch');
  } finally {
    await context.close().catch(() => {});
    await stopServer(server);
    fs.rmSync(tmp, { recursive: true, force: true });
  }
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
