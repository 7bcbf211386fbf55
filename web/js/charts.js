// Chart.js with the box-plot plugin, and the settings every plot shares: labelled axes with units,
// a legend, values on hover, axes padded so that no point sits on the border, log axes that always
// carry labels. Each chart's container gets data-points (how many data points were drawn) so people
// and tests can tell an empty plot from a drawn one; every chart panel can export its plot (SVG,
// PNG at publication size) and the aggregated data behind it (CSV).
import { Chart, registerables } from 'chart.js';
import { BoxPlotController, BoxAndWiskers } from '@sgratzl/chartjs-chart-boxplot';
import { el, clear, fmtNumber } from './dom.js';
import { chartSvg, chartPng, cloneConfig, toCsv, download, fileStem, figureSvg, figurePng, EXPORT_SIZES } from './export.js';

Chart.register(...registerables, BoxPlotController, BoxAndWiskers);
Chart.defaults.font.family = 'system-ui, -apple-system, "Segoe UI", Roboto, sans-serif';
Chart.defaults.color = '#1d232a';
Chart.defaults.animation = false; // plots redraw on live updates; animation only distracts
// Legends show each series' point shape (layers and phases differ by shape, not only by dash).
Chart.defaults.plugins.legend.labels.usePointStyle = true;
Chart.defaults.plugins.legend.labels.boxHeight = 8;

export { Chart };

const LOG_PAD_DECADES = 0.06; // room above and below the data on a log axis, as a share of its span
const LOG_PAD_MIN = 0.04; // ...at least this many decades
const NICE_STEPS = [1, 2, 5, 10];

export function axisTitle(text) {
  return { display: true, text, font: { weight: '600' } };
}

function niceStep(raw) {
  const p = 10 ** Math.floor(Math.log10(raw));
  return p * NICE_STEPS.find((s) => s * p >= raw - 1e-12);
}

/// Tick values for a log axis over [min, max] (both > 0) that always include labelled ticks: powers
/// of ten on long ranges, 1-2-5 on one to a few decades, evenly spaced round numbers below a decade.
export function logTicks(min, max) {
  if (!(min > 0) || !(max > min)) return [];
  const decades = Math.log10(max / min);
  const inRange = (v) => v >= min * (1 - 1e-9) && v <= max * (1 + 1e-9);
  if (decades >= 0.8) {
    const mantissas = decades > 2.5 ? [1] : [1, 2, 5];
    const out = [];
    for (let k = Math.floor(Math.log10(min)); k <= Math.ceil(Math.log10(max)); k++) {
      for (const m of mantissas) if (inRange(m * 10 ** k)) out.push(Number((m * 10 ** k).toPrecision(12)));
    }
    // Thinned from the top down, so that the power of ten nearest the top keeps its label.
    const kept = decades > 5 ? out.filter((v, i) => (out.length - 1 - i) % Math.ceil(decades / 5) === 0) : out;
    // Powers of ten only: the space between the last labelled power and the top of the axis (1 to
    // 9 s, say) gets a 5 or a 2 where it fits at least an eighth of the axis away from that power.
    if (mantissas.length === 1 && kept.length) {
      const top = kept[kept.length - 1];
      const m = [5, 2].find((k) => inRange(k * top) && Math.log10(k) >= 0.125 * decades);
      if (m) kept.push(Number((m * top).toPrecision(12)));
    }
    if (kept.length >= 2) return kept;
  }
  // Below a decade: round numbers evenly spaced, the widest 1-2-5 step that still gives 4 ticks.
  let step = 10 ** Math.ceil(Math.log10(max - min));
  const evenly = (st) => {
    const out = [];
    for (let v = Math.ceil(min / st) * st; v <= max * (1 + 1e-9); v += st) out.push(Number(v.toPrecision(12)));
    return out;
  };
  for (let k = 0; k < 12 && evenly(step).length < 4; k++) step /= [2, 2.5, 2][k % 3];
  return evenly(step);
}

