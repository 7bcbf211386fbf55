// A run's phase breakdown: one horizontal bar per phase (the run's total in that phase) and one for
// the whole run, on a log axis so that a millisecond phase stays visible beside a 30 s one; each bar
// says its time and share of the run; the tooltip splits it by iteration. Below, the table of phases.
import { drawChart, valueAxis, axisTitle } from './charts.js';
import { clear, fmtNumber, fmtSeconds, table } from './dom.js';
import { PHASE_COLOURS, PHASE_LABELS } from './palette.js';

export const PHASES_HELP = 'Seconds in each phase over the whole run and the run\u2019s total (log scale, so millisecond phases show); each bar is labelled with its time and share of the total; hover for the seconds per iteration.';
const TOTAL_COLOUR = '#1d232a';
const LABEL_ROOM = 0.3; // of the bars' span in decades, kept right of the longest bar for its label

/// Writes the time and share at the end of each bar (in the chart, so exports have them too).
const barLabels = {
  id: 'dashbenchBarLabels',
  afterDatasetsDraw(chart) {
    const ds = chart.data.datasets[0];
    const meta = chart.getDatasetMeta(0);
    if (!ds || !meta) return;
    const { ctx } = chart;
    const size = chart.options.scales?.x?.ticks?.font?.size || 11;
    ctx.save();
    ctx.font = `${size}px ${chart.options.font?.family || 'system-ui, sans-serif'}`;
    ctx.fillStyle = '#1d232a';
    ctx.textAlign = 'left';
    ctx.textBaseline = 'middle';
    meta.data.forEach((bar, i) => {
      const raw = ds.data[i];
      if (!raw || !(raw.x > 0)) return;
      ctx.fillText(raw.text, bar.x + 4, bar.y);
    });
    ctx.restore();
  },
};

/// d: the run detail (/api/runs/UUID): {run, phases: {phase: seconds}, phase_iterations: [{iteration, phase, seconds}]}.
export function drawPhaseBreakdown(box, tableBox, d) {
  const names = Object.keys(PHASE_COLOURS);
  const perIteration = (p) => d.phase_iterations.filter((x) => x.phase === p).sort((a, b) => a.iteration - b.iteration);
  const secondsOf = (p) => {
    const stored = d.phases ? d.phases[p] : null;
    if (typeof stored === 'number') return stored;
    const parts = perIteration(p);
    return parts.length ? parts.reduce((s, x) => s + x.seconds, 0) : null;
  };
  const total = typeof d.run.total_time === 'number' ? d.run.total_time : null;
  const share = (v) => (total > 0 ? ` (${fmtNumber((100 * v) / total, 2)} %)` : '');
  const bars = names
    .map((p) => ({ phase: p, label: PHASE_LABELS[p], seconds: secondsOf(p), colour: PHASE_COLOURS[p] }))
    .filter((b) => b.seconds > 0);
  if (total > 0) bars.push({ phase: 'total', label: 'total', seconds: total, colour: TOTAL_COLOUR });
  const values = bars.map((b) => b.seconds);
  const lo = Math.min(...values);
  const hi = Math.max(...values);
  // Bars start at a third of the shortest, so it has length; room on the right for the labels.
  const min = lo / 3;
  const span = Math.log10(hi / min);
  const max = hi * 10 ** (LABEL_ROOM * span + 0.05);
  const data = bars.map((b) => ({ x: b.seconds, y: b.label, phase: b.phase, text: `${fmtSeconds(b.seconds)}${b.phase === 'total' ? '' : share(b.seconds)}` }));
  const csvRows = [];
  for (const b of bars) {
    if (b.phase !== 'total') for (const x of perIteration(b.phase)) csvRows.push({ phase: b.phase, iteration: x.iteration, seconds: x.seconds });
    csvRows.push({ phase: b.phase, iteration: 'all', seconds: b.seconds });
  }
  drawChart(
    box,
    {
      type: 'bar',
      data: {
        labels: bars.map((b) => b.label),
        datasets: [{ label: 'seconds', data, backgroundColor: bars.map((b) => b.colour), borderColor: bars.map((b) => b.colour), borderWidth: 0, barPercentage: 0.8, categoryPercentage: 0.9 }],
      },
      options: {
        indexAxis: 'y',
        parsing: { xAxisKey: 'x', yAxisKey: 'y' },
        plugins: {
          legend: { display: false },
          tooltip: {
            callbacks: {
              label: (c) => `${c.raw.text}`,
              afterLabel: (c) => {
                const parts = c.raw.phase === 'total' ? [] : perIteration(c.raw.phase);
                return parts.length > 1 ? parts.map((x) => `iteration ${x.iteration}: ${fmtSeconds(x.seconds)}`) : [];
              },
            },
          },
        },
        scales: {
          x: valueAxis('time (s, log scale)', { log: true, min, max }),
          y: { type: 'category', title: axisTitle('phase'), ticks: { autoSkip: false } },
        },
      },
      plugins: [barLabels],
    },
    bars.filter((b) => b.phase !== 'total').length,
    'no phase times stored for this run',
    { csv: () => ({ columns: ['phase', 'iteration', 'seconds'], rows: csvRows }) },
  );
  if (!tableBox) return;
  const rows = names.map((p) => ({ phase: PHASE_LABELS[p], seconds: d.phases ? d.phases[p] : null, share: total && d.phases && typeof d.phases[p] === 'number' ? `${((100 * d.phases[p]) / total).toFixed(1)}%` : '' }));
  rows.push({ phase: 'total', seconds: total, share: '' });
  clear(tableBox).append(table(['phase', 'seconds', 'share'], rows, { cell: (c, v) => (c === 'seconds' && typeof v === 'number' ? fmtSeconds(v) : v) }));
}
