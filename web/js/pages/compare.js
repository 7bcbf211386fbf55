// Compare: plots of one scenario family's runs, per planner configuration, all from the runs table.
// The paper's figures (representation sizes H_T and H_M, planning time by phase, success rate), a
// plot builder (any metric against any scenario parameter, as medians with interquartile bands or as
// box plots), per-scene ratios of two configurations, Planner Arena's fraction solved against time
// and time-to-solve distributions, and runs side by side. Every setting is in the URL; every plot
// exports SVG, PNG and CSV; a click on a point opens its runs.
import { api } from '../api.js';
import { on, debounce } from '../events.js';
import { el, clear, fmtNumber, errorBox, badge } from '../dom.js';
import { chartPanel, destroyCharts, figureButtons } from '../charts.js';
import { fetchRuns, groupRuns, parametersOf, groupKey, defaultAxis, DERIVED_METRICS } from '../compare_data.js';
import { drawSizes, drawTimes, drawSuccess, drawBuilder, drawRatio, TIME_PARTS } from '../compare_figures.js';
import { drawSolvedCurve, drawTimeToSolve } from '../arena_figures.js';
import { drawStats, statsCsvButton } from '../compare_stats.js';
import { writeState, readString, readBool, readList } from '../url_state.js';
import { selectedRuns } from './runs.js';

const METRIC_GROUPS = ['time', 'size', 'count', 'outcome'];

function select(testid, options, value, title) {
  const s = el('select', { 'data-testid': testid, title });
  for (const o of options) s.append(el('option', { value: o.value, text: o.text }));
  if (value !== undefined && options.some((o) => o.value === value)) s.value = value;
  return s;
}

