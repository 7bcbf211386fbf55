// Compare: the paper's plots from the results database, per planner configuration. Representation
// sizes (task and motion) against a scenario parameter on a log scale; the planning time broken
// down by phase as stacked bars with the total; box plots across seeds with an outlier toggle;
// success rates; and a "diff only" table of runs selected on the Runs page.
import { api, query } from '../api.js';
import { on, debounce } from '../events.js';
import { el, clear, fmtNumber, fmtSeconds, errorBox, badge } from '../dom.js';
import { drawChart, valueAxis, axisTitle, destroyCharts } from '../charts.js';
import { colourFor, PHASE_COLOURS, PHASE_LABELS, LAYER_STYLES } from '../palette.js';
import { selectedRuns } from './runs.js';

const PHASES = Object.keys(PHASE_COLOURS);

function chartPanel(title, testid, help, controls = []) {
  const box = el('div', { class: 'chart-box', 'data-testid': testid, 'data-points': '0' });
  const panel = el('div', { class: 'panel' }, el('h2', { text: title }), help ? el('div', { class: 'muted', text: help }) : null, controls.length ? el('div', { class: 'toolbar' }, controls) : null, box);
  return { panel, box };
}

function median(g, metric) {
  const m = g.metrics[metric];
  return m && m.median !== null && m.median !== undefined ? m.median : null;
}

