// Planner Arena's plots on the Compare page: the fraction of runs solved against time (runs that
// did not solve stay in the denominator: censored, never dropped) and time-to-solve distributions,
// per series (planner configuration, and split value when the page splits).
import { drawChart, valueAxis, axisTitle, logTicks, percentAxis } from './charts.js';
import { fmtNumber, fmtSeconds } from './dom.js';
import { colour } from './palette.js';
import { summary, solvedCurve, isFinished } from './compare_data.js';
import { secondsTick } from './compare_figures.js';

/// Planner Arena: the share of each series' finished runs solved within t, against t (log scale).
/// Unsolved runs stay in the denominator; each curve runs on to the longest time limit.
export function drawSolvedCurve(box, ctx) {
  const datasets = [];
  const rows = [];
  let points = 0;
  const bySeries = new Map();
  for (const cell of ctx.grouped.cells.values()) {
    const key = ctx.split ? cell.series : cell.group;
    if (!bySeries.has(key)) bySeries.set(key, []);
    bySeries.get(key).push(...cell.runs);
  }
  const labels = [...bySeries.keys()].sort();
  const curves = new Map(labels.map((label) => [label, solvedCurve(bySeries.get(label))]));
  const starts = [...curves.values()].filter((c) => c.points.length).map((c) => c.points[0].x).filter((x) => x > 0);
  // Every curve starts at 0 % at the left edge of the (log) time axis, below the first solve of all.
  const start = starts.length ? Math.min(...starts) / 1.3 : null;
  for (const label of labels) {
    const curve = curves.get(label);
    if (curve.finished === 0 || start === null) continue;
    // A series that solved nothing is a line at 0 % (it must not vanish from the plot).
    curve.points = [{ x: start, y: 0 }, ...(curve.points.length ? curve.points : [{ x: Math.max(curve.end, start), y: 0 }])];
    points += curve.points.length - 1;
    rows.push({ series: label, time: 0, percent_solved: 0, finished: curve.finished });
    for (const p of curve.points.slice(1)) rows.push({ series: label, time: p.x, percent_solved: p.y, finished: curve.finished });
    const c = colour(ctx.grouped.series.includes(label) ? ctx.grouped.series.indexOf(label) : labels.indexOf(label));
    // 'before' (Chart.js: along at the old value, then up at the new point): the share holds until the
    // next solve; 'after' would rise at the previous point, a solve early.
    datasets.push({ label: `${label} (${curve.solved} of ${curve.finished})`, data: curve.points, borderColor: c, backgroundColor: c, stepped: 'before', pointRadius: 0, borderWidth: 2 });
  }
  const all = datasets.flatMap((d) => d.data.map((p) => p.x)).filter((v) => v > 0);
  drawChart(
    box,
    {
      type: 'line',
      data: { datasets },
      options: {
        plugins: { tooltip: { callbacks: { label: (c) => `${c.dataset.label}: ${fmtNumber(c.raw.y)}% solved by ${fmtSeconds(c.raw.x)}` } } },
        scales: {
          x: { ...valueAxis('time (s, log scale)', { log: true, fmt: secondsTick }), min: all.length ? Math.min(...all) : undefined, afterBuildTicks: (scale) => (scale.ticks = logTicks(scale.min, scale.max).map((value) => ({ value }))) },
          y: percentAxis('runs solved (% of finished runs)'),
        },
      },
    },
    points,
    'no finished runs for this selection',
    { csv: () => ({ columns: ['series', 'time', 'percent_solved', 'finished'], rows }) },
  );
}

/// Planner Arena: time to solve per series as box plots (solved runs; how many did not is in the label).
export function drawTimeToSolve(box, ctx) {
  const bySeries = new Map();
  for (const cell of ctx.grouped.cells.values()) {
    const key = ctx.split ? cell.series : cell.group;
    if (!bySeries.has(key)) bySeries.set(key, []);
    bySeries.get(key).push(...cell.runs);
  }
  const labels = [...bySeries.keys()].sort();
  const rows = [];
  let points = 0;
  const finished = labels.map((label) => bySeries.get(label).filter(isFinished)); // not the runs a batch skipped
  const values = labels.map((label, i) => {
    const runs = finished[i];
    const v = runs.filter((r) => r.status === 'solved' && r.total_time > 0).map((r) => r.total_time);
    points += v.length;
    rows.push({ series: label, runs: runs.length, solved: v.length, ...summary(v), values: undefined });
    return v;
  });
  const colours = labels.map((l, i) => colour(ctx.grouped.series.includes(l) ? ctx.grouped.series.indexOf(l) : i));
  drawChart(
    box,
    {
      type: 'boxplot',
      data: {
        labels: labels.map((l, i) => `${l} (${values[i].length}/${finished[i].length})`),
        datasets: [{ label: 'time to solve', data: values, backgroundColor: colours.map((c) => `${c}55`), borderColor: colours, borderWidth: 1.5, outlierBackgroundColor: colours, outlierRadius: 3, itemRadius: 2, itemStyle: 'circle', itemBackgroundColor: colours, coef: 1.5 }],
      },
      options: {
        indexAxis: 'x',
        plugins: { legend: { display: false } },
        scales: { x: { title: axisTitle('series (solved / runs)') }, y: valueAxis('time to solve (s, log scale)', { log: true, fmt: secondsTick }) },
      },
    },
    points,
    'no solved runs for this selection',
    { csv: () => ({ columns: ['series', 'runs', 'solved', 'n', 'median', 'q1', 'q3', 'min', 'max'], rows }) },
  );
}

