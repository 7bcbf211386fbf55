#!/usr/bin/env node
// Browser test of the Launch page's planner parameters (issue 41, item 2): a #/launch?spec= link with
// two lazy-dash configurations (clearance 0.005 and 0.002, labels clr5 and clr2) keeps both settings
// in the form, the spec preview and the rewritten URL; the paper profile is one click; a list of
// values sweeps (one configuration per value) and survives a reload; a sweep launched from the page
// runs with each configuration's setting stored on its runs. No console errors.
//   node tests/browser/launch_params.mjs --dashbench BUILD/dashbench [--artifacts DIR] [--keep]
// Exit: 0 passed, 1 failed, 77 skipped (Chromium cannot start here).
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { KEEP, loadPlaywright, launchBrowser, startServer, stopServer, step, expect, shot, results, finish, watchConsole, ARTIFACTS } from './harness.mjs';

const LINK_SPEC = {
  name: 'clearances',
  time_limit: 60,
  memory_limit: 2048,
  scenarios: [{ family: 'sorting', params: { robots: 2, objects: 2 } }],
  planners: [
    { name: 'lazy-dash', label: 'clr5', settings: { clearance: 0.005 } },
    { name: 'lazy-dash', label: 'clr2', settings: { clearance: 0.002 } },
  ],
  seeds: { from: 1, count: 1 },
};

