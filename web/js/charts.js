// Chart.js with the box-plot plugin, and the settings every plot shares: labelled axes with units,
// a legend, values on hover. Each chart's container gets data-points (how many data points were
// drawn) so people and tests can tell an empty plot from a drawn one.
import { Chart, registerables } from 'chart.js';
import { BoxPlotController, BoxAndWiskers } from '@sgratzl/chartjs-chart-boxplot';
import { el, clear, fmtNumber } from './dom.js';

Chart.register(...registerables, BoxPlotController, BoxAndWiskers);
Chart.defaults.font.family = 'system-ui, -apple-system, "Segoe UI", Roboto, sans-serif';
Chart.defaults.color = '#1d232a';
Chart.defaults.animation = false; // plots redraw on live updates; animation only distracts

export { Chart };

export function axisTitle(text) {
  return { display: true, text, font: { weight: '600' } };
}

/// A value axis: linear or logarithmic, with a title that names the unit.
export function valueAxis(title, { log = false, stacked = false, min, max, percent = false } = {}) {
  return {
    type: log ? 'logarithmic' : 'linear',
    stacked,
    min,
    max,
    title: axisTitle(title),
    ticks: {
      // Log axes label only 1, 2 and 5 times a power of ten; skipping would drop exactly those.
      autoSkip: !log,
      callback: (v, index, ticks) => {
        if (percent) return `${v}%`;
        if (log) {
          // 1, 2 and 5 times a power of ten on short ranges (never an axis without labels), powers
          // of ten alone on long ones (never a crowded axis).
          const values = ticks.map((t) => t.value).filter((x) => x > 0);
          const decades = Math.log10(Math.max(...values) / Math.min(...values));
          const mantissa = v / 10 ** Math.floor(Math.log10(v) + 1e-9);
          const shown = decades > 2.5 ? [1] : [1, 2, 5];
          return shown.some((m) => Math.abs(mantissa - m) < 1e-6) ? fmtNumber(v) : '';
        }
        return fmtNumber(v);
      },
    },
  };
}

/// Replaces the contents of `box` with a canvas holding a new chart (the old one is destroyed).
export function drawChart(box, config, pointCount, emptyText = 'no data for this selection') {
  if (box._chart) box._chart.destroy();
  clear(box);
  box.dataset.points = String(pointCount);
  if (pointCount === 0) {
    box.append(el('div', { class: 'chart-empty', text: emptyText }));
    box._chart = null;
    return null;
  }
  const canvas = el('canvas', { role: 'img', 'aria-label': config.options?.plugins?.title?.text || 'plot' });
  box.append(canvas);
  config.options = {
    responsive: true,
    maintainAspectRatio: false,
    interaction: { mode: 'nearest', intersect: false },
    ...config.options,
  };
  box._chart = new Chart(canvas, config);
  return box._chart;
}

export function destroyCharts(root) {
  for (const box of root.querySelectorAll('.chart-box')) {
    if (box._chart) box._chart.destroy();
    box._chart = null;
  }
}