/// A value axis: linear or logarithmic, with a title that names the unit. `fmt` formats tick labels.
export function valueAxis(title, { log = false, stacked = false, min, max, percent = false, fmt = fmtNumber } = {}) {
  const axis = {
    type: log ? 'logarithmic' : 'linear',
    stacked,
    min,
    max,
    title: axisTitle(title),
    ticks: { autoSkip: !log, callback: (v) => (percent ? `${v}%` : fmt(v)) },
  };
  if (log) {
    axis.bounds = 'data';
    axis.afterDataLimits = (scale) => {
      if (min === undefined && max === undefined && scale.min > 0 && scale.max >= scale.min) {
        const pad = Math.max(LOG_PAD_MIN, LOG_PAD_DECADES * Math.log10(scale.max / scale.min));
        scale.min /= 10 ** pad;
        scale.max *= 10 ** pad;
      }
    };
    axis.afterBuildTicks = (scale) => {
      const ticks = logTicks(scale.min, scale.max);
      if (ticks.length) scale.ticks = ticks.map((value) => ({ value }));
    };
  } else if (!percent) {
    axis.grace = '6%';
  }
  return axis;
}

/// A 0-100 % axis with room above and below, labelled every 20 %.
export function percentAxis(title) {
  return {
    type: 'linear',
    min: -4,
    max: 104,
    title: axisTitle(title),
    ticks: { callback: (v) => `${v}%` },
    afterBuildTicks: (scale) => {
      scale.ticks = [0, 20, 40, 60, 80, 100].map((value) => ({ value }));
    },
  };
}

/// An x axis of integer problem sizes (objects, robots, ...): half a step of room at each end, ticks
/// on integers only.
export function sizeAxis(title, values) {
  const finite = values.filter(Number.isFinite);
  const lo = finite.length ? Math.min(...finite) : 0;
  const hi = finite.length ? Math.max(...finite) : 1;
  const pad = Math.max(0.5, 0.05 * (hi - lo));
  return {
    type: 'linear',
    min: lo - pad,
    max: hi + pad,
    title: axisTitle(title),
    ticks: { autoSkip: false, callback: (v) => fmtNumber(v) },
    afterBuildTicks: (scale) => {
      // Integers only, at most about 10 (Chart.js would put ticks on the padded ends and skip some
      // integers next to them).
      const step = Math.max(1, Math.round(niceStep(Math.max(1, (hi - lo) / 8))));
      const ticks = [];
      for (let v = Math.ceil(lo / step) * step; v <= hi; v += step) ticks.push({ value: v });
      if (ticks.length === 0 || ticks[0].value > lo) ticks.unshift({ value: lo });
      scale.ticks = ticks;
    },
  };
}

/// SVG, PNG and CSV buttons and a size for the chart in `box` (data-testid TESTID-svg, ...).
export function exportButtons(box, testid, name) {
  const size = el('select', { title: 'export size', 'data-testid': `${testid}-size` }, Object.entries(EXPORT_SIZES).map(([k, s]) => el('option', { value: k, text: s.label })));
  const stem = () => fileStem(name, box.dataset.exportName);
  const button = (text, what, help) => el('button', { type: 'button', class: 'small secondary', title: help, 'data-testid': `${testid}-${what}`, onclick: () => exportBox(box, what, size.value, stem()) }, text);
  return el(
    'span',
    { class: 'exports' },
    button('SVG', 'svg', 'the plot as vector graphics at publication size'),
    button('PNG', 'png', 'the plot as a 300 dpi image at publication size'),
    button('CSV', 'csv', 'the aggregated data behind the plot'),
    size,
  );
}

/// A panel with a title, a help line, controls, the chart box and its export buttons.
export function chartPanel({ title, testid, help = '', controls = [], name = testid, tall = false }) {
  const box = el('div', { class: `chart-box${tall ? ' tall' : ''}`, 'data-testid': testid, 'data-points': '0' });
  const head = el('div', { class: 'panel-head' }, el('h2', { text: title }), exportButtons(box, testid, name));
  const panel = el('div', { class: 'panel' }, head, help ? el('div', { class: 'muted', text: help }) : null, controls.length ? el('div', { class: 'toolbar' }, controls) : null, box);
  return { panel, box, head };
}

