#!/usr/bin/env node
// Unit tests of the dashboard's pure modules under Node (no browser): the Compare page's statistics
// (quantiles, grouping into series, per-scene ratios, Planner Arena's solved-against-time curve with
// unsolved runs kept in the denominator, settings series labelled by the parameters that differ),
// the planner line's settings text, and the SVG recorder's colour and path output.
//   node tests/browser/web_units.mjs
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const WEB = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..', 'web', 'js');
const data = await import(pathToFileURL(path.join(WEB, 'compare_data.js')));
const svg = await import(pathToFileURL(path.join(WEB, 'svg_context.js')));
const url = await import(pathToFileURL(path.join(WEB, 'url_state.js')));
const dom = await import(pathToFileURL(path.join(WEB, 'dom.js')));
const batchEta = await import(pathToFileURL(path.join(WEB, 'batch_eta.js')));
const csv = await import(pathToFileURL(path.join(WEB, 'csv.js')));
const stats = await import(pathToFileURL(path.join(WEB, 'paired_stats.js')));
const CASES = JSON.parse(fs.readFileSync(path.join(WEB, '..', '..', 'tests', 'figures', 'paired_stats_cases.json'), 'utf8'));

let failed = 0;
function test(name, fn) {
  try {
    fn();
    console.log(`PASS ${name}`);
  } catch (e) {
    failed += 1;
    console.log(`FAIL ${name}: ${e.stack || e}`);
  }
}

const run = (over) => ({ family: 'sorting', robots: 2, objects: 4, seed: 1, config: 'lazy-dash', planner: 'lazy-dash', settings: '{}', status: 'solved', end_time: 'x', time_limit: 10, ...over });

test('quantiles follow type 7 (numpy linear)', () => {
  assert.equal(data.quantile([1, 2, 3, 4], 0.5), 2.5);
  assert.equal(data.quantile([1, 2, 3, 4], 0.25), 1.75);
  assert.equal(data.quantile([7], 0.75), 7);
  assert.equal(data.quantile([], 0.5), null);
  const s = data.summary([3, null, 1, 'x', 2, NaN]);
  assert.deepEqual([s.n, s.median, s.min, s.max], [3, 2, 1, 3]);
});

test('runs group into series per configuration and split value, x and split values sorted numerically', () => {
  const runs = [run({ objects: 10 }), run({ objects: 2 }), run({ robots: 16, objects: 2 }), run({ robots: 4, objects: 2 }), run({ config: 'dash', planner: 'dash', objects: 2 })];
  const g = data.groupRuns(runs, { x: 'objects', split: 'robots', groupBy: 'config' });
  assert.deepEqual(g.xs, [2, 10]);
  assert.deepEqual(g.series, ['dash · robots=2', 'lazy-dash · robots=2', 'lazy-dash · robots=4', 'lazy-dash · robots=16']);
  assert.equal(g.cells.get('lazy-dash · robots=2|2').runs.length, 1);
  const bySettings = data.groupRuns([run({ settings: '{"k":1}' }), run({})], { x: 'objects', split: '', groupBy: 'settings' });
  assert.deepEqual(bySettings.series, ['lazy-dash', 'lazy-dash k=1']);
});

