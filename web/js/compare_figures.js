// The Compare page's plots, each drawn from grouped runs (compare_data.js) into a chart box with the
// CSV of what it shows: the paper's figures (representation sizes, planning time by phase, success
// rate), the plot builder (any metric, median and interquartile band or box plots) and per-scene
// ratios of two configurations (Planner Arena's plots: arena_figures.js). Colours follow the series (planner configuration and split value) on every plot;
// line dashes and point shapes tell layers and phases apart.
import { drawChart, valueAxis, sizeAxis, axisTitle, percentAxis, exportButtons, destroyCharts } from './charts.js';
import { el, clear, fmtNumber } from './dom.js';
import { colour } from './palette.js';
import { summary, cellValues, successOf, ratios } from './compare_data.js';
import { wilson } from './paired_stats.js';

const LAYERS = {
  task: { label: 'H_T', point: 'circle', dash: [] },
  motion: { label: 'H_M', point: 'rect', dash: [7, 4] },
  task_extended: { label: 'H_TE', point: 'triangle', dash: [2, 3] },
  motion_extended: { label: 'H_ME', point: 'rectRot', dash: [10, 3, 2, 3] },
};
export const TIME_PARTS = {
  total_time: { label: 'total', point: 'circle', dash: [], width: 2.5 },
  time_construction: { label: 'construction', point: 'rect', dash: [7, 4], width: 1.8 },
  time_query: { label: 'query', point: 'triangle', dash: [2, 3], width: 1.8 },
  time_conflicts: { label: 'conflict resolution', point: 'rectRot', dash: [10, 3, 2, 3], width: 1.8 },
  // Runs recorded before the runs table had it (schema v5), and planners that do not validate, have
  // no validation time: their panels leave the line out.
  time_validation: { label: 'validation', point: 'star', dash: [1, 2], width: 1.8 },
};

/// The figures' shared inputs: {runs, grouped: groupRuns(...), x, split, groupBy, family,
/// includeUnsolved, filter, params, open(filter)}.
function seriesColour(ctx, label) {
  return colour(Math.max(0, ctx.grouped.series.indexOf(label)));
}

function quote(v) {
  const s = String(v);
  return s.includes('"') ? `'${s}'` : `"${s}"`;
}

/// The runs filter that lists the runs behind one point of a plot.
export function cellFilter(ctx, cell) {
  const parts = [`family = ${quote(ctx.family)}`];
  const sample = cell.runs[0];
  if (ctx.groupBy === 'planner') parts.push(`planner = ${quote(sample.planner)}`);
  else parts.push(`config = ${quote(sample.config)}`);
  if (ctx.groupBy === 'settings') {
    // One series may hold runs whose stored settings differ in form only (the same values).
    const distinct = [...new Set(cell.runs.map((r) => r.settings))];
    parts.push(distinct.length === 1 ? `settings = ${quote(distinct[0])}` : `(${distinct.map((v) => `settings = ${quote(v)}`).join(' or ')})`);
  }
  parts.push(`${ctx.x} = ${cell.x}`);
  if (ctx.split && cell.splitValue !== null && cell.splitValue !== undefined) parts.push(`${ctx.split} = ${cell.splitValue}`);
  if (ctx.batch) parts.push(`batch = ${quote(ctx.batch)}`);
  let q = parts.join(' and ');
  if (ctx.filter) q += ` and (${ctx.filter})`;
  return q;
}

function cellsOf(ctx, label) {
  return ctx.grouped.xs.map((x) => ctx.grouped.cells.get(`${label}|${x}`)).filter(Boolean);
}

const SUMMARY_COLUMNS = ['series', 'x', 'n', 'median', 'q1', 'q3', 'min', 'max'];

