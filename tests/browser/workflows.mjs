#!/usr/bin/env node
// Browser tests of the researcher's workflows on the dashboard (issue 26), against `dashbench serve`
// on a copy of data/demo.db:
//   node tests/browser/workflows.mjs --dashbench BUILD/dashbench [--artifacts DIR] [--keep]
// Checks: every page's state survives a reload of its URL (Compare, Runs, Run detail, Query); plot
// exports download a valid SVG (publication size, real text), PNG (300 dpi) and CSV, and the Query
// page's CSV; log axes keep labels on a narrow range and leave room around the data; Planner Arena's
// solved-against-time curve keeps unsolved runs in the denominator; a click on a plot point opens its
// runs; runs filter with "or" and sort from the keyboard, and a bad filter leaves no stale table;
// run detail links to its batch and downloads its scene and plan; overlays draw two runs on one plot
// and two plans on one clock; sizes over time show hyperarcs as well as vertices, the phase breakdown
// keeps millisecond phases (log axis, labelled bars), Compare's time panels include validation;
// Space, arrows and Shift+arrows drive the playback, Enter adds a tag;
// Launch sends one batch however fast it is clicked and its line follows the batch to its end; a run
// opened while running shows its 3D plan when it ends, and its planner line shows its settings (no
// "[object Object]", no raw "{}"). No console errors.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { ARTIFACTS, KEEP, loadPlaywright, launchBrowser, startServer, stopServer, step, expect, shot, results, finish, watchConsole, sleep } from './harness.mjs';

async function downloadOf(page, click) {
  const [dl] = await Promise.all([page.waitForEvent('download', { timeout: 30000 }), click()]);
  const file = await dl.path();
  return { name: dl.suggestedFilename(), bytes: fs.readFileSync(file) };
}

/// Width and height of a PNG from its IHDR chunk.
function pngSize(bytes) {
  expect(bytes.subarray(1, 4).toString() === 'PNG', 'not a PNG');
  return { width: bytes.readUInt32BE(16), height: bytes.readUInt32BE(20) };
}

function csvRows(text) {
  return text.trim().split(/\r?\n/);
}