test('settings series are labelled by the parameters that differ within a configuration', () => {
  const eff = (clearance, extra = {}) => JSON.stringify({ ...extra, parameters: { clearance, parking: true, motion_budget: 3 } });
  const runs = [
    run({ settings: eff(0.002) }),
    run({ settings: eff(0.005, { clearance: 0.005 }) }),
    run({ settings: eff(0.005, { clearance: 0.005 }), seed: 2 }),
    run({ config: 'dash', planner: 'dash', settings: eff(0.002) }),
    run({ config: 'lazy-task', settings: eff(0.002, { task_only: true }) }),
  ];
  data.labelSettings(runs);
  const g = data.groupRuns(runs, { x: 'objects', split: '', groupBy: 'settings' });
  assert.deepEqual(g.series, ['dash', 'lazy-dash clearance=0.002', 'lazy-dash clearance=0.005', 'lazy-task']);
  assert.equal(g.cells.get('lazy-dash clearance=0.005|4').runs.length, 2);
  for (const label of g.series) assert.ok(!/[{}"]|object/.test(label), `label with JSON: ${label}`);
  // Two parameters swept together, one of them only in the effective set; a run without stored
  // parameters (older databases) still gets a readable label.
  const two = [run({ settings: JSON.stringify({ a: 1, parameters: { a: 1, b: true } }) }), run({ settings: JSON.stringify({ a: 2, parameters: { a: 2, b: false } }) }), run({ config: 'old', settings: '{}' })];
  data.labelSettings(two);
  assert.deepEqual(two.map((r) => data.groupKey(r, 'settings')), ['lazy-dash a=1 b=true', 'lazy-dash a=2 b=false', 'old']);
  assert.deepEqual(data.flatSettings('{"task_only":true,"parameters":{"clearance":0.002}}'), { clearance: 0.002, task_only: true });
});

test('a configuration\'s series carries the profile its runs recorded unless its label names it', () => {
  const prof = (profile) => JSON.stringify({ profile, parameters: { parking: profile === 'default' } });
  const runs = [
    run({ settings: prof('default') }),
    run({ config: 'dash', planner: 'dash', settings: prof('default') }),
    run({ config: 'lazy-dash-paper', settings: prof('paper') }),
    run({ config: 'dash', planner: 'dash', settings: prof('paper'), seed: 2 }),
    run({ config: 'old', settings: '{}' }),
  ];
  const g = data.groupRuns(runs, { x: 'objects', split: '', groupBy: 'config' });
  assert.deepEqual(g.series, ['dash (default)', 'dash (paper)', 'lazy-dash (default)', 'lazy-dash-paper', 'old']);
  // Grouped by settings, the profile is said once, in the name, not again as a differing setting.
  data.labelSettings(runs);
  assert.deepEqual(runs.map((r) => data.groupKey(r, 'settings')), ['lazy-dash (default)', 'dash (default) parking=true', 'lazy-dash-paper', 'dash (paper) parking=false', 'old']);
  // A skipped run of a batch is on its configuration's series, profile included.
  const skipped = data.skippedRuns([{ status: 'skipped', family: 'sorting', params: { robots: 2, objects: 8 }, seed: 1, planner: 'dash', config: 'dash', stop_axis: 'objects' }], 'sorting', [runs[1]], false);
  assert.deepEqual(skipped.map((r) => data.groupKey(r, 'config')), ['dash (default)']);
});

test('the planner line prints settings as given, not the nested effective parameter set', () => {
  assert.equal(dom.paramsText({ task_only: true, parameters: { clearance: 0.002 } }), 'task_only=true');
  assert.equal(dom.paramsText({ parameters: { clearance: 0.002 } }), '');
  assert.equal(dom.paramsText({}), '');
  assert.equal(dom.paramsText({ robots: 2, objects: [2, 4] }), 'robots=2 objects=2,4');
  assert.deepEqual(dom.effectiveParameters({ parameters: { clearance: 0.002 } }), { clearance: 0.002 });
  assert.equal(dom.effectiveParameters({ task_only: true }), null);
});

test('numbers: significant digits, no trailing zeros, thousands separated', () => {
  assert.deepEqual([dom.fmtNumber(0.0015), dom.fmtNumber(7.022), dom.fmtNumber(1233), dom.fmtNumber(1143.6, 4), dom.fmtNumber(1143.6, 5), dom.fmtNumber(12345.6, 4)], ['0.0015', '7.02', '1,233', '1,144', '1,143.6', '12,346']);
});

test('success counts finished runs only; skipped and running runs are not failures', () => {
  const cell = { runs: [run({}), run({ status: 'timeout' }), run({ status: 'running', end_time: null }), run({ status: 'skipped' })] };
  assert.deepEqual(data.successOf(cell), { finished: 2, solved: 1, skipped: 1, rate: 0.5 });
});

test('a batch\'s skipped runs join the figures on the lines its runs show, labelled as their configuration', () => {
  const skip = (robots, objects, config = 'dash') => ({ key: `k${robots}-${objects}-${config}`, status: 'skipped', skipped: 'dash solved none of the 3 runs at objects=2', family: 'sorting', params: { robots, objects }, seed: 1, planner: config, config, stop_axis: 'objects' });
  const fetched = data.labelSettings([run({ config: 'dash', planner: 'dash', robots: 2, objects: 2, status: 'timeout' }), run({ robots: 2, objects: 8 })]);
  const batchRuns = [skip(2, 8), skip(2, 16), skip(4, 8), { ...skip(2, 8), family: 'wall' }, { ...skip(2, 32), status: 'solved' }];
  const all = data.skippedRuns(batchRuns, 'sorting', fetched, false);
  // robots=4 has no run of dash among those fetched (say a filter left it out): not shown.
  assert.deepEqual(all.map((r) => [r.robots, r.objects, r.status, r.uuid, r.settings_label]), [[2, 8, 'skipped', null, 'dash'], [2, 16, 'skipped', null, 'dash']]);
  // With a filter, only sizes some fetched run has (objects=8 here): the filter may have cut 16.
  assert.deepEqual(data.skippedRuns(batchRuns, 'sorting', fetched, true).map((r) => r.objects), [8]);
  // In the success figure they are skips, not failures.
  const grouped = data.groupRuns(fetched.concat(all), { x: 'objects', split: 'robots', groupBy: 'config' });
  assert.deepEqual(data.successOf(grouped.cells.get('dash · robots=2|16')), { finished: 0, solved: 0, skipped: 1, rate: null });
});

test('solved against time keeps unsolved runs in the denominator and runs on to the time limit', () => {
  const runs = [run({ total_time: 3 }), run({ total_time: 1 }), run({ status: 'timeout', total_time: 10 }), run({ status: 'crashed', total_time: 0.5 }), run({ total_time: 2 })];
  const c = data.solvedCurve(runs);
  assert.equal(c.finished, 5);
  assert.equal(c.solved, 3);
  assert.equal(c.censored, 2);
  assert.deepEqual(c.points.map((p) => p.x), [1, 2, 3, 10]);
  assert.deepEqual(c.points.map((p) => p.y), [20, 40, 60, 60]);
});

test('ratios pair the two configurations on the same scene only', () => {
  const runs = [
    run({ uuid: 'a', config: 'dash', total_time: 6 }),
    run({ uuid: 'b', total_time: 2 }),
    run({ uuid: 'c', config: 'dash', seed: 2, total_time: 5 }), // no lazy-dash on seed 2
    run({ uuid: 'd', seed: 3, status: 'timeout', total_time: 10 }),
    run({ uuid: 'e', config: 'dash', seed: 3, total_time: 4 }),
  ];
  const r = data.ratios(runs, { metric: 'total_time', numerator: 'dash', denominator: 'lazy-dash', x: 'objects', split: '', groupBy: 'config', params: ['robots', 'objects'], includeUnsolved: false });
  assert.equal(r.length, 1);
  assert.equal(r[0].ratio, 3);
  assert.deepEqual(r[0].uuids.sort(), ['a', 'b']);
});

test('SVG colours: alpha goes to an opacity', () => {
  assert.deepEqual(svg.splitColour('#0072B255'), { colour: '#0072B2', opacity: 0x55 / 255 });
  assert.deepEqual(svg.splitColour('rgba(0, 114, 178, 0.25)'), { colour: '#0072b2', opacity: 0.25 });
  assert.deepEqual(svg.splitColour('#abc'), { colour: '#aabbcc', opacity: 1 });
  assert.equal(svg.splitColour('transparent').opacity, 0);
});

test('SVG recorder: transforms, dashes, clipping and text become SVG', () => {
  globalThis.document = { createElement: () => ({ getContext: () => ({ measureText: (t) => ({ width: 6 * t.length }) }) }) };
  const ctx = new svg.SvgContext(100, 50, {});
  ctx.save();
  ctx.translate(10, 5);
  ctx.beginPath();
  ctx.rect(0, 0, 20, 10);
  ctx.clip();
  ctx.strokeStyle = 'rgba(255,0,0,0.5)';
  ctx.lineWidth = 2;
  ctx.setLineDash([4, 2]);
  ctx.beginPath();
  ctx.moveTo(0, 0);
  ctx.lineTo(5, 5);
  ctx.stroke();
  ctx.restore();
  ctx.font = '600 12px sans-serif';
  ctx.textAlign = 'center';
  ctx.fillText('a < b', 50, 40);
  ctx.beginPath();
  ctx.arc(20, 20, 3, 0, 2 * Math.PI);
  ctx.fill();
  const out = ctx.serialize('3.5in', '1.75in');
  assert.match(out, /<svg[^>]+width="3\.5in"[^>]+viewBox="0 0 100 50"/);
  assert.match(out, /<clipPath id="clip1"><path d="M10 5L30 5L30 15L10 15Z"\/><\/clipPath>/);
  assert.match(out, /<g clip-path="url\(#clip1\)">\n<path d="M10 5L15 10" fill="none" stroke="#ff0000" stroke-opacity="0\.5" stroke-width="2"[^>]*stroke-dasharray="4 2"\/>\n<\/g>/);
  assert.match(out, /<text x="50" y="40" font-family="sans-serif" font-size="12" font-weight="600" text-anchor="middle"[^>]*>a &lt; b<\/text>/);
  assert.match(out, /<path d="M23 20A3 3 0 0 1 17 20A3 3 0 0 1 23 20" fill="#000000" stroke="none"\/>/);
  assert.equal((out.match(/<g /g) || []).length, (out.match(/<\/g>/g) || []).length);
});

test('URL state: a page\u2019s settings round-trip through the hash, defaults and empty values left out', () => {
  globalThis.location = { hash: '#/run/ab%2Fc?overlay=x,y&q=a%20%3D%201' };
  globalThis.history = { state: null, replaceState: (s, t, h) => (globalThis.location.hash = h) };
  const { page, args, params } = url.parseHash();
  assert.equal(page, 'run');
  assert.deepEqual(args, ['ab/c']);
  assert.deepEqual(url.readList(params, 'overlay'), ['x', 'y']);
  assert.equal(url.readString(params, 'q'), 'a = 1');
  url.writeState({ q: 'robots = 2 or robots = 4', log: true, unsolved: false, empty: '', none: null, runs: ['u1', 'u2'], sort: 'id' }, { sort: 'id', unsolved: false });
  const back = url.parseHash();
  assert.equal(back.page, 'run');
  assert.deepEqual(back.args, ['ab/c']);
  assert.deepEqual([...back.params.keys()].sort(), ['log', 'q', 'runs']);
  assert.equal(url.readString(back.params, 'q'), 'robots = 2 or robots = 4');
  assert.equal(url.readBool(back.params, 'log'), true);
  assert.equal(url.readNumber(back.params, 'missing', 7), 7);
  const before = globalThis.location.hash;
  url.writeState({ q: 'x'.repeat(9000) });
  assert.equal(globalThis.location.hash, before, 'a state too long for a link is not written');
  globalThis.location = { hash: '#/runs/%E0%A4%A' };
  assert.deepEqual(url.parseHash().args, ['%E0%A4%A'], 'a malformed escape does not throw');
});


test('a long phase\'s progress reads as steps scheduled of the plan\'s', () => {
  const w = { phase: 'conflict_resolution', done: 37, total: 146, rate: 4.23, current: 'ur5e_3, ur5e_7' };
  assert.equal(dom.fmtWork(w), 'conflict resolution: steps 37/146 (ur5e_3, ur5e_7) · 4.2 steps/s');
  assert.equal(dom.fmtWork({ ...w, current: '' }), '');
  assert.equal(dom.fmtWork({ ...w, done: 146, current: null }, { ended: true }), 'conflict resolution: steps 146/146 · 4.2 steps/s');
  assert.equal(dom.fmtWork({ phase: null, done: null, total: null }), '');
  assert.equal(dom.fmtWork(null), '');
});

test('the default x axis is the one the runs vary: objects when they do, else the parameter with the most values', () => {
  const params = ['robots', 'objects'];
  assert.equal(data.defaultAxis([run({ robots: 2 }), run({ robots: 3 })], params), 'robots');
  assert.equal(data.defaultAxis([run({ objects: 2 }), run({ objects: 4, robots: 3 })], params), 'objects');
  assert.equal(data.defaultAxis([run({ walls: 1 }), run({ walls: 2, robots: 4 })], ['robots', 'walls']), 'robots', 'a tie goes to the first by name, as report picks');
  assert.equal(data.defaultAxis([], params), null);
});

const near = (actual, expected, what) => {
  if (expected === null) return assert.equal(actual, null, what);
  assert.ok(Math.abs(actual - expected) <= 1e-9 * Math.max(1, Math.abs(expected)), `${what}: ${actual}, expected ${expected}`);
};

test('Student t quantiles match the table', () => {
  for (const [p, df, t] of CASES.t_quantiles) near(stats.studentQuantile(p, df), t, `t(${p}; ${df})`);
});

test('paired statistics on the hand-checked cases: ratio with its t interval, sign test on censored pairs, Wilson intervals', () => {
  for (const c of CASES.cases) {
    const got = stats.pairedStats(c.pairs.map(([a, b]) => ({ a: stats.observation(a), b: stats.observation(b) })));
    const e = c.expected;
    for (const k of ['pairs', 'both_solved', 'a_faster', 'b_faster', 'undecided', 'a_solved', 'b_solved']) assert.equal(got[k], e[k], `${c.name}: ${k}`);
    for (const k of ['ratio', 'ratio_low', 'ratio_high', 'p_value']) near(got[k], e[k], `${c.name}: ${k}`);
    near(got.a_success.low, e.a_low, `${c.name}: a low`);
    near(got.a_success.high, e.a_high, `${c.name}: a high`);
    near(got.b_success.low, e.b_low, `${c.name}: b low`);
    near(got.b_success.high, e.b_high, `${c.name}: b high`);
  }
});

test('sign test p stays finite for thousands of pairs', () => {
  assert.equal(stats.signTestP(5000, 10000), 1);
  const p = stats.signTestP(4900, 10000); // the normal approximation gives 0.0466
  assert.ok(p > 0.044 && p < 0.049, `p = ${p}`);
  assert.equal(stats.signTestP(0, 0), null);
});

test('CSV numbers: floating-point noise rounded off, measured digits and integers kept', () => {
  assert.equal(csv.csvNumber(619.6950000000055), '619.695');
  assert.equal(csv.csvNumber(0.1 + 0.2), '0.3');
  assert.equal(csv.csvNumber(0.009797123456), '0.00979712346');
  assert.equal(csv.csvNumber(1234567890123), '1234567890123');
  assert.equal(csv.csvNumber(NaN), '');
  assert.equal(csv.toCsv(['a', 'b'], [{ a: 619.6950000000055, b: 'x,y' }]), 'a,b\r\n619.695,"x,y"\r\n');
});

test('a batch\u2019s time left counts down while a long run works and is re-estimated when a run ends', () => {
  const p = { done: 1, remaining: 3, elapsed: 10, eta: 30 };
  assert.equal(batchEta.steadyEta('b', p), 30);
  // The runner's estimate grows while nothing ends (issue 41: 23 s left became 119 s); this one falls.
  assert.equal(batchEta.steadyEta('b', { ...p, elapsed: 20, eta: 60 }), 20);
  assert.equal(batchEta.steadyEta('b', { ...p, elapsed: 45, eta: 135 }), null, 'past its estimate: unknown');
  assert.equal(batchEta.steadyEta('b', { done: 2, remaining: 2, elapsed: 50, eta: 50 }), 50);
  assert.equal(batchEta.steadyEta('other', { done: 0, remaining: 4, elapsed: 3, eta: null }), null);
  assert.equal(batchEta.steadyEta('b', { done: 4, remaining: 0, elapsed: 90, eta: 0 }), 0);
});

console.log(failed ? `${failed} failed` : 'all passed');
process.exit(failed ? 1 : 0);