/// Lines of medians: one per (series, part); `parts` {metric: style}; `only`: one series' label;
/// `yRange` [min, max]: the same y range as other panels.
function medianLines(box, ctx, parts, { yTitle, log, fmt = fmtNumber, unit = '', empty, only = null, yRange = null }) {
  const datasets = [];
  const rows = [];
  let points = 0;
  for (const label of ctx.grouped.series) {
    if (only !== null && label !== only) continue;
    for (const [metric, style] of Object.entries(parts)) {
      const data = [];
      for (const cell of cellsOf(ctx, label)) {
        const s = summary(cellValues(cell, metric, ctx.includeUnsolved));
        if (s.n === 0 || (log && !(s.median > 0))) continue;
        data.push({ x: cell.x, y: s.median, s, filter: cellFilter(ctx, cell) });
        rows.push({ series: label, part: style.label, metric, x: cell.x, ...s, values: undefined });
      }
      if (!data.length) continue;
      points += data.length;
      const c = seriesColour(ctx, label);
      datasets.push({
        label: only !== null ? style.label : Object.keys(parts).length > 1 ? `${label} · ${style.label}` : label,
        data,
        borderColor: c,
        backgroundColor: c,
        pointStyle: style.point,
        pointRadius: 4,
        borderDash: style.dash,
        borderWidth: style.width || 2,
      });
    }
  }
  drawChart(
    box,
    {
      type: 'line',
      data: { datasets },
      options: {
        plugins: {
          title: { display: only !== null, text: only || '', font: { weight: '600' }, padding: { top: 2, bottom: 4 } },
          tooltip: {
            callbacks: {
              label: (c) => `${c.dataset.label}: ${fmt(c.raw.y)}${unit} (median of ${c.raw.s.n}; IQR ${fmt(c.raw.s.q1)}–${fmt(c.raw.s.q3)})`,
              footer: () => 'click: open these runs',
            },
          },
        },
        scales: { x: sizeAxis(`${ctx.x} (count)`, ctx.grouped.xs), y: valueAxis(yTitle, { log, fmt, min: yRange?.[0], max: yRange?.[1] }) },
      },
    },
    points,
    empty,
    { csv: () => ({ columns: ['series', 'part', 'metric', ...SUMMARY_COLUMNS.slice(1)], rows }), onPoint: (raw) => raw.filter && ctx.open(raw.filter) },
  );
}

/// (a) Representation sizes: H_T and H_M (and the extended layers), medians across seeds, log scale.
export function drawSizes(box, ctx, count, extended) {
  const parts = {};
  for (const [layer, style] of Object.entries(LAYERS)) {
    if (!extended && layer.endsWith('extended')) continue;
    parts[`${layer}_${count}`] = style;
  }
  medianLines(box, ctx, parts, { yTitle: `${count} (count, log scale)`, log: true, empty: 'no sizes for this selection' });
}

/// (b) Planning time by phase: one small panel per series (the same y range on all of them), with
/// construction, query, conflict resolution, validation (where the runs have it) and total as
/// lines; log scale. `container` gets the
/// panels and data-points (all of them).
export function drawTimes(container, ctx, shown) {
  destroyCharts(container);
  clear(container);
  const parts = Object.fromEntries(Object.entries(TIME_PARTS).filter(([k]) => shown.includes(k)));
  let lo = Infinity;
  let hi = 0;
  for (const cell of ctx.grouped.cells.values()) {
    for (const metric of Object.keys(parts)) {
      const m = summary(cellValues(cell, metric, ctx.includeUnsolved)).median;
      if (m > 0) {
        lo = Math.min(lo, m);
        hi = Math.max(hi, m);
      }
    }
  }
  // A tenth of the data's span (at least 0.05 decades) above and below: the small panels' points
  // stay clear of the frame.
  const pad = hi > lo ? 10 ** Math.max(0.05, 0.1 * Math.log10(hi / lo)) : 1.5;
  const yRange = hi > 0 ? [lo / pad, hi * pad] : null;
  let points = 0;
  ctx.grouped.series.forEach((label, k) => {
    const testid = `chart-times-${k}`;
    const box = el('div', { class: 'chart-box small', 'data-testid': testid, 'data-points': '0', 'data-series': label });
    box.dataset.exportName = `${ctx.family}-${label}`;
    // The series is the chart's own title (it goes into the exports too).
    container.append(el('div', { class: 'multiple' }, el('div', { class: 'panel-head' }, el('span', { class: 'grow-space' }), exportButtons(box, testid, 'time-breakdown')), box));
    const empty = ctx.includeUnsolved ? `${label}: no times` : `${label}: no solved run`;
    medianLines(box, ctx, parts, { yTitle: 'time (s, log scale)', log: true, fmt: secondsTick, empty, only: label, yRange });
    points += Number(box.dataset.points);
  });
  container.dataset.points = String(points);
  if (ctx.grouped.series.length === 0) container.append(el('div', { class: 'muted', text: 'no times for this selection' }));
}

