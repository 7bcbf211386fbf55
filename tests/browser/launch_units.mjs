#!/usr/bin/env node
// Unit tests under Node of the Launch page's planner configurations (web/js/pages/launch_planners.js)
// and the dashboard's words for durations and counts (web/js/dom.js): parameter values and sweeps,
// the paper profile, automatic labels, and "1 h 51 min" / "1 run".
//   node tests/browser/launch_units.mjs
import assert from 'node:assert/strict';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const WEB = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..', 'web', 'js');
const lp = await import(pathToFileURL(path.join(WEB, 'pages', 'launch_planners.js')));
const dom = await import(pathToFileURL(path.join(WEB, 'dom.js')));

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

// A few parameters as /api/planners lists them.
const PARAMS = [
  { name: 'straight_first', type: 'bool', default: 'true', paper: 'false', description: '' },
  { name: 'deep_backoffs', type: 'bool', default: 'true', paper: 'false', description: '' },
  { name: 'transition_resamples', type: 'int', default: '2', paper: '0', min: 0, max: 100, description: '' },
  { name: 'clearance', type: 'real', default: '0.002', paper: '', min: 0, max: 0.05, description: '' },
];
const info = (n) => PARAMS.find((p) => p.name === n);

test('a parameter field holds nothing (the default), one value, or a list (a sweep), checked against its range', () => {
  assert.deepEqual(lp.parseParamValues(info('clearance'), ''), []);
  assert.deepEqual(lp.parseParamValues(info('clearance'), '0.005'), [0.005]);
  assert.deepEqual(lp.parseParamValues(info('clearance'), '0.002, 0.005'), [0.002, 0.005]);
  assert.deepEqual(lp.parseParamValues(info('straight_first'), 'true, false'), [true, false]);
  assert.throws(() => lp.parseParamValues(info('clearance'), '0.5'), /out of range 0..0.05/);
  assert.throws(() => lp.parseParamValues(info('transition_resamples'), '1.5'), /not an integer/);
  assert.throws(() => lp.parseParamValues(info('straight_first'), 'yes'), /not true or false/);
  assert.throws(() => lp.parseParamValues(info('clearance'), '0.002, 0.002'), /listed twice/);
});

test('the paper profile sets every extension to its paper value and leaves clearance alone', () => {
  assert.deepEqual(lp.paperSettings(PARAMS), { straight_first: false, deep_backoffs: false, transition_resamples: 0 });
});

test('automatic labels name the planner, the paper profile and the settings', () => {
  assert.equal(lp.autoLabel('lazy-dash', false, {}, PARAMS), 'lazy-dash');
  assert.equal(lp.autoLabel('lazy-dash', true, {}, PARAMS), 'lazy-task');
  assert.equal(lp.autoLabel('lazy-dash', false, { clearance: 0.005 }, PARAMS), 'lazy-dash clearance=0.005');
  assert.equal(lp.autoLabel('lazy-dash', false, lp.paperSettings(PARAMS), PARAMS), 'lazy-dash-paper');
  assert.equal(lp.autoLabel('lazy-dash', false, { ...lp.paperSettings(PARAMS), clearance: 0.005 }, PARAMS), 'lazy-dash-paper clearance=0.005');
  assert.ok(lp.isAutoLabel({ name: 'lazy-dash', label: 'lazy-dash clearance=0.005', settings: { clearance: 0.005 } }, [{ name: 'lazy-dash', parameters: PARAMS }]));
  assert.ok(!lp.isAutoLabel({ name: 'lazy-dash', label: 'clr5', settings: { clearance: 0.005 } }, [{ name: 'lazy-dash', parameters: PARAMS }]));
});

test('a row with lists expands into one configuration per combination, labelled with its values', () => {
  const row = { name: 'lazy-dash', label: 'clr', taskOnly: true, fixed: { deep_backoffs: false }, swept: [['clearance', [0.002, 0.005]], ['straight_first', [true, false]]], extra: {} };
  const out = lp.expandConfigurations(row, PARAMS);
  assert.equal(out.length, 4);
  assert.deepEqual(out[0], { name: 'lazy-dash', label: 'clr clearance=0.002 straight_first=true', settings: { deep_backoffs: false, clearance: 0.002, straight_first: true, task_only: true } });
  assert.equal(new Set(out.map((e) => e.label)).size, 4, 'labels are distinct');
  const single = lp.expandConfigurations({ name: 'lazy-dash', label: '', taskOnly: false, fixed: { clearance: 0.005 }, swept: [], extra: { test_fault: 'abort' } }, PARAMS);
  assert.deepEqual(single, [{ name: 'lazy-dash', label: 'lazy-dash clearance=0.005', settings: { test_fault: 'abort', clearance: 0.005 } }]);
  const big = { name: 'lazy-dash', label: '', taskOnly: false, fixed: {}, swept: [['transition_resamples', [...Array(9).keys()]], ['clearance', [0, 0.001, 0.002, 0.003, 0.004, 0.005, 0.006, 0.007]]], extra: {} };
  assert.throws(() => lp.expandConfigurations(big, PARAMS), /72 configurations \(at most 64 per row\)/);
});

test('durations read in hours and minutes past an hour; counts agree with their noun', () => {
  assert.equal(dom.fmtSeconds(0.0098), '9.8 ms');
  assert.equal(dom.fmtSeconds(125), '2 min 5 s');
  assert.equal(dom.fmtSeconds(400000), '111 h 7 min');
  assert.equal(dom.fmtSeconds(3599.6), '1 h 0 min');
  assert.equal(dom.plural(1, 'run'), '1 run');
  assert.equal(dom.plural(2, 'run'), '2 runs');
  assert.equal(dom.plural(1200, 'process', 'processes'), '1,200 processes');
});

console.log(failed ? `${failed} failed` : 'all passed');
process.exit(failed ? 1 : 0);
