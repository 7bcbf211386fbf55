#!/usr/bin/env node
// Browser tests of the Compare page's defaults and statistics (issue 41), against `dashbench serve`
// on a copy of data/demo.db:
//   node tests/browser/compare_stats.mjs --dashbench BUILD/dashbench [--artifacts DIR] [--keep]
// Checks: "compare this batch" opens on the axis the batch varies (robots for a batch over robots,
// as `dashbench report --figures` picks it), not on objects; the paired statistics of two
// configurations (seed-paired time ratio with its 95 % t interval, the sign test on Gehan's pair
// scores with timeouts censored at the limit, success rates with Wilson intervals) are drawn and
// agree with `dashbench report` on the same database; their CSV carries them; the plot fixes (curves
// from 0 %, a lone median, export names, CSV digits, log ticks, asterisks); Launch names a long run
// and its time left never counts up while the run works. No console errors.
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { ARTIFACTS, DASHBENCH, KEEP, loadPlaywright, launchBrowser, startServer, stopServer, step, expect, shot, results, finish, watchConsole, sleep } from './harness.mjs';

async function downloadOf(page, click) {
  const [dl] = await Promise.all([page.waitForEvent('download', { timeout: 30000 }), click()]);
  return { name: dl.suggestedFilename(), bytes: fs.readFileSync(await dl.path()) };
}