export function secondsTick(v) {
  if (v === null || v === undefined) return '';
  return v >= 1 ? `${fmtNumber(v)}` : fmtNumber(v, 2);
}

/// Skipped sizes in a bar chart: a cross on the axis where the series' bar would stand.
const skippedCrosses = {
  id: 'skippedCrosses',
  afterDatasetsDraw(chart) {
    const { ctx } = chart;
    const y = chart.scales.y.getPixelForValue(0) - 7;
    chart.data.datasets.forEach((ds, i) => {
      const meta = chart.getDatasetMeta(i);
      if (meta.hidden) return;
      meta.data.forEach((bar, k) => {
        if (!ds.data[k] || !ds.data[k].skippedPoint) return;
        ctx.save();
        ctx.strokeStyle = ds.borderColor;
        ctx.lineWidth = 1.8;
        ctx.beginPath();
        ctx.moveTo(bar.x - 4, y - 4);
        ctx.lineTo(bar.x + 4, y + 4);
        ctx.moveTo(bar.x - 4, y + 4);
        ctx.lineTo(bar.x + 4, y - 4);
        ctx.stroke();
        ctx.restore();
      });
    });
  },
};

/// Each success bar's 95 % Wilson interval as a whisker with caps (raw.ci: [low, high] in percent).
const wilsonWhiskers = {
  id: 'wilsonWhiskers',
  afterDatasetsDraw(chart) {
    const { ctx } = chart;
    const y = chart.scales.y;
    chart.data.datasets.forEach((ds, i) => {
      const meta = chart.getDatasetMeta(i);
      if (meta.hidden) return;
      meta.data.forEach((bar, k) => {
        const ci = ds.data[k] && ds.data[k].ci;
        if (!ci) return;
        const top = y.getPixelForValue(ci[1]);
        const bottom = y.getPixelForValue(ci[0]);
        const cap = Math.min(4, (bar.width || 8) / 3);
        ctx.save();
        ctx.strokeStyle = '#333333';
        ctx.lineWidth = 1;
        ctx.beginPath();
        ctx.moveTo(bar.x, top);
        ctx.lineTo(bar.x, bottom);
        ctx.moveTo(bar.x - cap, top);
        ctx.lineTo(bar.x + cap, top);
        ctx.moveTo(bar.x - cap, bottom);
        ctx.lineTo(bar.x + cap, bottom);
        ctx.stroke();
        ctx.restore();
      });
    });
  },
};