async function main() {
  const playwright = loadPlaywright();
  fs.mkdirSync(ARTIFACTS, { recursive: true });
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'dashbench-launch-'));
  const context = await launchBrowser(playwright, path.join(tmp, 'profile'));
  let server = null;
  const page = context.pages()[0] || (await context.newPage());
  try {
    server = await startServer(tmp);
    const url = server.url;
    const token = fs.readFileSync(path.join(tmp, 'token'), 'utf8').trim();
    page.setDefaultTimeout(90000); // a loaded 2-core machine takes 15 s to load a page
    page.setDefaultNavigationTimeout(120000);
    const consoleErrors = watchConsole(page);
    const preview = async () => JSON.parse(await page.evaluate(() => document.querySelector('[data-testid=spec-preview]').textContent));
    const urlSpec = () => page.evaluate(() => JSON.parse(new URLSearchParams(location.hash.split('?')[1]).get('spec')));
    const planners = (spec) => spec.planners.map((p) => ({ label: p.label, clearance: p.settings && p.settings.clearance }));
    await page.goto(`${url}/#token=${token}`);
    await page.waitForFunction(() => location.hash === '#/runs');

    await step('Launch link: both configurations keep their clearance in the form, the preview and the URL', async () => {
      await page.goto(`${url}/#/launch?spec=${encodeURIComponent(JSON.stringify(LINK_SPEC))}`);
      await page.waitForSelector('[data-testid=run-count][data-runs="2"]');
      const rows = page.locator('[data-testid=planner-row]');
      expect((await rows.count()) === 2, `${await rows.count()} planner rows`);
      const form = await page.evaluate(() =>
        [...document.querySelectorAll('[data-testid=planner-row]')].map((r) => ({ label: r.querySelector('[data-testid=planner-label]')?.value, clearance: r.querySelector('[data-setting=clearance]')?.value })),
      );
      expect(JSON.stringify(form) === JSON.stringify([{ label: 'clr5', clearance: '0.005' }, { label: 'clr2', clearance: '0.002' }]), `the form: ${JSON.stringify(form)}`);
      const want = JSON.stringify([{ label: 'clr5', clearance: 0.005 }, { label: 'clr2', clearance: 0.002 }]);
      expect(JSON.stringify(planners(await preview())) === want, `the spec preview: ${JSON.stringify((await preview()).planners)}`);
      await page.waitForFunction(() => decodeURIComponent(location.hash).includes('"clearance":0.005'));
      expect(JSON.stringify(planners(await urlSpec())) === want, `the URL: ${JSON.stringify((await urlSpec()).planners)}`);
    });

    await step('Launch: every named parameter per configuration; the paper profile and the defaults one click away', async () => {
      const parameters = (await (await page.request.get(`${url}/api/planners`)).json()).planners.find((p) => p.name === 'lazy-dash').parameters;
      const fields = await page.locator('[data-testid=planner-row] >> nth=0 >> [data-setting]').count();
      expect(parameters.length > 10 && fields === parameters.length, `${fields} fields for ${parameters.length} parameters`);
      const first = page.locator('[data-testid=planner-row]').first();
      await first.locator('[data-testid=profile-paper]').click();
      const paper = Object.fromEntries(parameters.filter((p) => p.paper !== '').map((p) => [p.name, p.type === 'bool' ? p.paper === 'true' : Number(p.paper)]));
      await page.waitForFunction((n) => JSON.parse(document.querySelector('[data-testid=spec-preview]').textContent).planners[0].settings && Object.keys(JSON.parse(document.querySelector('[data-testid=spec-preview]').textContent).planners[0].settings).length === n, Object.keys(paper).length + 1);
      const settings = (await preview()).planners[0].settings;
      expect(Object.entries(paper).every(([k, v]) => settings[k] === v) && settings.clearance === 0.005, `paper profile settings: ${JSON.stringify(settings)}`);
      await page.waitForSelector('[data-testid=run-count][data-runs="2"]');
      await first.locator('[data-testid=profile-default]').click();
      await page.waitForFunction(() => !JSON.parse(document.querySelector('[data-testid=spec-preview]').textContent).planners[0].settings);
      await shot(page, 'launch-parameters');
    });

    await step('Launch: a list of values sweeps, one configuration per value, kept by a reload', async () => {
      await page.locator('[data-testid=planner-row] >> nth=1 >> [data-setting=clearance]').fill('0.002, 0.004');
      await page.waitForSelector('[data-testid=run-count][data-runs="3"]');
      const swept = planners(await preview()).slice(1);
      expect(JSON.stringify(swept) === JSON.stringify([{ label: 'clr2 clearance=0.002', clearance: 0.002 }, { label: 'clr2 clearance=0.004', clearance: 0.004 }]), `the sweep: ${JSON.stringify(swept)}`);
      const before = await preview();
      await page.waitForFunction(() => decodeURIComponent(location.hash).includes('"clearance":0.004'));
      await page.reload();
      await page.waitForSelector('[data-testid=run-count][data-runs="3"]');
      const after = await preview();
      expect(JSON.stringify(after.planners) === JSON.stringify(before.planners), `after a reload: ${JSON.stringify(after.planners)} (before: ${JSON.stringify(before.planners)})`);
    });

    await step('Launch: a sweep launched from the page stores each configuration\'s setting on its runs', async () => {
      const spec = { ...LINK_SPEC, name: 'sweep', planners: [{ name: 'lazy-dash', label: 'sweep', settings: { task_only: true } }] };
      await page.goto(`${url}/#/launch?spec=${encodeURIComponent(JSON.stringify(spec))}`);
      await page.waitForSelector('[data-testid=run-count][data-runs="1"]');
      await page.locator('[data-testid=planner-params-summary]').click(); // folded: no setting but task_only
      await page.locator('[data-setting=clearance]').fill('0.001, 0.003');
      await page.waitForSelector('[data-testid=run-count][data-runs="2"]');
      await page.waitForSelector('[data-testid=submit]:not([disabled])');
      await page.locator('[data-testid=submit]').click();
      const batch = await (await page.waitForSelector('[data-testid=launch-result][data-batch]')).getAttribute('data-batch');
      await page.waitForSelector('[data-testid=launch-result][data-status=finished]', { timeout: 180000 });
      const runs = (await (await page.request.get(`${url}/api/batches/${batch}`)).json()).runs;
      const got = [];
      for (const r of runs) {
        const d = await (await page.request.get(`${url}/api/runs/${r.uuid}`)).json();
        got.push([r.config, d.settings.clearance, d.settings.task_only]);
      }
      got.sort();
      expect(JSON.stringify(got) === JSON.stringify([['sweep clearance=0.001', 0.001, true], ['sweep clearance=0.003', 0.003, true]]), `the runs: ${JSON.stringify(got)}`);
    });

    await step('no console error', async () => {
      expect(consoleErrors.length === 0, `console errors:\n${consoleErrors.join('\n')}`);
    });
  } catch (e) {
    results.push({ name: 'setup', ok: false });
    console.log(`FAIL setup: ${e.stack || e}`);
  } finally {
    await context.close().catch(() => {});
    await stopServer(server);
    if (!KEEP) fs.rmSync(tmp, { recursive: true, force: true });
  }
  finish();
}

main();