async function main() {
  const playwright = loadPlaywright();
  fs.mkdirSync(ARTIFACTS, { recursive: true });
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'dashbench-workflows-'));
  const context = await launchBrowser(playwright, path.join(tmp, 'profile'), { downloads: true });
  let server = null;
  try {
    server = await startServer(tmp);
    const token = fs.readFileSync(path.join(tmp, 'token'), 'utf8').trim();
    const url = server.url;
    const page = context.pages()[0] || (await context.newPage());
    page.setDefaultTimeout(30000);
    let provoking = false;
    const consoleErrors = watchConsole(page, () => provoking);
    const api = async (p) => (await page.request.get(`${url}${p}`)).json();
    await page.goto(`${url}/#token=${token}`);
    await page.waitForFunction(() => location.hash === '#/runs');
    const points = (id) => page.waitForFunction((sel) => Number(document.querySelector(`[data-testid=${sel}]`)?.dataset.points) > 0, id, { timeout: 30000 });

    await step('Compare: settings live in the URL and a reload reproduces the view', async () => {
      await page.goto(`${url}/#/compare`);
      await points('chart-task-sizes');
      await page.selectOption('[data-testid=compare-split]', '');
      await page.selectOption('[data-testid=builder-metric]', 'collision_checks');
      await page.selectOption('[data-testid=builder-style]', 'box');
      await page.locator('[data-testid=compare-filter]').fill('robots = 2 or robots = 4');
      await page.locator('[data-testid=compare-filter]').press('Enter');
      await page.waitForFunction(() => location.hash.includes('metric=collision_checks') && location.hash.includes('style=box') && location.hash.includes('split=none'));
      const hash = await page.evaluate(() => location.hash);
      expect(/family=sorting/.test(hash) && /x=objects/.test(hash) && /q=robots/.test(hash), `the URL lacks the settings: ${hash}`);
      await page.goto(`${url}/#/runs`);
      await page.goto(`${url}/${hash}`);
      await points('chart-builder');
      const values = await page.evaluate(() => ({
        metric: document.querySelector('[data-testid=builder-metric]').value,
        style: document.querySelector('[data-testid=builder-style]').value,
        split: document.querySelector('[data-testid=compare-split]').value,
        filter: document.querySelector('[data-testid=compare-filter]').value,
        type: document.querySelector('[data-testid=chart-builder]')._chart.config.type,
      }));
      expect(values.metric === 'collision_checks' && values.style === 'box' && values.split === '' && values.filter === 'robots = 2 or robots = 4' && values.type === 'boxplot', `after a reload: ${JSON.stringify(values)}`);
    });

    await step('Compare: every plot is drawn, and the paper\u2019s figures show both planners', async () => {
      await page.goto(`${url}/#/compare?family=sorting`);
      for (const id of ['chart-task-sizes', 'chart-motion-sizes', 'chart-times', 'chart-success', 'chart-builder', 'chart-ratio', 'chart-solved-time', 'chart-time-to-solve']) await points(id);
      const labels = await page.evaluate(() => document.querySelector('[data-testid=chart-task-sizes]')._chart.data.datasets.map((d) => d.label));
      expect(labels.some((l) => /^dash\b/.test(l)) && labels.some((l) => /^lazy-dash\b/.test(l)), `the size plot lacks a planner: ${labels.join(' | ')}`);
      expect(labels.some((l) => l.includes('H_T')) && labels.some((l) => l.includes('H_M')), `the size plot lacks a layer: ${labels.join(' | ')}`);
      // The time panels include the validation phase where the runs carry it (schema v5).
      const validated = (await api(`/api/runs?limit=1&q=${encodeURIComponent('family = sorting and config = lazy-dash and time_validation > 0')}`)).total;
      expect(validated > 0, 'no Lazy-DaSH run of the demo database has a validation time');
      const timeLabels = await page.evaluate(() => [...document.querySelectorAll('[data-testid=chart-times] .chart-box')].filter((b) => /^lazy-dash\b/.test(b.dataset.series || '') && b._chart).flatMap((b) => b._chart.data.datasets.map((d) => d.label)));
      expect(timeLabels.includes('validation') && timeLabels.includes('total'), `the Lazy-DaSH time panel lacks validation: ${timeLabels.join(' | ')}`);
      await shot(page, 'compare-figures');
    });

    await step('Exports: SVG at publication size with real text, PNG at 300 dpi, CSV of the aggregated data', async () => {
      const svg = await downloadOf(page, () => page.locator('[data-testid=chart-task-sizes-svg]').click());
      const text = svg.bytes.toString('utf8');
      expect(svg.name.endsWith('.svg') && text.startsWith('<?xml') && /<svg[^>]+width="3.5in"/.test(text), `not a 3.5 in SVG: ${svg.name} ${text.slice(0, 200)}`);
      expect((text.match(/<path /g) || []).length > 20, 'the SVG has too few paths');
      expect(/<text[^>]*>vertices \(count, log scale\)<\/text>/.test(text), 'the SVG lacks the y axis title as text');
      expect(!/NaN|undefined/.test(text), 'the SVG has NaN or undefined in it');
      const valid = await page.evaluate((t) => !new DOMParser().parseFromString(t, 'image/svg+xml').querySelector('parsererror'), text);
      expect(valid, 'the SVG does not parse');
      const png = await downloadOf(page, () => page.locator('[data-testid=chart-times-0-png]').click());
      const size = pngSize(png.bytes);
      expect(size.width === 1050 && Math.abs(size.height - 780) <= 2, `PNG of ${size.width} x ${size.height} px, expected 3.5 x 2.6 in at 300 dpi`);
      const csv = await downloadOf(page, () => page.locator('[data-testid=chart-success-csv]').click());
      const lines = csvRows(csv.bytes.toString('utf8'));
      expect(lines[0] === 'series,x,finished,solved,skipped,rate,rate_low,rate_high' && lines.length > 3, `success CSV: ${lines.slice(0, 3).join(' / ')}`);
      const panels = await page.evaluate(() => [...document.querySelectorAll('[data-testid=chart-times] .chart-box')].filter((b) => Number(b.dataset.points) > 0).length);
      const figure = (await downloadOf(page, () => page.locator('[data-testid=figure-times-svg]').click())).bytes.toString('utf8');
      const nested = (figure.match(/<svg x="/g) || []).length;
      const ids = [...figure.matchAll(/id="([^"]+)"/g)].map((m) => m[1]);
      expect(nested === panels && panels >= 2, `the time figure has ${nested} panels, the page ${panels}`);
      expect(new Set(ids).size === ids.length, 'clip ids repeat across the panels');
      expect(await page.evaluate((t) => !new DOMParser().parseFromString(t, 'image/svg+xml').querySelector('parsererror'), figure), 'the figure SVG does not parse');
      const both = pngSize((await downloadOf(page, () => page.locator('[data-testid=figure-sizes-png]').click())).bytes);
      expect(both.width === 2100 && Math.abs(both.height - 780) <= 2, `the sizes figure PNG is ${both.width} x ${both.height}`);
      const sizes = await downloadOf(page, () => page.locator('[data-testid=chart-task-sizes-csv]').click());
      const rows = csvRows(sizes.bytes.toString('utf8'));
      expect(rows[0].startsWith('series,part,metric,x,n,median') && rows.length > 5, `sizes CSV: ${rows[0]}`);
    });

    await step('Log axes: labels on a narrow range, room around the data', async () => {
      const r = await page.evaluate(async () => {
        const { drawChart, valueAxis, logTicks } = await import('/js/charts.js');
        const box = document.createElement('div');
        box.className = 'chart-box';
        document.body.append(box);
        const chart = drawChart(box, { type: 'line', data: { datasets: [{ label: 'H_M', data: [{ x: 1, y: 28 }, { x: 2, y: 31 }, { x: 3, y: 36 }] }] }, options: { scales: { x: { type: 'linear' }, y: valueAxis('vertices', { log: true }) } } }, 3);
        const y = chart.scales.y;
        const labels = y.ticks.map((t) => t.label).filter((l) => l !== '' && l !== undefined);
        const out = { labels, min: y.min, max: y.max, wide: logTicks(3, 40000) };
        chart.destroy();
        box.remove();
        return out;
      });
      expect(r.labels.length >= 3, `narrow log axis labels: ${JSON.stringify(r.labels)}`);
      expect(r.min < 28 && r.max > 36, `no room around the data: ${r.min}..${r.max}`);
      expect(r.wide.includes(10) && r.wide.includes(10000), `wide range ticks: ${r.wide}`);
      const empty = await page.evaluate(() =>
        [...document.querySelectorAll('.chart-box')]
          .filter((b) => b._chart && b._chart.scales.y && b._chart.scales.y.type === 'logarithmic')
          .map((b) => [b.dataset.testid, b._chart.scales.y.ticks.filter((t) => t.label).length])
          .filter(([, n]) => n < 2),
      );
      expect(empty.length === 0, `log axes with fewer than 2 labels: ${JSON.stringify(empty)}`);
    });

    await step('Planner Arena: unsolved runs stay in the denominator', async () => {
      const r = await page.evaluate(() => {
        const chart = document.querySelector('[data-testid=chart-solved-time]')._chart;
        return chart.data.datasets.map((d) => ({ label: d.label, last: d.data[d.data.length - 1].y }));
      });
      for (const d of r) {
        const m = d.label.match(/\((\d+) of (\d+)\)$/);
        expect(m, `label without counts: ${d.label}`);
        const expected = (100 * Number(m[1])) / Number(m[2]);
        expect(Math.abs(d.last - expected) < 1e-6, `${d.label} ends at ${d.last} %, expected ${expected} %`);
      }
    });

    await step('A click on a plot point opens its runs', async () => {
      const box = page.locator('[data-testid=chart-success]');
      // The middle of the first bar that stands for runs (success is drawn as grouped bars).
      const pos = await box.evaluate((b) => {
        const chart = b._chart;
        for (let i = 0; i < chart.data.datasets.length; ++i) {
          const meta = chart.getDatasetMeta(i);
          const k = meta.data.findIndex((e, j) => !e.skip && chart.data.datasets[i].data[j] && chart.data.datasets[i].data[j].filter);
          if (k >= 0) return { x: meta.data[k].x, y: (meta.data[k].y + meta.data[k].base) / 2 };
        }
        return null;
      });
      expect(pos, 'the success plot has no bar with runs');
      await box.locator('canvas').click({ position: pos });
      await page.waitForFunction(() => location.hash.startsWith('#/runs?q='));
      const q = await page.evaluate(() => decodeURIComponent(new URLSearchParams(location.hash.split('?')[1]).get('q')));
      expect(/family = "sorting"/.test(q) && /config = /.test(q) && /objects = \d/.test(q), `the runs filter: ${q}`);
      await page.waitForSelector('[data-testid=runs-total][data-total]');
      const n = Number(await page.getAttribute('[data-testid=runs-total]', 'data-total'));
      expect(n >= 1 && n <= 6, `the point opened ${n} runs`);
    });

    await step('Runs: "or", keyboard sorting in the URL, no stale table under an error', async () => {
      await page.goto(`${url}/#/runs`);
      await page.waitForSelector('[data-testid=runs-total][data-total]');
      const filter = page.locator('[data-testid=filter]');
      await filter.fill('objects = 2 or objects = 6');
      await filter.press('Enter');
      const expected = (await api(`/api/runs?q=${encodeURIComponent('objects = 2 or objects = 6')}`)).total;
      const all = (await api('/api/runs')).total;
      expect(expected > 0 && expected < all, `"or" matched ${expected} of ${all}`);
      await page.waitForSelector(`[data-testid=runs-total][data-total="${expected}"]`);
      const th = page.locator('[data-testid=runs-table] th[data-column=total_time]');
      await th.focus();
      await page.keyboard.press('Enter');
      await page.waitForSelector('[data-testid=runs-table] th[data-column=total_time][aria-sort=descending]');
      await page.keyboard.press('Enter');
      await page.waitForSelector('[data-testid=runs-table] th[data-column=total_time][aria-sort=ascending]');
      const hash = await page.evaluate(() => location.hash);
      expect(hash.includes('sort=total_time') && hash.includes('order=asc'), `sort not in the URL: ${hash}`);
      await page.reload();
      await page.waitForSelector('[data-testid=runs-table] th[data-column=total_time][aria-sort=ascending]');
      expect((await filter.inputValue()) === 'objects = 2 or objects = 6', 'the filter did not survive a reload');
      const fit = await page.evaluate(() => {
        const wrap = document.querySelector('[data-testid=runs-table]');
        return { scroll: wrap.scrollWidth, client: wrap.clientWidth };
      });
      expect(fit.scroll <= fit.client + 1, `the default columns overflow at 1440 px: ${fit.scroll} > ${fit.client}`);
      provoking = true;
      await filter.fill('robots >= many');
      await filter.press('Enter');
      await page.waitForSelector('[data-testid=filter-error]:has-text("is a number")');
      provoking = false;
      expect((await page.locator('[data-testid=runs-table] tbody tr').count()) === 0, 'the old table stayed under the error');
      await shot(page, 'runs-error');
    });

    await step('Runs: the selection is in the URL and narrows Compare', async () => {
      await page.goto(`${url}/#/runs?q=${encodeURIComponent('family = sorting and status = solved')}`);
      await page.waitForSelector('[data-testid=runs-table] tbody tr');
      const boxes = page.locator('[data-testid=runs-table] tbody tr input[type=checkbox]');
      for (let i = 0; i < (await boxes.count()); i++) await boxes.nth(i).uncheck();
      await boxes.nth(0).check();
      await boxes.nth(1).check();
      const uuids = await page.evaluate(() => [...document.querySelectorAll('[data-testid=runs-table] tbody tr')].slice(0, 2).map((r) => r.dataset.uuid));
      await page.waitForFunction((u) => decodeURIComponent(location.hash).includes(`sel=${u.join(',')}`) || decodeURIComponent(location.hash).includes(`sel=${[...u].reverse().join(',')}`), uuids);
      await page.reload();
      await page.waitForSelector('[data-testid=runs-table] tbody tr');
      const checked = await page.evaluate(() => [...document.querySelectorAll('[data-testid=runs-table] tbody tr')].filter((r) => r.querySelector('input').checked).map((r) => r.dataset.uuid));
      expect(checked.length === 2 && uuids.every((u) => checked.includes(u)), `after a reload: ${checked}`);
      await page.locator('[data-testid=compare-selected]').click();
      await page.waitForSelector('[data-testid=compare-info][data-runs="2"]');
      await page.waitForSelector('[data-testid=diff-table] tbody tr');
    });

    const solved = (await api(`/api/runs?limit=2&sort=id&order=asc&q=${encodeURIComponent('has_plan = 1 and robots = 2')}`)).runs;
    await step('Run detail: batch link, scene and plan downloads, the URL keeps the overlay', async () => {
      expect(solved.length === 2, 'the demo database needs two solved 2-robot runs');
      const [a, b] = solved;
      await page.goto(`${url}/#/run/${a.uuid}?overlay=${b.uuid}`);
      await page.waitForSelector('[data-testid=viewer][data-ready="1"]', { timeout: 60000 });
      await page.waitForSelector('[data-testid=viewer-overlay][data-ready="1"]', { timeout: 60000 });
      const batch = await page.getAttribute('[data-testid=batch-link]', 'href');
      expect(batch === `#/runs?q=${encodeURIComponent(`batch = "${a.batch}"`)}`, `batch link ${batch}`);
      for (const [id, check] of [['download-scene', (j) => Array.isArray(j.robots) && Array.isArray(j.objects)], ['download-plan', (j) => j.robots && Array.isArray(j.events)]]) {
        const dl = await downloadOf(page, () => page.locator(`[data-testid=${id}]`).click());
        const json = JSON.parse(dl.bytes.toString('utf8'));
        expect(dl.name.endsWith('.json') && check(json), `${id}: ${dl.name}`);
      }
      await points('chart-timeline');
      const labels = await page.evaluate(() => document.querySelector('[data-testid=chart-timeline]')._chart.data.datasets.map((d) => d.label));
      expect(labels.some((l) => l.startsWith(a.uuid.slice(0, 8))) && labels.some((l) => l.startsWith(b.uuid.slice(0, 8))), `the sizes plot does not overlay both runs: ${labels}`);
      const marks = await page.evaluate(() => document.querySelector('[data-testid=chart-marks]')._chart?.data.datasets.map((d) => d.label) || []);
      expect(marks.length === 0 || marks.every((l) => l === a.uuid.slice(0, 8) || l === b.uuid.slice(0, 8)), `marks datasets: ${marks}`);
      const yTicks = await page.evaluate(() => document.querySelector('[data-testid=chart-marks]')._chart?.scales.y.ticks.map((t) => t.label));
      expect(!yTicks || (yTicks.includes('frontier') && yTicks.includes('task space expansion')), `kind axis labels: ${yTicks}`);
      await page.reload();
      await page.waitForSelector('[data-testid=viewer-overlay][data-ready="1"]', { timeout: 60000 });
      await shot(page, 'run-overlay');
    });

    await step('Keyboard: Space plays and pauses, arrows step, Shift+arrow to the next plan point, Enter tags', async () => {
      const time = async (sel = 'viewer') => Number(await page.getAttribute(`[data-testid=${sel}]`, 'data-time'));
      await page.locator('h1').click();
      await page.keyboard.press('Space');
      await page.waitForFunction(() => Number(document.querySelector('[data-testid=viewer]').dataset.time) > 0.1, null, { timeout: 15000 });
      await page.keyboard.press('Space');
      const paused = await time();
      await sleep(400);
      expect((await time()) === paused, 'Space did not pause');
      expect((await time('viewer-overlay')) > 0, 'the overlaid plan did not move with the clock');
      const label = await page.textContent('[data-testid=time-label]');
      const duration = Number(label.match(/\/ ([\d.]+) s/)[1]);
      await page.keyboard.press('ArrowRight');
      const stepped = await page.evaluate(() => Number(document.querySelector('[data-testid=scrubber]').value));
      expect(Math.abs((await time()) - Math.min(paused + 0.01 * duration, duration)) < 0.01 + 1e-3 * duration || stepped > 0, `ArrowRight: ${paused} -> ${await time()}`);
      const before = await time();
      await page.keyboard.press('Shift+ArrowRight');
      const after = await time();
      const points = await page.evaluate(async (uuids) => {
        const out = [];
        for (const uuid of uuids) {
          const plan = await (await fetch(`/api/runs/${uuid}/plan`)).json();
          out.push(...Object.values(plan.robots).flatMap((r) => r.points.map((p) => p.t)));
        }
        return out;
      }, solved.map((r) => r.uuid)); // both plans on the clock
      expect(after > before && points.some((t) => Math.abs(t - after) < 2e-3), `Shift+ArrowRight went ${before} -> ${after}, not to a plan point`);
      const hash = await page.evaluate(() => location.hash);
      const inUrl = Number(new URLSearchParams(hash.split('?')[1]).get('t'));
      expect(Math.abs(inUrl - after) < 0.01, `the plan time is not in the URL: ${hash}`);
      await page.locator('[data-testid=events-type]').selectOption('phase');
      await page.waitForFunction(() => location.hash.includes('events=phase'));
      await page.reload();
      await page.waitForSelector('[data-testid=viewer-overlay][data-ready="1"]', { timeout: 60000 });
      expect(Math.abs((await time()) - after) < 0.01, `after a reload the plan is at ${await time()}, not ${after}`);
      expect((await page.locator('[data-testid=events-type]').inputValue()) === 'phase', 'the events filter did not survive a reload');
      await page.locator('[data-testid=tag-input]').fill('keyboard-tag');
      await page.locator('[data-testid=tag-input]').press('Enter');
      await page.waitForSelector('[data-testid=tags] .chip:has-text("keyboard-tag")');
    });

    await step('Run detail: sizes over time show hyperarcs as well as vertices; the phase breakdown keeps millisecond phases', async () => {
      const first = async (q) => (await api(`/api/runs?limit=1&sort=id&order=asc&q=${encodeURIComponent(q)}`)).runs[0];
      const dash = await first('config = dash and status = solved and robots = 2');
      const lazy = await first('config = lazy-dash and status = solved and robots = 2');
      expect(dash && lazy, 'the demo database needs a solved 2-robot DaSH and Lazy-DaSH run');
      const sizeLabels = () => page.evaluate(() => document.querySelector('[data-testid=chart-timeline]')._chart.data.datasets.map((d) => d.label));
      await page.goto(`${url}/#/run/${dash.uuid}`);
      await points('chart-timeline');
      await page.selectOption('[data-testid=sizes-count]', 'both');
      await points('chart-timeline');
      const both = await sizeLabels();
      expect(both.includes('H_M vertices') && both.includes('H_M hyperarcs'), `sizes over time: ${both.join(' | ')}`);
      // DaSH's H_M gains hyperarcs over the run (its vertices may stay flat).
      const arcs = await page.evaluate(() => document.querySelector('[data-testid=chart-timeline]')._chart.data.datasets.find((d) => d.label === 'H_M hyperarcs').data.map((p) => p.y));
      expect(arcs.length > 1 && arcs[arcs.length - 1] > arcs[0], `H_M hyperarcs over time: ${arcs.join(', ')}`);
      await page.selectOption('[data-testid=sizes-count]', 'hyperarcs');
      await page.waitForFunction(() => document.querySelector('[data-testid=chart-timeline]')._chart?.data.datasets.every((d) => d.label.endsWith('hyperarcs')));
      const title = await page.evaluate(() => document.querySelector('[data-testid=chart-timeline]')._chart.options.scales.y.title.text);
      expect(/^hyperarcs/.test(title), `y axis title: ${title}`);
      await page.selectOption('[data-testid=sizes-count]', 'both');

      await page.goto(`${url}/#/run/${lazy.uuid}`);
      await points('chart-phases');
      const r = await page.evaluate(() => {
        const c = document.querySelector('[data-testid=chart-phases]')._chart;
        const meta = c.getDatasetMeta(0);
        const bars = c.data.datasets[0].data.map((p, i) => ({ label: p.y, seconds: p.x, text: p.text, px: Math.abs(meta.data[i].x - meta.data[i].base) }));
        return { type: c.scales.x.type, ticks: c.scales.x.ticks.filter((t) => t.label !== '' && t.label !== undefined).length, bars };
      });
      const short = r.bars.filter((b) => b.seconds < 0.01);
      expect(r.type === 'logarithmic' && r.ticks >= 2, `phase axis: ${r.type}, ${r.ticks} labelled ticks`);
      expect(short.length > 0, `no millisecond phase in ${lazy.uuid}: ${JSON.stringify(r.bars)}`);
      expect(r.bars.every((b) => b.px >= 3 && /s\b/.test(b.text || '')), `a phase bar is hidden or unlabelled: ${JSON.stringify(r.bars)}`);
      await shot(page, 'run-phases');
    });

    await step('Query: the statement in the URL, results as CSV', async () => {
      const sql = 'SELECT family, status, count(*) AS runs FROM dash_runs GROUP BY family, status ORDER BY family, status';
      await page.goto(`${url}/#/query?sql=${encodeURIComponent(sql)}`);
      await page.waitForSelector('[data-testid=query-status].ok');
      const shown = await page.locator('[data-testid=query-result] tbody tr').count();
      const dl = await downloadOf(page, () => page.locator('[data-testid=query-csv]').click());
      const lines = csvRows(dl.bytes.toString('utf8'));
      expect(lines[0] === 'family,status,runs' && lines.length === shown + 1, `query CSV: ${lines.length} lines for ${shown} rows`);
      provoking = true;
      await page.locator('[data-testid=sql]').fill('DROP TABLE dash_runs');
      await page.locator('[data-testid=run-query]').click();
      await page.waitForSelector('[data-testid=query-status]:has-text("refused")');
      provoking = false;
      const status = await page.textContent('[data-testid=query-status]');
      expect(!/refused:\s*refused/i.test(status), `doubled prefix: ${status}`);
    });

    await step('Dispatch: a run page links to dispatching its plan, the run is in the URL', async () => {
      await page.goto(`${url}/#/run/${solved[0].uuid}`);
      await page.locator('[data-testid=dispatch-link]').click();
      await page.waitForSelector('[data-testid=dispatch-run], [data-testid=dispatch-missing]');
      if (await page.locator('[data-testid=dispatch-missing]').count()) return;
      // The page may still be drawing the previous route's form: wait for the run from the link.
      await page.waitForFunction((id) => document.querySelector('[data-testid=dispatch-run]')?.value === id, solved[0].uuid, { timeout: 15000 }).catch(() => {});
      expect((await page.locator('[data-testid=dispatch-run]').inputValue()) === solved[0].uuid, 'the run did not reach the Dispatch page');
      await page.locator('[data-testid=time-scale]').fill('2');
      await page.waitForFunction(() => location.hash.includes('scale=2'));
    });

    await step('Launch: the spec lives in the URL', async () => {
      await page.goto(`${url}/#/launch`);
      await page.waitForSelector('[data-testid=run-count][data-runs]');
      await page.locator('input[data-param=objects]').fill('2, 4');
      await page.locator('[data-testid=seed-count]').fill('3');
      await page.locator('[data-testid=batch-name]').fill('shared');
      await page.waitForSelector('[data-testid=run-count][data-runs="6"]');
      await page.waitForFunction(() => decodeURIComponent(location.hash).includes('"name":"shared"'));
      await page.reload();
      await page.waitForSelector('[data-testid=run-count][data-runs="6"]');
      const v = await page.evaluate(() => [document.querySelector('input[data-param=objects]').value, document.querySelector('[data-testid=batch-name]').value]);
      expect(v[0] === '2, 4' && v[1] === 'shared', `after a reload: ${v}`);
    });

    await step('Launch: one batch per click however fast, its line follows the batch to the end, "compare this batch"', async () => {
      await page.goto(`${url}/#/launch`);
      await page.waitForSelector('[data-testid=run-count][data-runs]');
      const before = (await api('/api/batches')).batches.length;
      await page.locator('input[data-param=robots]').fill('2');
      await page.locator('input[data-param=objects]').fill('2');
      await page.locator('[data-testid=seed-count]').fill('1');
      await page.locator('[data-testid=time-limit]').fill('120');
      await page.locator('[data-testid=batch-name]').fill('once');
      await page.waitForSelector('[data-testid=run-count][data-runs="1"]');
      await page.waitForSelector('[data-testid=submit]:not([disabled])');
      await page.locator('[data-testid=submit]').evaluate((b) => {
        b.click();
        b.click();
        b.click();
      });
      const result = await page.waitForSelector('[data-testid=launch-result][data-batch]');
      const batch = await result.getAttribute('data-batch');
      await sleep(500);
      expect((await api('/api/batches')).batches.length === before + 1, 'more than one batch was launched');
      await page.waitForSelector('[data-testid=launch-result][data-status=finished]', { timeout: 180000 });
      const line = await page.textContent('[data-testid=launch-result]');
      expect(!/queued/.test(line) && /1\/1 done/.test(line), `the launch line: ${line}`);
      await page.locator(`tr[data-batch="${batch}"] [data-testid=compare-batch]`).click();
      await page.waitForFunction((b) => location.hash.includes(`batch=${b}`), batch);
      await page.waitForSelector('[data-testid=compare-info][data-runs="1"]');
    });

    await step('Compare: the sizes a batch\'s axis stop rule skipped are crosses in the success figure', async () => {
      // "aborting" crashes at objects=2, so its objects=3 and 4 are skipped; the task-only planner runs all three.
      const spec = { name: 'stop', time_limit: 60, memory_limit: 2048, scenarios: [{ family: 'sorting', params: { robots: 2, objects: [2, 3, 4] }, stop_axis: 'objects' }], planners: [{ name: 'lazy-dash', settings: { test_fault: 'abort' }, label: 'aborting' }, { name: 'lazy-dash', settings: { task_only: true }, label: 'lazy-task' }], seeds: [1] };
      const res = await page.request.post(`${url}/api/batches`, { data: { spec, workers: 1 }, headers: { Authorization: `Bearer ${token}` } });
      expect(res.ok(), `launch: ${res.status()} ${await res.text()}`);
      const batch = (await res.json()).batch_id;
      for (let i = 0; i < 600 && (await api(`/api/batches/${batch}`)).status !== 'finished'; i++) await sleep(100);
      await page.goto(`${url}/#/compare?family=sorting&batch=${batch}`);
      await page.waitForSelector('[data-testid=compare-info][data-runs="4"][data-skipped="2"]');
      await points('chart-success');
      const crosses = await page.evaluate(() => document.querySelector('[data-testid=chart-success]')._chart.data.datasets.map((d) => [d.label, d.data.filter((p) => p && p.skippedPoint).map((p) => p.x)]));
      expect(JSON.stringify(crosses) === JSON.stringify([['aborting · robots=2', ['3', '4']], ['lazy-task · robots=2', []]]), `skipped sizes in the success figure: ${JSON.stringify(crosses)}`);
    });

    await step('A run opened while it runs shows its 3D plan when it ends, without a reload', async () => {
      // DaSH on sorting with 4 robots takes seconds to tens of seconds; a larger scene if this
      // machine solved the smaller one before the page could show it running.
      let seen = false;
      for (const objects of [6, 8]) {
        const spec = { name: `live-${objects}`, time_limit: 300, memory_limit: 4096, scenarios: [{ family: 'sorting', params: { robots: 4, objects } }], planners: [{ name: 'dash', label: 'dash' }], seeds: { from: 1, count: 1 } };
        const res = await page.request.post(`${url}/api/batches`, { data: { spec, workers: 1 }, headers: { Authorization: `Bearer ${token}` } });
        expect(res.ok(), `launch: ${res.status()} ${await res.text()}`);
        const batch = (await res.json()).batch_id;
        let run = null;
        for (let i = 0; i < 1200 && !run; i++) {
          const list = (await api(`/api/runs?q=${encodeURIComponent(`batch = "${batch}"`)}`)).runs;
          if (list.length && list[0].status !== 'queued') run = list[0];
          else await sleep(50);
        }
        expect(run, 'the run never started');
        if (run.status !== 'running') continue;
        await page.goto(`${url}/#/run/${run.uuid}`);
        const first = await page.waitForFunction(
          () => {
            const v = document.querySelector('[data-testid=viewer]');
            const badge = document.querySelector('[data-testid=run-header] h1 .badge');
            if (!v || !badge || v.dataset.ready !== '1') return null;
            return badge.textContent === 'running' && v.dataset.hasPlan === '0' ? 'running' : 'ended';
          },
          null,
          { timeout: 60000 },
        );
        if ((await first.jsonValue()) !== 'running') continue;
        seen = true;
        expect(await page.locator('[data-testid=play]').isDisabled(), 'Play is enabled without a plan');
        await page.waitForSelector('[data-testid=run-header] h1 .badge:not(.running)', { timeout: 300000 });
        const status = await page.textContent('[data-testid=run-header] h1 .badge');
        expect(status === 'solved', `the run ended ${status}`);
        // A batch run's settings carry its full effective parameter set: the planner line shows the
        // settings as given, never "[object Object]" or a raw "{}".
        const plannerText = await page.evaluate(() => {
          const dt = [...document.querySelectorAll('[data-testid=run-header] dl.kv dt')].find((d) => d.textContent === 'planner');
          return dt ? dt.nextElementSibling.innerText : null;
        });
        expect(plannerText && /^dash \(dash\)/.test(plannerText), `the planner line: ${plannerText}`);
        expect(!/\[object/.test(plannerText) && !/\{\}/.test(plannerText), `the planner line: ${plannerText}`);
        await page.waitForSelector('[data-testid=viewer][data-has-plan="1"]', { timeout: 60000 });
        expect(!(await page.locator('[data-testid=play]').isDisabled()), 'Play stays disabled after the run ended');
        await page.waitForFunction(() => !/0–0 of 0/.test(document.querySelector('[data-testid=events]').textContent), null, { timeout: 30000 });
        await shot(page, 'run-live-ended');
        break;
      }
      expect(seen, 'every run ended before the page showed it running: nothing was checked');
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