/// (c) Success rate: solved out of finished runs, as grouped bars (one slot per size, one bar per
/// series: equal rates such as 100 % stay side by side instead of hiding each other). 0 % is a stub
/// bar, no runs is a gap, a size the batch skipped a cross on the axis.
export function drawSuccess(box, ctx) {
  const datasets = [];
  const rows = [];
  let points = 0;
  for (const label of ctx.grouped.series) {
    const data = ctx.grouped.xs.map((x) => {
      const cell = ctx.grouped.cells.get(`${label}|${x}`);
      if (!cell) return { x: String(x), y: null };
      const s = successOf(cell);
      if (s.rate === null && s.skipped > 0) {
        // A size the batch skipped (its axis stopped after every seed failed a smaller one).
        rows.push({ series: label, x, finished: 0, solved: 0, skipped: s.skipped, rate: '', rate_low: '', rate_high: '' });
        points += 1;
        return { x: String(x), y: 0, s, skippedPoint: true, filter: cellFilter(ctx, cell) };
      }
      if (s.rate === null) return { x: String(x), y: null };
      const w = wilson(s.solved, s.finished);
      rows.push({ series: label, x, finished: s.finished, solved: s.solved, skipped: s.skipped, rate: s.rate, rate_low: w.low, rate_high: w.high });
      points += 1;
      return { x: String(x), y: 100 * s.rate, s, ci: [100 * w.low, 100 * w.high], filter: cellFilter(ctx, cell) };
    });
    const c = seriesColour(ctx, label);
    datasets.push({
      label,
      data,
      borderColor: c,
      backgroundColor: (p) => (p.raw && p.raw.skippedPoint ? 'rgba(0,0,0,0)' : c),
      borderWidth: (p) => (p.raw && p.raw.skippedPoint ? 0 : 1),
      minBarLength: 3,
      barPercentage: 0.9,
      categoryPercentage: 0.85,
    });
  }
  drawChart(
    box,
    {
      type: 'bar',
      data: { labels: ctx.grouped.xs.map(String), datasets },
      options: {
        interaction: { mode: 'nearest', intersect: true },
        plugins: {
          legend: { labels: { usePointStyle: false } },
          tooltip: { callbacks: { label: (c) => (c.raw.skippedPoint ? `${c.dataset.label}: skipped (${c.raw.s.skipped} runs not run: a smaller size failed on every seed)` : `${c.dataset.label}: ${fmtNumber(c.raw.y)}% (${c.raw.s.solved} of ${c.raw.s.finished} solved; 95% Wilson interval ${fmtNumber(c.raw.ci[0], 2)}–${fmtNumber(c.raw.ci[1], 2)}%)`) } },
        },
        scales: {
          x: { type: 'category', title: axisTitle(`${ctx.x} (count)`), ticks: { autoSkip: false } },
          y: { ...percentAxis('success rate (% of finished runs)'), min: 0 },
        },
      },
      plugins: [skippedCrosses, wilsonWhiskers],
    },
    points,
    'no finished runs for this selection',
    { csv: () => ({ columns: ['series', 'x', 'finished', 'solved', 'skipped', 'rate', 'rate_low', 'rate_high'], rows }), onPoint: (raw) => raw.filter && ctx.open(raw.filter) },
  );
}

/// The plot builder: `metric` against the x parameter, medians with the interquartile band, or boxes.
export function drawBuilder(box, ctx, { metric, label, style, log }) {
  if (style === 'box') return drawBuilderBoxes(box, ctx, { metric, label, log });
  const datasets = [];
  const rows = [];
  let points = 0;
  for (const series of ctx.grouped.series) {
    const data = [];
    for (const cell of cellsOf(ctx, series)) {
      const s = summary(cellValues(cell, metric, ctx.includeUnsolved).filter((v) => !log || v > 0));
      if (s.n === 0) continue;
      data.push({ x: cell.x, y: s.median, q1: s.q1, q3: s.q3, s, filter: cellFilter(ctx, cell) });
      rows.push({ series, x: cell.x, ...s, values: undefined });
    }
    if (!data.length) continue;
    points += data.length;
    const c = seriesColour(ctx, series);
    datasets.push({ label: `${series} IQR low`, band: true, data: data.map((d) => ({ x: d.x, y: d.q1 })), borderColor: 'transparent', backgroundColor: `${c}33`, pointRadius: 0, fill: false });
    datasets.push({ label: `${series} IQR`, band: true, data: data.map((d) => ({ x: d.x, y: d.q3 })), borderColor: 'transparent', backgroundColor: `${c}33`, pointRadius: 0, fill: '-1' });
    datasets.push({ label: series, data, borderColor: c, backgroundColor: c, pointRadius: 4, borderWidth: 2 });
  }
  drawChart(
    box,
    {
      type: 'line',
      data: { datasets },
      options: {
        plugins: {
          legend: { labels: { filter: (item, data) => !data.datasets[item.datasetIndex].band } },
          tooltip: {
            filter: (item) => !item.dataset.band,
            callbacks: { label: (c) => `${c.dataset.label}: median ${fmtNumber(c.raw.y)}, IQR ${fmtNumber(c.raw.q1)}–${fmtNumber(c.raw.q3)} (n=${c.raw.s.n})` },
          },
        },
        scales: { x: sizeAxis(`${ctx.x} (count)`, ctx.grouped.xs), y: valueAxis(`${label}${log ? ' (log scale)' : ''}`, { log }) },
      },
    },
    points,
    'no values of this metric for this selection',
    { csv: () => ({ columns: SUMMARY_COLUMNS, rows }), onPoint: (raw) => raw.filter && ctx.open(raw.filter) },
  );
  return null;
}