export function mount(root) {
  const familySelect = el('select', { 'data-testid': 'compare-family' });
  const xSelect = el('select', { 'data-testid': 'compare-x' });
  const groupSelect = el('select', {}, el('option', { value: 'config', text: 'planner configuration' }), el('option', { value: 'planner', text: 'planner' }));
  const splitSelect = el('select', { 'data-testid': 'compare-split', title: 'one series per value of another parameter' });
  const filterInput = el('input', { type: 'text', size: 44, placeholder: 'optional filter, e.g. robots = 4' });
  const unsolved = el('input', { type: 'checkbox' });
  const status = el('div', { class: 'error' });
  const countSelect = el('select', {}, el('option', { value: 'vertices', text: 'vertices' }), el('option', { value: 'hyperarcs', text: 'hyperarcs' }));
  const boxMetric = el('select', { 'data-testid': 'box-metric' });
  const boxLog = el('input', { type: 'checkbox', checked: true });
  const outliers = el('input', { type: 'checkbox', checked: true, 'data-testid': 'outliers' });

  const task = chartPanel('Task representation sizes', 'chart-task-sizes', 'Median across seeds of H_T and H_TE, log scale.', [el('label', {}, 'count', countSelect)]);
  const motion = chartPanel('Motion representation sizes', 'chart-motion-sizes', 'Median across seeds of H_M and H_ME, log scale (task-only runs have none).');
  const times = chartPanel('Planning time breakdown', 'chart-times', 'Median time of each phase (task phases in blues and green, motion phases in oranges and purple); the black mark is the median total.');
  const boxes = chartPanel('Across seeds', 'chart-box', 'Box: quartiles; whiskers: 1.5 × IQR; dots: outliers.', [
    el('label', {}, 'metric', boxMetric),
    el('label', {}, boxLog, 'log scale'),
    el('label', {}, outliers, 'show outliers'),
  ]);
  const success = chartPanel('Success rate', 'chart-success', 'Solved runs out of finished runs (timeouts, infeasible and crashed runs count as failures).');
  const diffBox = el('div', { 'data-testid': 'diff' });
  const diffOnly = el('input', { type: 'checkbox', checked: true, 'data-testid': 'diff-only' });
  const diffInput = el('input', { type: 'text', size: 60, placeholder: 'run uuids, comma separated (or select runs on the Runs page)' });

  root.append(
    el('h1', { text: 'Compare' }),
    el(
      'div',
      { class: 'panel toolbar' },
      el('label', {}, 'family', familySelect),
      el('label', {}, 'x axis', xSelect),
      el('label', {}, 'group by', groupSelect),
      el('label', {}, 'series per', splitSelect),
      filterInput,
      el('label', { title: 'medians over timeouts and infeasible runs too' }, unsolved, 'include unsolved runs'),
      status,
    ),
    el('div', { class: 'grid2' }, task.panel, motion.panel, times.panel, boxes.panel, success.panel),
    el('div', { class: 'panel' }, el('h2', { text: 'Runs side by side' }), el('div', { class: 'toolbar' }, diffInput, el('label', {}, diffOnly, 'differences only')), diffBox),
  );

  let overview = [];
  let series = null;

  function configs() {
    return [...new Set(series.groups.map((g) => g.group))].sort();
  }
  function xs() {
    return [...new Set(series.groups.map((g) => g.x))].sort((a, b) => a - b);
  }
  function group(cfg, x) {
    return series.groups.find((g) => g.group === cfg && g.x === x);
  }
  const xName = () => series.x;

  function drawSizes(target, layers, title) {
    const cfgs = configs();
    const count = countSelect.value;
    const datasets = [];
    let points = 0;
    for (const cfg of cfgs) {
      for (const layer of layers) {
        const metric = `${layer}_${count}`;
        const data = [];
        for (const x of xs()) {
          const g = group(cfg, x);
          const y = g ? median(g, metric) : null;
          if (y !== null && y > 0) data.push({ x, y, n: g.metrics[metric].n });
        }
        if (data.length === 0) continue;
        points += data.length;
        const style = LAYER_STYLES[layer];
        datasets.push({
          label: `${cfg} · ${style.label}`,
          data,
          borderColor: colourFor(cfg, cfgs),
          backgroundColor: colourFor(cfg, cfgs),
          pointStyle: style.point,
          pointRadius: 5,
          borderDash: style.dash,
        });
      }
    }
    drawChart(
      target.box,
      {
        type: 'line',
        data: { datasets },
        options: {
          plugins: {
            title: { display: false, text: title },
            tooltip: { callbacks: { label: (c) => `${c.dataset.label}: ${fmtNumber(c.raw.y)} ${count} (median of ${c.raw.n})` } },
          },
          scales: {
            x: { type: 'linear', title: axisTitle(`${xName()} (count)`), ticks: { precision: 0 } },
            y: valueAxis(`${count} (count, log scale)`, { log: true }),
          },
        },
      },
      points,
    );
  }

  function drawTimes() {
    const cfgs = configs();
    const cats = [];
    for (const cfg of cfgs) for (const x of xs()) if (group(cfg, x)) cats.push(group(cfg, x));
    const labels = cats.map((g) => [g.group, `${xName()}=${g.x}`]);
    const datasets = PHASES.map((p) => ({
      type: 'bar',
      label: PHASE_LABELS[p],
      data: cats.map((g) => median(g, `time_${p}`) ?? 0),
      backgroundColor: PHASE_COLOURS[p],
      stack: 'phases',
    }));
    datasets.push({
      type: 'line',
      label: 'total (median)',
      data: cats.map((g) => median(g, 'total_time')),
      showLine: false,
      pointStyle: 'line',
      pointRadius: 14,
      pointBorderWidth: 3,
      borderColor: '#000000',
      backgroundColor: '#000000',
    });
    const points = cats.filter((g) => median(g, 'total_time') !== null).length;
    drawChart(
      times.box,
      {
        type: 'bar',
        data: { labels, datasets },
        options: {
          plugins: {
            tooltip: {
              mode: 'index',
              callbacks: {
                label: (c) => `${c.dataset.label}: ${fmtSeconds(c.raw)}`,
                footer: (items) => {
                  const g = cats[items[0].dataIndex];
                  return `task ${fmtSeconds(median(g, 'time_task'))} · motion ${fmtSeconds(median(g, 'time_motion'))} · n=${g.metrics.total_time.n}`;
                },
              },
            },
          },
          scales: { x: { stacked: true, title: axisTitle(`planner configuration and ${xName()}`) }, y: valueAxis('time (s)', { stacked: true }) },
        },
      },
      points,
    );
  }

  function drawBoxes() {
    const cfgs = configs();
    const metric = boxMetric.value || 'total_time';
    const meta = series.metrics.find((m) => m.name === metric);
    const log = boxLog.checked;
    let points = 0;
    const datasets = cfgs.map((cfg) => {
      const data = xs().map((x) => {
        const g = group(cfg, x);
        const values = g ? g.metrics[metric].values.filter((v) => !log || v > 0) : [];
        points += values.length;
        return values;
      });
      return {
        label: cfg,
        data,
        backgroundColor: `${colourFor(cfg, cfgs)}55`,
        borderColor: colourFor(cfg, cfgs),
        borderWidth: 1.5,
        outlierBackgroundColor: colourFor(cfg, cfgs),
        outlierRadius: outliers.checked ? 3.5 : 0,
        itemRadius: 0,
        coef: 1.5,
      };
    });
    drawChart(
      boxes.box,
      {
        type: 'boxplot',
        data: { labels: xs().map(String), datasets },
        options: {
          plugins: { tooltip: { callbacks: {} } },
          scales: {
            x: { title: axisTitle(`${xName()} (count)`) },
            y: valueAxis(`${meta.label} (${meta.unit}${log ? ', log scale' : ''})`, { log }),
          },
        },
      },
      points,
    );
  }

  function drawSuccess() {
    const cfgs = configs();
    let points = 0;
    const datasets = cfgs.map((cfg) => ({
      label: cfg,
      data: xs().map((x) => {
        const g = group(cfg, x);
        if (!g || g.success_rate === null) return null;
        points += 1;
        return 100 * g.success_rate;
      }),
      backgroundColor: colourFor(cfg, cfgs),
    }));
    drawChart(
      success.box,
      {
        type: 'bar',
        data: { labels: xs().map(String), datasets },
        options: {
          plugins: {
            tooltip: {
              callbacks: {
                label: (c) => {
                  const g = group(c.dataset.label, xs()[c.dataIndex]);
                  return `${c.dataset.label}: ${c.raw.toFixed(0)}% (${g.solved} of ${g.finished} solved)`;
                },
              },
            },
          },
          scales: { x: { title: axisTitle(`${xName()} (count)`) }, y: valueAxis('success rate (%)', { min: 0, max: 100, percent: true }) },
        },
      },
      points,
    );
  }

  function drawAll() {
    if (!series) return;
    drawSizes(task, ['task', 'task_extended'], 'task sizes');
    drawSizes(motion, ['motion', 'motion_extended'], 'motion sizes');
    drawTimes();
    drawBoxes();
    drawSuccess();
  }

  async function loadSeries() {
    if (!familySelect.value || !xSelect.value) return;
    try {
      series = await api.get(
        `/api/series${query({
          family: familySelect.value,
          x: xSelect.value,
          group_by: groupSelect.value,
          split: splitSelect.value,
          q: filterInput.value.trim(),
          include_unsolved: unsolved.checked ? 1 : '',
        })}`,
      );
      status.textContent = '';
      if (boxMetric.options.length === 0) {
        for (const m of series.metrics) boxMetric.append(el('option', { value: m.name, text: `${m.label} (${m.unit})` }));
        boxMetric.value = 'total_time';
      }
      drawAll();
    } catch (e) {
      status.textContent = e.message;
    }
  }

  function fillX() {
    const fam = overview.find((f) => f.family === familySelect.value);
    clear(xSelect);
    for (const p of fam ? fam.parameters : []) xSelect.append(el('option', { value: p, text: p }));
    if (fam && fam.parameters.includes('objects')) xSelect.value = 'objects';
    fillSplit();
  }

  /// The other parameters; by default the first of them, so that runs of different sizes never mix.
  function fillSplit() {
    const fam = overview.find((f) => f.family === familySelect.value);
    const others = (fam ? fam.parameters : []).filter((p) => p !== xSelect.value);
    clear(splitSelect).append(el('option', { value: '', text: '(none: all together)' }));
    for (const p of others) splitSelect.append(el('option', { value: p, text: p }));
    splitSelect.value = others.includes('robots') ? 'robots' : others[0] || '';
  }

  async function loadDiff() {
    const uuids = diffInput.value.split(',').map((s) => s.trim()).filter(Boolean);
    clear(diffBox);
    if (uuids.length < 2) {
      diffBox.append(el('div', { class: 'muted', text: 'Select two or more runs on the Runs page (or paste their uuids) to compare them field by field.' }));
      return;
    }
    try {
      const [cols, list] = await Promise.all([api.get('/api/runs/columns'), api.get(`/api/runs${query({ uuids: uuids.join(','), limit: 100, sort: 'id', order: 'asc' })}`)]);
      const runs = list.runs;
      const rows = [];
      for (const c of cols.columns) {
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
      const head = el('tr', {}, el('th', { text: 'field' }), runs.map((r) => el('th', {}, el('a', { href: `#/run/${r.uuid}`, class: 'mono', text: r.uuid.slice(0, 8) }))));
      diffBox.append(el('div', { class: 'table-wrap' }, el('table', { class: 'data', 'data-testid': 'diff-table' }, el('thead', {}, head), el('tbody', {}, rows))));
    } catch (e) {
      diffBox.append(errorBox(e.message));
    }
  }

  familySelect.addEventListener('change', () => {
    fillX();
    loadSeries();
  });
  xSelect.addEventListener('change', () => {
    fillSplit();
    loadSeries();
  });
  for (const c of [splitSelect, groupSelect, unsolved]) c.addEventListener('change', loadSeries);
  filterInput.addEventListener('keydown', (e) => {
    if (e.key === 'Enter') loadSeries();
  });
  countSelect.addEventListener('change', () => {
    drawSizes(task, ['task', 'task_extended'], 'task sizes');
    drawSizes(motion, ['motion', 'motion_extended'], 'motion sizes');
  });
  for (const c of [boxMetric, boxLog, outliers]) c.addEventListener('change', drawBoxes);
  diffOnly.addEventListener('change', loadDiff);
  diffInput.addEventListener('change', loadDiff);
  diffInput.value = selectedRuns().join(', ');

  const reload = debounce(loadSeries, 1000);
  const offs = [on('run', (m) => m.status !== 'running' && reload())];

  (async () => {
    try {
      overview = (await api.get('/api/compare/overview')).families;
      if (overview.length === 0) {
        status.textContent = 'No runs in the database yet: launch a batch first.';
        return;
      }
      for (const f of overview) familySelect.append(el('option', { value: f.family, text: `${f.family} (${f.runs} runs)` }));
      familySelect.value = overview.some((f) => f.family === 'sorting') ? 'sorting' : overview[0].family;
      fillX();
      await loadSeries();
    } catch (e) {
      status.textContent = e.message;
    }
  })();
  loadDiff();
  return () => {
    offs.forEach((off) => off());
    destroyCharts(root);
  };
}
