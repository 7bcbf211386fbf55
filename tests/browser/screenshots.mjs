#!/usr/bin/env node
// The screenshots in docs/dashboard.md: every page of the dashboard at 1440 x 900 (NAME.png) and at
// 800 x 900 (NAME-800.png) on a copy of data/demo.db, in headless Chromium.
//   node tests/browser/screenshots.mjs --dashbench BUILD/dashbench --out docs/img [--widths 1440,800]
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { ROOT, option, loadPlaywright, launchBrowser, startServer, stopServer } from './harness.mjs';

const OUT = path.resolve(option('out', path.join(ROOT, 'docs', 'img')));
const WIDTHS = option('widths', '1440,800').split(',').map(Number).filter((w) => w >= 320 && w <= 4000);

async function main() {
  for (const width of WIDTHS) await shootAll(width, width === 1440 ? '' : `-${width}`);
}

async function shootAll(width, suffix) {
  const playwright = loadPlaywright();
  fs.mkdirSync(OUT, { recursive: true });
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'dashbench-shots-'));
  const context = await launchBrowser(playwright, path.join(tmp, 'profile'), { width, height: 900 });
  let server = null;
  try {
    server = await startServer(tmp);
    const token = fs.readFileSync(path.join(tmp, 'token'), 'utf8').trim();
    const url = server.url;
    const page = context.pages()[0] || (await context.newPage());
    page.setDefaultTimeout(120000); // a loaded machine takes a while to draw a page
    const api = async (p) => (await page.request.get(`${url}${p}`)).json();
    const shot = async (name, fullPage = false) => {
      await page.waitForTimeout(300);
      await page.screenshot({ path: path.join(OUT, `${name}${suffix}.png`), fullPage });
      console.log(`wrote ${path.join(OUT, `${name}${suffix}.png`)}`);
    };
    const drawn = (id) => page.waitForFunction((sel) => Number(document.querySelector(`[data-testid=${sel}]`)?.dataset.points) > 0, id);
    await page.goto(`${url}/#token=${token}`);
    await page.waitForFunction(() => location.hash === '#/runs');

    // A sweep of the clearance next to the paper profile: the planner parameters in use.
    const spec = { name: 'clearance-sweep', time_limit: 30, memory_limit: 4096, scenarios: [{ family: 'sorting', params: { robots: [2, 4], objects: 4 } }], planners: [{ name: 'lazy-dash', label: 'lazy-dash' }, { name: 'lazy-dash', label: 'clr', settings: { clearance: 0.005 } }], seeds: { from: 1, count: 3 } };
    await page.goto(`${url}/#/launch?spec=${encodeURIComponent(JSON.stringify(spec))}`);
    await page.waitForSelector('[data-testid=run-count][data-runs]');
    await page.locator('[data-testid=planner-row] >> nth=1 >> [data-setting=clearance]').fill('0.002, 0.005');
    await page.locator('[data-testid=planner-row] >> nth=0 >> summary').click();
    await page.locator('[data-testid=planner-row] >> nth=0 >> [data-testid=profile-paper]').click();
    await page.waitForSelector('[data-testid=run-count][data-runs="18"]');
    await page.evaluate(() => window.scrollTo(0, 0));
    await shot('launch');

    await page.goto(`${url}/#/runs?q=${encodeURIComponent('family = sorting and (robots = 4 or objects = 6)')}&sort=total_time&order=desc`);
    await page.waitForSelector('[data-testid=runs-total][data-total]');
    await shot('runs');

    await page.goto(`${url}/#/compare?family=sorting&x=objects&split=robots`);
    for (const id of ['chart-task-sizes', 'chart-times', 'chart-success', 'chart-builder', 'chart-solved-time']) await drawn(id);
    await page.setViewportSize({ width, height: 900 });
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