function drawBuilderBoxes(box, ctx, { metric, label, log }) {
  const rows = [];
  let points = 0;
  const datasets = ctx.grouped.series.map((series) => {
    const c = seriesColour(ctx, series);
    return {
      label: series,
      data: ctx.grouped.xs.map((x) => {
        const cell = ctx.grouped.cells.get(`${series}|${x}`);
        const values = cell ? cellValues(cell, metric, ctx.includeUnsolved).filter((v) => typeof v === 'number' && (!log || v > 0)) : [];
        points += values.length;
        if (values.length) rows.push({ series, x, ...summary(values), values: undefined });
        return values;
      }),
      backgroundColor: `${c}55`,
      borderColor: c,
      borderWidth: 1.5,
      outlierBackgroundColor: c,
      outlierRadius: 3,
      itemRadius: 0,
      coef: 1.5,
    };
  });
  drawChart(
    box,
    {
      type: 'boxplot',
      data: { labels: ctx.grouped.xs.map(String), datasets },
      options: { scales: { x: { title: axisTitle(`${ctx.x} (count)`) }, y: valueAxis(`${label}${log ? ' (log scale)' : ''}`, { log }) } },
    },
    points,
    'no values of this metric for this selection',
    { csv: () => ({ columns: SUMMARY_COLUMNS, rows }) },
  );
}

/// Per scene (same family, parameters and seed), `numerator` / `denominator` of a metric; the line
/// is the median ratio at each x (one per split value), the dotted line ratio 1.
export function drawRatio(box, ctx, { metric, label, numerator, denominator }) {
  const list = ratios(ctx.runs, { metric, numerator, denominator, x: ctx.x, split: ctx.split, groupBy: ctx.groupBy, params: ctx.params, includeUnsolved: ctx.includeUnsolved });
  const splits = [...new Set(list.map((r) => r.split))].sort((a, b) => a - b);
  const datasets = [];
  splits.forEach((sv, k) => {
    const mine = list.filter((r) => r.split === sv);
    const c = colour(k);
    const name = ctx.split ? `${ctx.split}=${sv}` : 'scenes';
    datasets.push({ type: 'scatter', label: `${name}: each scene`, data: mine.map((r) => ({ x: r.x, y: r.ratio, r, filter: `uuid = ${quote(r.uuids[0])} or uuid = ${quote(r.uuids[1])}` })), backgroundColor: `${c}88`, borderColor: c, pointRadius: 3 });
    const xs = [...new Set(mine.map((r) => r.x))].sort((a, b) => a - b);
    // The median as a bar across each x (a line through them when there are several): with one x
    // value a line alone would not show.
    datasets.push({ type: 'line', label: `${name}: median`, data: xs.map((x) => ({ x, y: summary(mine.filter((r) => r.x === x).map((r) => r.ratio)).median })), borderColor: c, backgroundColor: c, pointStyle: 'line', pointRadius: 9, pointBorderWidth: 3, pointHoverRadius: 9, borderWidth: 2 });
  });
  const xs = [...new Set(list.map((r) => r.x))];
  if (list.length) {
    datasets.push({ type: 'line', label: 'equal (ratio 1)', data: [{ x: Math.min(...xs) - 0.5, y: 1 }, { x: Math.max(...xs) + 0.5, y: 1 }], borderColor: '#777777', borderDash: [3, 3], borderWidth: 1, pointRadius: 0 });
  }
  drawChart(
    box,
    {
      type: 'scatter',
      data: { datasets },
      options: {
        plugins: { tooltip: { callbacks: { label: (c) => (c.raw.r ? `${c.raw.r.scene}: ${fmtNumber(c.raw.r.a)} / ${fmtNumber(c.raw.r.b)} = ${fmtNumber(c.raw.y)}` : `${c.dataset.label}: ${fmtNumber(c.raw.y)}`) } } },
        scales: { x: sizeAxis(`${ctx.x} (count)`, xs), y: valueAxis(`${label}: ${numerator} / ${denominator} (ratio, log scale)`, { log: true }) },
      },
    },
    list.length,
    `no scene has a value of this metric from both ${numerator} and ${denominator}`,
    { csv: () => ({ columns: ['scene', 'x', 'split', 'numerator', 'denominator', 'ratio'], rows: list.map((r) => ({ ...r, numerator: r.a, denominator: r.b })) }), onPoint: (raw) => raw.filter && ctx.open(raw.filter) },
  );
}