export function mount(root, args, params = new URLSearchParams()) {
  const state = {
    family: readString(params, 'family'),
    x: readString(params, 'x'),
    split: params.has('split') ? (params.get('split') === 'none' ? '' : params.get('split')) : null, // null: choose a default
    group: readString(params, 'group', 'config'),
    q: readString(params, 'q'),
    batch: readString(params, 'batch'),
    unsolved: readBool(params, 'unsolved'),
    ext: readBool(params, 'ext'),
    phases: params.has('phases') ? readList(params, 'phases') : Object.keys(TIME_PARTS),
    metric: readString(params, 'metric', 'total_time'),
    style: readString(params, 'style', 'band'),
    log: readBool(params, 'log', true),
    num: readString(params, 'num'),
    den: readString(params, 'den'),
    ratio: readString(params, 'ratio', 'total_time'),
    runs: params.has('runs') ? readList(params, 'runs') : selectedRuns(),
    diff: readBool(params, 'diff', true),
  };
  // The x axis as the link or the user chose it; otherwise the one the fetched runs vary (defaultAxis).
  let xChosen = params.has('x');
  let mounted = true; // a fetch or a debounced reload that ends after the page was left must not write its URL
  function save() {
    if (!mounted) return;
    writeState({ ...state, split: state.split === '' ? 'none' : state.split, phases: state.phases.join(',') }, { group: 'config', unsolved: false, ext: false, phases: Object.keys(TIME_PARTS).join(','), metric: 'total_time', style: 'band', log: true, ratio: 'total_time', diff: true });
  }

  const familySelect = el('select', { 'data-testid': 'compare-family' });
  const xSelect = el('select', { 'data-testid': 'compare-x' });
  const splitSelect = el('select', { 'data-testid': 'compare-split', title: 'one series per value of another parameter' });
  const groupSelect = select('compare-group', [
    { value: 'config', text: 'planner configuration' },
    { value: 'planner', text: 'planner' },
    { value: 'settings', text: 'configuration and its settings (sweeps)' },
  ], state.group);
  const filterInput = el('input', { type: 'text', size: 40, value: state.q, placeholder: 'optional filter, e.g. robots = 4 or robots = 8', 'data-testid': 'compare-filter' });
  const batchInput = el('input', { type: 'text', size: 22, value: state.batch, placeholder: 'batch id (optional)', 'data-testid': 'compare-batch' });
  const unsolved = el('input', { type: 'checkbox', checked: state.unsolved, 'data-testid': 'compare-unsolved' });
  const status = el('div', { class: 'error', 'data-testid': 'compare-status' });
  const info = el('span', { class: 'muted', 'data-testid': 'compare-info' });

  const extBox = el('input', { type: 'checkbox', checked: state.ext });
  const sizesV = chartPanel({ tall: true, title: 'Representation sizes: vertices', testid: 'chart-task-sizes', name: 'sizes-vertices', help: 'Median across seeds; H_T solid circles, H_M dashed squares (extended layers: dotted), log scale. Click a point for its runs.', controls: [el('label', {}, extBox, 'extended layers (H_TE, H_ME)')] });
  const sizesH = chartPanel({ tall: true, title: 'Representation sizes: hyperarcs', testid: 'chart-motion-sizes', name: 'sizes-hyperarcs', help: 'Median across seeds, the same series and styles, log scale.' });
  const phaseBoxes = Object.entries(TIME_PARTS).map(([k, p]) => {
    const box = el('input', { type: 'checkbox', checked: state.phases.includes(k), 'data-phase': k });
    return el('label', {}, box, p.label);
  });
  const timesBox = el('div', { class: 'multiples', 'data-testid': 'chart-times', 'data-points': '0' });
  const times = {
    box: timesBox,
    panel: el(
      'div',
      { class: 'panel wide' },
      el('div', { class: 'panel-head' }, el('h2', { text: 'Planning time by phase' }), figureButtons('figure-times', 'time-breakdown', () => [...timesBox.querySelectorAll('.chart-box')])),
      el('div', { class: 'muted', text: 'One panel per series, the same y range on all: median across seeds of construction (task + motion), query (task + motion), conflict detection and resolution, validation (where the runs have it), and total; log scale. Line style and point shape: phase. Each panel exports on its own.' }),
      el('div', { class: 'toolbar' }, phaseBoxes),
      timesBox,
    ),
  };
  const success = chartPanel({ tall: true, title: 'Success rate', testid: 'chart-success', name: 'success-rate', help: 'Solved runs out of finished runs (timeouts, infeasible and crashed runs count as failures). One bar per series and size, side by side so that equal rates never hide each other: 0 % is a stub bar, no runs a gap, a cross on the axis a size the batch skipped. Whiskers: 95 % Wilson interval of the rate.' });

  const metricSelect = el('select', { 'data-testid': 'builder-metric' });
  const styleSelect = select('builder-style', [{ value: 'band', text: 'median and interquartile band' }, { value: 'box', text: 'box plots' }], state.style);
  const logBox = el('input', { type: 'checkbox', checked: state.log, 'data-testid': 'builder-log' });
  const builder = chartPanel({ title: 'Plot builder', testid: 'chart-builder', name: 'builder', help: 'Any metric against the x axis parameter, per series. Box: quartiles; whiskers: 1.5 × IQR; dots: outliers.', controls: [el('label', {}, 'metric', metricSelect), el('label', {}, 'as', styleSelect), el('label', {}, logBox, 'log scale')], tall: true });
  const numSelect = el('select', { 'data-testid': 'ratio-num' });
  const denSelect = el('select', { 'data-testid': 'ratio-den' });
  const ratioMetric = el('select', { 'data-testid': 'ratio-metric' });
  const ratio = chartPanel({ title: 'Ratio per scene', testid: 'chart-ratio', name: 'ratio', help: 'For each scene (same parameters and seed) solved by both: the first series\u2019 value over the second\u2019s; the line is the median per x.', controls: [el('label', {}, ratioMetric), numSelect, el('span', { text: '/' }), denSelect] });
  const statsBox = el('div', { 'data-testid': 'paired-stats', 'data-rows': '0' });
  const statsTitle = el('h2', { text: 'Paired statistics' });
  const statsPanel = el(
    'div',
    { class: 'panel wide' },
    el('div', { class: 'panel-head' }, statsTitle, el('span', { class: 'exports' }, statsCsvButton(statsBox, 'paired-statistics'))),
    el('div', { class: 'muted', text: 'The two configurations of the ratio plot on the same scenes and seeds, per size and over all. Time ratio: geometric mean of the total-time ratios over the pairs both solved, with a 95 % Student t interval on the log ratios. Sign test: two-sided exact binomial on Gehan\u2019s pair scores, where a run that did not solve (timeout, infeasible, crash) is censored at its time limit: a solve within the partner\u2019s limit counts as faster, two failures say nothing; failures are neither dropped nor counted as taking the limit. Success: solved pairs with a 95 % Wilson interval. The same numbers as `dashbench report`.' }),
    statsBox,
  );
  const solved = chartPanel({ title: 'Runs solved against time (Planner Arena)', testid: 'chart-solved-time', name: 'solved-vs-time', help: 'Share of finished runs solved within t. Runs that time out or fail stay in the count (censored, never dropped): a curve ends below 100 % if some runs were not solved.' });
  const tts = chartPanel({ title: 'Time to solve (Planner Arena)', testid: 'chart-time-to-solve', name: 'time-to-solve', help: 'Distribution of solved runs\u2019 total time per series; the label says how many of the runs were solved.' });

  const diffBox = el('div', { 'data-testid': 'diff' });
  const diffOnly = el('input', { type: 'checkbox', checked: state.diff, 'data-testid': 'diff-only' });
  const diffInput = el('input', { type: 'text', size: 60, value: state.runs.join(', '), placeholder: 'run uuids, comma separated (or select runs on the Runs page)', 'data-testid': 'diff-input' });

  root.append(
    el('h1', { text: 'Compare' }),
    el(
      'div',
      { class: 'panel toolbar' },
      el('label', {}, 'family', familySelect),
      el('label', {}, 'x axis', xSelect),
      el('label', {}, 'series per', groupSelect),
      el('label', {}, 'and per', splitSelect),
      filterInput,
      batchInput,
      el('label', { title: 'medians over timeouts and infeasible runs too' }, unsolved, 'include unsolved runs'),
      info,
      status,
    ),
    el('div', { class: 'panel-head' }, el('h2', { class: 'section', text: 'The paper\u2019s figures' }), figureButtons('figure-sizes', 'sizes', () => [sizesV.box, sizesH.box], () => 2)),
    el('div', { class: 'grid2' }, sizesV.panel, sizesH.panel),
    times.panel,
    el('div', { class: 'grid2' }, success.panel, solved.panel),
    el('h2', { class: 'section', text: 'Plot builder' }),
    el('div', { class: 'grid2' }, builder.panel, ratio.panel),
    statsPanel,
    el('h2', { class: 'section', text: 'Distributions and runs' }),
    el('div', { class: 'grid2' }, tts.panel, el('div', { class: 'panel' }, el('h2', { text: 'Runs side by side' }), el('div', { class: 'toolbar' }, diffInput, el('label', {}, diffOnly, 'differences only')), diffBox)),
  );

  let overview = [];
  let columns = [];
  let data = null; // {runs, truncated}
  let ctx = null;

  function open(filter) {
    location.hash = `#/runs?q=${encodeURIComponent(filter)}`;
  }

  function metricOptions() {
    const out = [];
    for (const g of METRIC_GROUPS) {
      for (const c of columns.filter((c) => c.group === g && c.type !== 'text')) out.push({ value: c.name, text: c.label });
      if (g === 'time') for (const m of DERIVED_METRICS) out.push({ value: m.name, text: m.label });
    }
    return out;
  }
  const labelOf = (name) => metricOptions().find((o) => o.value === name)?.text || name;

  function drawAll() {
    if (!data) return;
    const params = parametersOf(data.runs, columns);
    ctx = {
      runs: data.runs,
      grouped: groupRuns(data.runs, { x: state.x, split: state.split, groupBy: state.group }),
      x: state.x,
      split: state.split,
      groupBy: state.group,
      family: state.family,
      batch: state.batch,
      filter: state.q,
      includeUnsolved: state.unsolved,
      params,
      open,
    };
    for (const p of [sizesV, sizesH, times, success, builder, ratio, solved, tts]) p.box.dataset.exportName = state.family;
    drawSizes(sizesV.box, ctx, 'vertices', state.ext);
    drawSizes(sizesH.box, ctx, 'hyperarcs', state.ext);
    drawTimes(times.box, ctx, state.phases);
    drawSuccess(success.box, ctx);
    drawBuilderPanel();
    drawRatioPanel();
    drawSolvedCurve(solved.box, ctx);
    drawTimeToSolve(tts.box, ctx);
  }
  function drawBuilderPanel() {
    if (!ctx) return;
    // File names say what is plotted: builder-sorting-collision_checks-by-objects-box.svg, not builder-sorting.svg.
    builder.box.dataset.exportName = `${state.family}-${state.metric}-by-${state.x}${state.style === 'box' ? '-box' : ''}`;
    drawBuilder(builder.box, ctx, { metric: state.metric, label: labelOf(state.metric), style: state.style, log: state.log });
  }
  function drawRatioPanel() {
    if (!ctx) return;
    const groups = [...new Set(ctx.runs.map((r) => groupKey(r, state.group)))].sort();
    const fill = (sel, key, preferred, not) => {
      clear(sel);
      for (const g of groups) sel.append(el('option', { value: g, text: g }));
      if (!groups.includes(state[key])) state[key] = groups.includes(preferred) && preferred !== not ? preferred : groups.find((g) => g !== not) || groups[0] || '';
      sel.value = state[key];
    };
    fill(numSelect, 'num', 'dash', null);
    fill(denSelect, 'den', 'lazy-dash', state.num);
    ratio.box.dataset.exportName = `${state.family}-${state.ratio}-${state.num}-vs-${state.den}`;
    drawRatio(ratio.box, ctx, { metric: state.ratio, label: labelOf(state.ratio), numerator: state.num, denominator: state.den });
    statsTitle.textContent = `Paired statistics: ${state.num} against ${state.den}`;
    statsBox.dataset.exportName = `${state.family}-${state.num}-vs-${state.den}`;
    drawStats(statsBox, ctx, { numerator: state.num, denominator: state.den });
  }

  async function load() {
    if (!mounted) return;
    save();
    if (!state.family || !state.x) return;
    info.textContent = 'loading…';
    try {
      data = await fetchRuns(state.family, state.q, state.batch);
      status.textContent = '';
      const ran = data.runs.length - data.skipped;
      info.textContent = `${ran} runs${data.skipped ? ` (and ${data.skipped} skipped by the axis stop rule)` : ''}${data.truncated ? ' (the first ones only: narrow the filter)' : ''}`;
      info.dataset.runs = String(ran);
      info.dataset.skipped = String(data.skipped);
      pickAxis();
      drawAll();
    } catch (e) {
      data = null;
      info.textContent = '';
      status.textContent = e.message;
      clear(statsBox).dataset.rows = '0';
      for (const p of [sizesV, sizesH, times, success, builder, ratio, solved, tts]) {
        destroyCharts(p.panel);
        clear(p.box).append(el('div', { class: 'chart-empty', text: 'no plot: see the error above' }));
        p.box.dataset.points = '0';
      }
    }
  }

  function fillX() {
    const fam = overview.find((f) => f.family === state.family);
    const ps = fam ? fam.parameters : [];
    clear(xSelect);
    for (const p of ps) xSelect.append(el('option', { value: p, text: p }));
    if (!ps.includes(state.x)) state.x = ps.includes('objects') ? 'objects' : ps[0] || '';
    xSelect.value = state.x;
    fillSplit();
  }

  /// With no x axis chosen, the one the fetched runs vary (a batch over robots opens on robots).
  function pickAxis() {
    if (xChosen) return;
    const fam = overview.find((f) => f.family === state.family);
    const best = defaultAxis(data.runs, fam ? fam.parameters : []);
    if (!best || best === state.x) return;
    state.x = best;
    xSelect.value = best;
    fillSplit();
    save();
  }

  /// The other parameters; by default the first of them, so that runs of different sizes never mix.
  function fillSplit() {
    const fam = overview.find((f) => f.family === state.family);
    const others = (fam ? fam.parameters : []).filter((p) => p !== state.x);
    clear(splitSelect).append(el('option', { value: '', text: '(nothing else)' }));
    for (const p of others) splitSelect.append(el('option', { value: p, text: p }));
    if (state.split === null || (state.split && !others.includes(state.split))) state.split = others.includes('robots') ? 'robots' : others[0] || '';
    splitSelect.value = state.split;
  }

  async function loadDiff() {
    state.runs = diffInput.value.split(',').map((s) => s.trim()).filter(Boolean).slice(0, 50);
    save();
    clear(diffBox);
    if (state.runs.length < 2) {
      diffBox.append(el('div', { class: 'muted', text: 'Select two or more runs on the Runs page (or paste their uuids) to compare them field by field.' }));
      return;
    }
    try {
      const list = await api.get(`/api/runs?uuids=${encodeURIComponent(state.runs.join(','))}&limit=100&sort=id&order=asc`);
      const runs = list.runs;
      const rows = [];
      for (const c of columns) {
        const values = runs.map((r) => r[c.name]);
        const same = values.every((v) => JSON.stringify(v) === JSON.stringify(values[0]));
        if (diffOnly.checked && same) continue;
        rows.push(
          el(
            'tr',
            { class: same ? 'same' : '' },
            el('th', { text: c.label, title: c.name }),
            values.map((v) => el('td', { class: typeof v === 'number' ? 'num' : '' }, c.name === 'status' && v ? badge(v) : v === null || v === undefined ? '' : typeof v === 'number' ? fmtNumber(v, 4) : String(v))),
          ),
        );
      }
      const overlay = runs.length > 1 ? el('a', { href: `#/run/${runs[0].uuid}?overlay=${runs.slice(1).map((r) => r.uuid).join(',')}`, 'data-testid': 'open-overlay' }, 'overlay these runs on one run page') : null;
      const head = el('tr', {}, el('th', { text: 'field' }), runs.map((r) => el('th', {}, el('a', { href: `#/run/${r.uuid}`, class: 'mono', text: r.uuid.slice(0, 8) }))));
      diffBox.append(el('div', { class: 'toolbar' }, overlay), el('div', { class: 'table-wrap' }, el('table', { class: 'data', 'data-testid': 'diff-table' }, el('thead', {}, head), el('tbody', {}, rows))));
    } catch (e) {
      diffBox.append(errorBox(e.message));
    }
  }

  familySelect.addEventListener('change', () => {
    state.family = familySelect.value;
    state.split = null;
    xChosen = false;
    fillX();
    load();
  });
  xSelect.addEventListener('change', () => {
    state.x = xSelect.value;
    xChosen = true;
    fillSplit();
    save();
    drawAll();
  });
  splitSelect.addEventListener('change', () => {
    state.split = splitSelect.value;
    save();
    drawAll();
  });
  groupSelect.addEventListener('change', () => {
    state.group = groupSelect.value;
    save();
    drawAll();
  });
  unsolved.addEventListener('change', () => {
    state.unsolved = unsolved.checked;
    save();
    drawAll();
  });
  for (const input of [filterInput, batchInput]) {
    input.addEventListener('keydown', (e) => {
      if (e.key !== 'Enter') return;
      state.q = filterInput.value.trim();
      state.batch = batchInput.value.trim();
      load();
    });
  }
  extBox.addEventListener('change', () => {
    state.ext = extBox.checked;
    save();
    drawSizes(sizesV.box, ctx, 'vertices', state.ext);
    drawSizes(sizesH.box, ctx, 'hyperarcs', state.ext);
  });
  for (const label of phaseBoxes) {
    label.querySelector('input').addEventListener('change', () => {
      state.phases = phaseBoxes.map((l) => l.querySelector('input')).filter((i) => i.checked).map((i) => i.dataset.phase);
      save();
      if (ctx) drawTimes(times.box, ctx, state.phases);
    });
  }
  metricSelect.addEventListener('change', () => {
    state.metric = metricSelect.value;
    save();
    drawBuilderPanel();
  });
  styleSelect.addEventListener('change', () => {
    state.style = styleSelect.value;
    save();
    drawBuilderPanel();
  });
  logBox.addEventListener('change', () => {
    state.log = logBox.checked;
    save();
    drawBuilderPanel();
  });
  for (const [sel, key] of [[numSelect, 'num'], [denSelect, 'den'], [ratioMetric, 'ratio']]) {
    sel.addEventListener('change', () => {
      state[key] = sel.value;
      save();
      drawRatioPanel();
    });
  }
  diffOnly.addEventListener('change', () => {
    state.diff = diffOnly.checked;
    loadDiff();
  });
  diffInput.addEventListener('change', loadDiff);

  const reload = debounce(load, 1500);
  const offs = [on('run', (m) => m.status !== 'running' && reload())];

  (async () => {
    try {
      const [ov, cols] = await Promise.all([api.get('/api/compare/overview'), api.get('/api/runs/columns')]);
      overview = ov.families;
      columns = cols.columns;
      for (const o of metricOptions()) {
        metricSelect.append(el('option', { value: o.value, text: o.text }));
        ratioMetric.append(el('option', { value: o.value, text: o.text }));
      }
      if (!metricOptions().some((o) => o.value === state.metric)) state.metric = 'total_time';
      metricSelect.value = state.metric;
      ratioMetric.value = metricOptions().some((o) => o.value === state.ratio) ? state.ratio : 'total_time';
      if (overview.length === 0) {
        status.textContent = 'No runs in the database yet: launch a batch first.';
        return;
      }
      for (const f of overview) familySelect.append(el('option', { value: f.family, text: `${f.family} (${f.runs} runs)` }));
      if (state.batch && !state.family) {
        // "compare this batch": the batch's family.
        const first = await api.get(`/api/runs?limit=1&q=${encodeURIComponent(`batch = "${state.batch.replace(/"/g, '')}"`)}`);
        if (first.runs.length) state.family = first.runs[0].family;
      }
      if (!overview.some((f) => f.family === state.family)) state.family = overview.some((f) => f.family === 'sorting') ? 'sorting' : overview[0].family;
      familySelect.value = state.family;
      fillX();
      await load();
      await loadDiff();
    } catch (e) {
      status.textContent = e.message;
    }
  })();
  return () => {
    mounted = false;
    offs.forEach((off) => off());
    destroyCharts(root);
  };
}