async function main() {
  const playwright = loadPlaywright();
  fs.mkdirSync(ARTIFACTS, { recursive: true });
  const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'dashbench-compare-stats-'));
  const context = await launchBrowser(playwright, path.join(tmp, 'profile'), { downloads: true });
  let server = null;
  try {
    server = await startServer(tmp);
    const token = fs.readFileSync(path.join(tmp, 'token'), 'utf8').trim();
    const url = server.url;
    const page = context.pages()[0] || (await context.newPage());
    page.setDefaultTimeout(30000);
    const consoleErrors = watchConsole(page);
    const api = async (p) => (await page.request.get(`${url}${p}`)).json();
    // Launches `spec` with one worker and waits (2 minutes at most) until the batch has finished; its id.
    const runBatch = async (spec) => {
      const res = await page.request.post(`${url}/api/batches`, { data: { spec, workers: 1 }, headers: { Authorization: `Bearer ${token}` } });
      expect(res.ok(), `launch: ${res.status()} ${await res.text()}`);
      const batch = (await res.json()).batch_id;
      let status = '';
      for (let i = 0; i < 1200 && (status = (await api(`/api/batches/${batch}`)).status) !== 'finished'; i++) await sleep(100);
      expect(status === 'finished', `the batch ended ${status}`);
      return batch;
    };
    await page.goto(`${url}/#token=${token}`);
    await page.waitForFunction(() => location.hash === '#/runs');
    // Let the Runs page finish loading: a page still loading when the route changes may write its
    // own state over the next page's URL (runs.js saveState after its fetch).
    const settled = () => page.waitForSelector('[data-testid=runs-total][data-total]');
    await settled();

    await step('A Runs page left while its reload is pending does not write over the next page\u2019s URL', async () => {
      await page.goto(`${url}/#/runs`);
      await settled();
      // Leave the Runs page the moment a run changes (its reload is then pending, 500 ms debounced) for
      // a Compare link of the demo batch, then give that reload time to fire. Every URL the page writes
      // from then on is logged: each must keep the link's batch.
      const target = '#/compare?batch=demo-20261125-174120-94c0';
      const armed = page.evaluate((hash) => new Promise((resolve) => {
        window.__written = [];
        const replace = history.replaceState.bind(history);
        history.replaceState = (state, title, url) => {
          window.__written.push(String(url));
          return replace(state, title, url);
        };
        const source = new EventSource('/api/events');
        // 200 ms after the event: the page's own stream (another connection) has delivered it too,
        // and its debounced reload is due 300 ms later.
        source.addEventListener('run', () => {
          source.close();
          setTimeout(() => {
            window.__written = [];
            location.hash = hash;
            resolve();
          }, 200);
        });
      }), target);
      const spec = { name: 'leave', time_limit: 60, memory_limit: 2048, scenarios: [{ family: 'sorting', params: { robots: 2, objects: 2 } }], planners: [{ name: 'lazy-dash', settings: { task_only: true }, label: 'lazy-task' }], seeds: [1] };
      const res = await page.request.post(`${url}/api/batches`, { data: { spec, workers: 1 }, headers: { Authorization: `Bearer ${token}` } });
      expect(res.ok(), `launch: ${res.status()} ${await res.text()}`);
      await armed;
      await sleep(1500);
      const written = await page.evaluate(() => window.__written);
      const lost = written.filter((u) => !u.includes('batch=demo-20261125-174120-94c0'));
      expect(lost.length === 0, `the Runs page wrote over the Compare link: ${JSON.stringify(written)}`);
    });

    await step('"Compare this batch" opens on the axis the batch varies (robots), as report picks it', async () => {
      // Two quick task-only runs that differ in robots only (objects fixed at 2).
      const spec = { name: 'robots-only', time_limit: 60, memory_limit: 2048, scenarios: [{ family: 'sorting', params: { robots: [2, 3], objects: 2 } }], planners: [{ name: 'lazy-dash', settings: { task_only: true }, label: 'lazy-task' }], seeds: [1] };
      const batch = await runBatch(spec);
      // The link the Launch page's batch table gives (launch.js: "#/compare?batch=ID"), in a fresh
      // load: the Runs page open while the batch ran has a debounced reload pending, which would
      // write its own state over the next page's URL (runs.js: not cancelled when the page is left).
      await page.goto('about:blank');
      await page.goto(`${url}/#/compare?batch=${encodeURIComponent(batch)}`);
      await page.waitForSelector('[data-testid=compare-info][data-runs="2"]');
      await page.waitForFunction(() => Number(document.querySelector('[data-testid=chart-builder]')?.dataset.points) > 0);
      const x = await page.locator('[data-testid=compare-x]').inputValue();
      expect(x === 'robots', `Compare opened with x = ${x}`);
      const xs = await page.evaluate(() => document.querySelector('[data-testid=chart-builder]')._chart.data.datasets.filter((d) => !d.band).flatMap((d) => d.data.map((p) => p.x)));
      expect(JSON.stringify([...new Set(xs)].sort()) === '[2,3]', `builder points at x = ${JSON.stringify(xs)}`);
      await page.waitForFunction(() => location.hash.includes('x=robots')).catch(async () => {
        throw new Error(`the URL does not keep x=robots: ${await page.evaluate(() => location.hash)}`);
      });
      // The report's figures pick the same axis for the same batch.
      const dir = path.join(tmp, 'figures');
      execFileSync(DASHBENCH, ['report', server.db, '--batch', batch, '--figures', dir, '--svg-only'], { stdio: 'pipe' });
      const svg = fs.readFileSync(path.join(dir, 'sorting-success.svg'), 'utf8');
      expect(/problem size: robots \(count\)/.test(svg), 'the report\u2019s figure is not over robots');
      // A choice in the URL still wins.
      await page.goto(`${url}/#/runs`);
      await settled();
      await page.goto(`${url}/#/compare?batch=${encodeURIComponent(batch)}&x=objects`);
      await page.waitForSelector('[data-testid=compare-info][data-runs="2"]');
      await page.waitForFunction(() => Number(document.querySelector('[data-testid=chart-builder]')?.dataset.points) > 0);
      expect((await page.locator('[data-testid=compare-x]').inputValue()) === 'objects', 'x=objects in the link was not kept');
    });

    await step('One batch\u2019s two profiles of a planner are two series, each named with its profile, on the page and in the report', async () => {
      // The same planner under --profile paper and --profile default, unlabelled (task-only: quick).
      const planners = ['paper', 'default'].map((profile) => ({ name: 'lazy-dash', profile, settings: { task_only: true } }));
      const spec = { name: 'two-profiles', time_limit: 60, memory_limit: 2048, scenarios: [{ family: 'sorting', params: { robots: 2, objects: [2, 3] } }], planners, seeds: [1] };
      const batch = await runBatch(spec);
      await page.goto('about:blank');
      await page.goto(`${url}/#/compare?batch=${encodeURIComponent(batch)}`);
      await page.waitForSelector('[data-testid=compare-info][data-runs="4"]');
      await page.waitForFunction(() => Number(document.querySelector('[data-testid=chart-builder]')?.dataset.points) > 0);
      const names = await page.evaluate(() => [...new Set(document.querySelector('[data-testid=chart-builder]')._chart.data.datasets.filter((d) => !d.band).map((d) => d.label.split(' \u00b7 ')[0]))].sort()); // "SERIES · robots=2": the split
      const want = ['lazy-dash (default) {"task_only":true}', 'lazy-dash (paper) {"task_only":true}'];
      expect(JSON.stringify(names) === JSON.stringify(want), `builder series: ${JSON.stringify(names)}`);
      const dir = path.join(tmp, 'figures-profiles');
      execFileSync(DASHBENCH, ['report', server.db, '--batch', batch, '--figures', dir, '--svg-only'], { stdio: 'pipe' });
      const svg = fs.readFileSync(path.join(dir, 'sorting-success.svg'), 'utf8');
      for (const profile of ['paper', 'default']) expect(svg.includes(`lazy-dash (${profile})`), `the report\u2019s figure has no series of the ${profile} profile`);
    });

    await step('Paired statistics: the page\u2019s numbers agree with `dashbench report`, and reach the CSV', async () => {
      const report = execFileSync(DASHBENCH, ['report', server.db], { encoding: 'utf8' });
      const start = report.indexOf('== sorting');
      const next = report.indexOf('\n== ', start + 3);
      const section = report.slice(start, next < 0 ? undefined : next);
      const m = section.match(/^\s*all\s+(dash|lazy-dash) \/ (dash|lazy-dash)\s+(\d+)\s+(\d+)\s+(\S+)\s+\[(\S+), (\S+)\]\s+(\d+)\s+(\d+)\s+(\d+)\s+(\S+)\s+(\d+)\/\d+ \[(\d+)%, (\d+)%\]\s+(\d+)\/\d+/m);
      expect(m, `no "all dash / lazy-dash" row in the report:\n${section}`);
      const [, a, b, pairs, both, ratio, low, high, aFaster, bFaster, undecided, p, aSolved, aLow, aHigh, bSolved] = m;
      await page.goto(`${url}/#/compare?family=sorting&split=none&num=${a}&den=${b}`);
      await page.waitForSelector('[data-testid=paired-stats][data-rows]:not([data-rows="0"])');
      const all = await page.evaluate(() => document.querySelector('[data-testid=paired-stats]')._csv().rows.at(-1));
      const close = (x, y) => Math.abs(x - Number(y)) <= 0.006 * Math.abs(Number(y)) + 1e-12;
      const got = JSON.stringify(all);
      expect(all.x === 'all' && all.pairs === Number(pairs) && all.both_solved === Number(both), `pairs: ${got} against ${m[0]}`);
      expect(close(all.ratio, ratio) && close(all.ratio_low, low) && close(all.ratio_high, high), `ratio: ${got} against ${m[0]}`);
      expect(all.a_faster === Number(aFaster) && all.b_faster === Number(bFaster) && all.undecided === Number(undecided), `sign test counts: ${got} against ${m[0]}`);
      expect(p === '<0.001' ? all.p_value < 0.001 : close(all.p_value, p), `p: ${got} against ${m[0]}`);
      expect(all.a_solved === Number(aSolved) && all.b_solved === Number(bSolved) && Math.round(100 * all.a_low) === Number(aLow) && Math.round(100 * all.a_high) === Number(aHigh), `success: ${got} against ${m[0]}`);
      // Timeouts stay in: the demo database has DaSH runs that timed out (sorting robots=2 objects=6).
      expect(all.pairs > all.both_solved, `no unsolved pair among ${all.pairs}: the test does not exercise censoring`);
      const file = await downloadOf(page, () => page.locator('[data-testid=paired-stats-csv]').click());
      const lines = file.bytes.toString('utf8').trim().split(/\r?\n/);
      expect(lines[0] === 'split,x,pairs,both_solved,ratio,ratio_low,ratio_high,a_faster,b_faster,undecided,p_value,a_solved,a_rate,a_low,a_high,b_solved,b_rate,b_low,b_high', `CSV header: ${lines[0]}`);
      expect(lines.at(-1).startsWith(`,all,${pairs},${both},`), `CSV last row: ${lines.at(-1)}`);
      expect(/paired-statistics-sorting-/.test(file.name), `CSV file name: ${file.name}`);
      await shot(page, 'compare-paired-stats');
    });

    await step('Plots: solved-over-time curves start at 0 %, a lone ratio median shows, exports name the metric, CSV without float noise', async () => {
      await page.goto(`${url}/#/compare?family=sorting&x=objects&split=none&num=dash&den=lazy-dash&q=${encodeURIComponent('objects = 2')}&metric=collision_checks`);
      await page.waitForFunction(() => ['chart-solved-time', 'chart-ratio', 'chart-builder'].every((id) => Number(document.querySelector(`[data-testid=${id}]`)?.dataset.points) > 0));
      // Each curve starts at 0 % on the axis's left edge and stays there until its first solve
      // (stepped 'before': along at the old share, up at the new point).
      const curves = await page.evaluate(() => {
        const chart = document.querySelector('[data-testid=chart-solved-time]')._chart;
        return chart.data.datasets.map((d, i) => ({ first: d.data[0].y, stepped: d.stepped, zero: chart.scales.y.getPixelForValue(0), y0: chart.getDatasetMeta(i).data[0]?.y }));
      });
      expect(curves.length > 0 && curves.every((c) => c.first === 0 && c.y0 === c.zero), `solved-over-time curves start at ${JSON.stringify(curves)}`);
      expect(curves.every((c) => c.stepped === 'before'), `the curves rise a solve early (stepped ${curves.map((c) => c.stepped)})`);
      const median = await page.evaluate(() => {
        const chart = document.querySelector('[data-testid=chart-ratio]')._chart;
        const i = chart.data.datasets.findIndex((d) => /median/.test(d.label));
        const el = chart.getDatasetMeta(i).data[0];
        return { points: chart.data.datasets[i].data.length, radius: el.options.radius, style: el.options.pointStyle };
      });
      expect(median.points === 1 && median.radius >= 4, `the ratio median with one x value: ${JSON.stringify(median)}`);
      const svg = await downloadOf(page, () => page.locator('[data-testid=chart-builder-svg]').click());
      expect(/collision_checks/.test(svg.name), `builder export named ${svg.name}`);
      const builderCsv = (await downloadOf(page, () => page.locator('[data-testid=chart-builder-csv]').click())).bytes.toString('utf8');
      const timesCsv = (await downloadOf(page, () => page.locator('[data-testid=chart-times-0-csv]').click())).bytes.toString('utf8');
      for (const text of [builderCsv, timesCsv]) {
        // No value with more than 9 significant digits (619.6950000000055 has 16).
        const noisy = text.split(/[,\r\n]+/).filter((f) => /^-?\d*\.\d+$/.test(f) && f.replace(/^-?[0.]*/, '').replace('.', '').length > 9);
        expect(noisy.length === 0, `CSV values with floating-point noise: ${noisy.slice(0, 5).join(' ')}`);
      }
    });

    await step('Plots: phase panels label the decade below their top and keep points off the frame; SVG draws validation as an asterisk', async () => {
      await page.goto(`${url}/#/compare?family=sorting&split=none`);
      await page.waitForFunction(() => Number(document.querySelector('[data-testid=chart-times]')?.dataset.points) > 0);
      const panels = await page.evaluate(() =>
        [...document.querySelectorAll('[data-testid=chart-times] .chart-box')]
          .filter((b) => b._chart)
          .map((b) => {
            const c = b._chart;
            const y = c.scales.y;
            const tops = c.data.datasets.flatMap((d, i) => c.getDatasetMeta(i).data.map((e) => e.y));
            return { series: b.dataset.series, ticks: y.ticks.map((t) => t.value), max: y.max, gap: Math.min(...tops) - c.chartArea.top, bottom: c.chartArea.bottom - Math.max(...tops) };
          }),
      );
      for (const p of panels) {
        const above = p.ticks.filter((v) => v > 1);
        expect(p.max < 2 || above.length > 0, `${p.series}: no tick between 1 and the top (${p.max}): ${p.ticks}`);
        expect(p.gap >= 6 && p.bottom >= 6, `${p.series}: a point ${Math.min(p.gap, p.bottom).toFixed(1)} px from the frame`);
      }
      const lazy = await page.evaluate(() => [...document.querySelectorAll('[data-testid=chart-times] .chart-box')].findIndex((b) => /^lazy-dash\b/.test(b.dataset.series || '') && b._chart));
      expect(lazy >= 0, 'no Lazy-DaSH time panel');
      const text = (await downloadOf(page, () => page.locator(`[data-testid=chart-times-${lazy}-svg]`).click())).bytes.toString('utf8');
      // An asterisk: four strokes through one centre (Chart.js's 'star'), drawn as one path of four
      // M-L segments, at least 7 px across (at 2.6 px, the filled shapes' radius, it prints as a dot).
      const stars = [...text.matchAll(/<path d="(M[-\d. ]+L[-\d. ]+M[-\d. ]+L[-\d. ]+M[-\d. ]+L[-\d. ]+M[-\d. ]+L[-\d. ]+)" fill="none"/g)].map((m) => {
        const xs = [...m[1].matchAll(/[ML](-?[\d.]+) (-?[\d.]+)/g)].map((p) => Number(p[1]));
        return Math.max(...xs) - Math.min(...xs);
      });
      expect(stars.length > 0, 'the SVG has no asterisk (validation\u2019s point style)');
      expect(Math.min(...stars) >= 7, `asterisks ${Math.min(...stars).toFixed(1)} px across print as dots`);
    });

    await step('Launch: a long run shows which run it is and for how long; the time left never counts up while it works', async () => {
      // Three runs one after another, each working its whole 8 s (the runner's ignore-deadline test fault: a
      // run of known length, however fast the machine plans).
      const spec = { name: 'eta', time_limit: 8, memory_limit: 4096, scenarios: [{ family: 'sorting', params: { robots: 2, objects: 2 } }], planners: [{ name: 'dash', label: 'dash', settings: { test_fault: 'ignore-deadline' } }], seeds: [1, 2, 3] };
      await page.goto(`${url}/#/launch`);
      const res = await page.request.post(`${url}/api/batches`, { data: { spec, workers: 1 }, headers: { Authorization: `Bearer ${token}` } });
      expect(res.ok(), `launch: ${res.status()} ${await res.text()}`);
      const batch = (await res.json()).batch_id;
      const row = `tr[data-batch="${batch}"]`;
      await page.waitForSelector(row);
      const seconds = (text) => {
        const m = text.match(/about (?:(\d+) min (\d+) s|([\d.]+) (µs|ms|s)) left/);
        if (!m) return null;
        return m[1] ? 60 * Number(m[1]) + Number(m[2]) : Number(m[3]) * { µs: 1e-6, ms: 1e-3, s: 1 }[m[4]];
      };
      const samples = [];
      let named = '';
      for (let i = 0; i < 600; i++) {
        const r = await page.evaluate((sel) => {
          const tr = document.querySelector(sel);
          return tr ? { status: tr.dataset.status, text: tr.querySelector('.progress-label')?.textContent || '', work: [...tr.querySelectorAll('[data-testid=run-work]')].map((w) => w.textContent) } : null;
        }, row);
        if (!r || r.status === 'finished') break;
        const done = Number((r.text.match(/(\d+)\/3 done/) || [])[1]);
        samples.push({ done, eta: seconds(r.text) });
        named = named || r.work.find((w) => /dash: running for/.test(w)) || '';
        await sleep(250);
      }
      let rises = 0;
      for (let i = 1; i < samples.length; i++) {
        const [a, b] = [samples[i - 1], samples[i]];
        if (a.done === b.done && a.eta !== null && b.eta !== null && b.eta > a.eta + 0.01) rises += 1;
      }
      const known = samples.filter((x) => x.eta !== null).length;
      expect(known >= 4, `the time left showed in only ${known} of ${samples.length} samples`);
      expect(rises === 0, `the time left rose ${rises} times while no run ended: ${JSON.stringify(samples.filter((x) => x.eta !== null).slice(0, 40))}`);
      expect(/^sorting\/.*seed=\d.*dash: running for [\d.]+ s$/.test(named), `no line named the long run: "${named}"`);
    });

    await step('Launch names the phase a long run without progress events is in (a DaSH construction)', async () => {
      const spec = { name: 'phase', time_limit: 20, memory_limit: 4096, scenarios: [{ family: 'sorting', params: { robots: 4, objects: 8 } }], planners: [{ name: 'dash', label: 'dash' }], seeds: [1] };
      await page.goto(`${url}/#/launch`);
      const headers = { Authorization: `Bearer ${token}` };
      const res = await page.request.post(`${url}/api/batches`, { data: { spec, workers: 1 }, headers });
      expect(res.ok(), `launch: ${res.status()} ${await res.text()}`);
      const batch = (await res.json()).batch_id;
      const row = `tr[data-batch="${batch}"]`;
      await page.waitForSelector(row);
      let named = '';
      const seen = new Set();
      for (let i = 0; i < 100 && !named; i++) {
        const work = await page.evaluate((sel) => [...(document.querySelector(sel)?.querySelectorAll('[data-testid=run-work]') || [])].map((w) => w.textContent), row);
        work.forEach((w) => seen.add(w));
        named = work.find((w) => /dash: (task|motion|validation)[a-z: ]*, running for [\d.]+ s$/.test(w)) || '';
        if (!named) await sleep(250);
      }
      await page.request.post(`${url}/api/batches/${batch}/cancel`, { headers });
      expect(named !== '', `no line named the run's phase; lines seen: ${JSON.stringify([...seen].slice(0, 10))}`);
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