/// Buttons that export the plots in `boxes()` as one figure (panels in a grid), SVG or PNG.
export function figureButtons(testid, name, boxes, columns = (n) => Math.min(3, n)) {
  const size = el('select', { title: 'panel size', 'data-testid': `${testid}-size` }, Object.entries(EXPORT_SIZES).map(([k, s]) => el('option', { value: k, text: `panels: ${s.label}` })));
  const run = async (what) => {
    const configs = boxes().filter((b) => b._config).map((b) => b._config);
    if (!configs.length) return;
    const stem = fileStem(name, boxes()[0]?.dataset.exportName);
    if (what === 'svg') download(`${stem}.svg`, figureSvg(configs, size.value, columns(configs.length)), 'image/svg+xml');
    else download(`${stem}.png`, await figurePng(configs, size.value, columns(configs.length)));
  };
  return el(
    'span',
    { class: 'exports' },
    el('span', { class: 'muted', text: 'whole figure:' }),
    el('button', { type: 'button', class: 'small secondary', 'data-testid': `${testid}-svg`, title: 'every panel in one SVG', onclick: () => run('svg') }, 'SVG'),
    el('button', { type: 'button', class: 'small secondary', 'data-testid': `${testid}-png`, title: 'every panel in one 300 dpi PNG', onclick: () => run('png') }, 'PNG'),
    size,
  );
}

function exportBox(box, what, size, stem) {
  if (what === 'csv') {
    const data = box._csv ? box._csv() : null;
    if (data) download(`${stem}.csv`, toCsv(data.columns, data.rows), 'text/csv');
    return;
  }
  if (!box._config) return;
  if (what === 'svg') download(`${stem}.svg`, chartSvg(box._config, size), 'image/svg+xml');
  else download(`${stem}.png`, chartPng(box._config, size));
}

/// Replaces the contents of `box` with a canvas holding a new chart (the old one is destroyed).
/// `csv`: () => {columns, rows}, the data behind the plot; `onPoint(raw, dataset)`: a click on a point.
export function drawChart(box, config, pointCount, emptyText = 'no data for this selection', { csv, onPoint } = {}) {
  if (box._chart) box._chart.destroy();
  clear(box);
  box.dataset.points = String(pointCount);
  box._csv = csv || null;
  if (pointCount === 0) {
    box.append(el('div', { class: 'chart-empty', text: emptyText }));
    box._chart = null;
    box._config = null;
    return null;
  }
  const canvas = el('canvas', { role: 'img', 'aria-label': config.options?.plugins?.title?.text || box.dataset.testid || 'plot' });
  box.append(canvas);
  config.options = {
    responsive: true,
    maintainAspectRatio: false,
    interaction: { mode: 'nearest', intersect: false },
    ...config.options,
  };
  if (onPoint) {
    config.options.onClick = (event, elements, chart) => {
      const hit = chart.getElementsAtEventForMode(event, 'nearest', { intersect: true }, false)[0];
      if (!hit) return;
      const ds = chart.data.datasets[hit.datasetIndex];
      onPoint(ds.data[hit.index], ds, hit.index);
    };
    config.options.onHover = (event, elements, chart) => {
      const hit = chart.getElementsAtEventForMode(event, 'nearest', { intersect: true }, false)[0];
      chart.canvas.style.cursor = hit ? 'pointer' : 'default';
    };
  }
  box._config = cloneConfig(config);
  box._chart = new Chart(canvas, config);
  return box._chart;
}

export function destroyCharts(root) {
  for (const box of root.querySelectorAll('.chart-box')) {
    if (box._chart) box._chart.destroy();
    box._chart = null;
  }
}
