// A run's timeline plots, for one run or several overlaid: representation sizes over time (stepped,
// log scale) and the constraints and task space expansions as marks on rows by kind. One run: colour
// tells the layers (and the kinds) apart. Several: colour is the run, line dash the layer, and each
// run's marks sit side by side within the kind's row.
import { drawChart, valueAxis, axisTitle } from './charts.js';
import { fmtNumber, fmtSeconds } from './dom.js';
import { LAYER_STYLES, OKABE_ITO, colour } from './palette.js';

export const LAYERS = ['task', 'task_extended', 'motion', 'motion_extended'];
const LAYER_COLOURS = { task: '#0072B2', task_extended: '#56B4E9', motion: '#D55E00', motion_extended: '#E69F00' };
export const MARK_ROWS = ['frontier', 'history', 'motion', 'interaction', 'task space expansion'];
const ROW_SPREAD = 0.5; // of a row's height, shared by the overlaid runs' marks

/// entries: [{uuid, progress: {columns, rows}, end}]; the first is the run of the page.
export function drawSizesOverTime(box, entries) {
  const overlay = entries.length > 1;
  const datasets = [];
  const rows = [];
  let end = 0;
  entries.forEach((entry, k) => {
    const cols = entry.progress.columns;
    const ti = cols.indexOf('t');
    end = Math.max(end, entry.end || 0);
    for (const l of LAYERS) {
      const i = cols.indexOf(`${l}_vertices`);
      const data = entry.progress.rows.filter((row) => row[i] > 0).map((row) => ({ x: row[ti], y: row[i] }));
      if (!data.length) continue;
      for (const d of data) rows.push({ run: entry.uuid, layer: LAYER_STYLES[l].label, t: d.x, vertices: d.y });
      end = Math.max(end, data[data.length - 1].x);
      const c = overlay ? colour(k) : LAYER_COLOURS[l];
      datasets.push({
        label: overlay ? `${entry.uuid.slice(0, 8)} ${LAYER_STYLES[l].label}` : `${LAYER_STYLES[l].label} vertices`,
        data,
        borderColor: c,
        backgroundColor: c,
        borderDash: overlay ? [[], [2, 3], [7, 4], [10, 3, 2, 3]][LAYERS.indexOf(l)] : LAYER_STYLES[l].dash,
        pointStyle: LAYER_STYLES[l].point,
        pointRadius: data.length > 60 ? 0 : 2,
        borderWidth: 2,
        stepped: 'before',
      });
    }
  });
  drawChart(
    box,
    {
      type: 'line',
      data: { datasets },
      options: {
        plugins: { tooltip: { callbacks: { label: (c) => `${c.dataset.label}: ${fmtNumber(c.raw.y)} at ${fmtSeconds(c.raw.x)}` } } },
        scales: {
          x: { type: 'linear', min: 0, max: end > 0 ? end : undefined, title: axisTitle('time since the run started (s)') },
          y: valueAxis('vertices (count, log scale)', { log: true }),
        },
      },
    },
    rows.length,
    'no progress snapshots stored for this run',
    { csv: () => ({ columns: ['run', 'layer', 't', 'vertices'], rows }) },
  );
}

/// entries: [{uuid, timeline, end}]: constraint and expansion marks on rows by kind; x spans the runs.
export function drawMarks(box, entries) {
  const overlay = entries.length > 1;
  const datasets = [];
  const rows = [];
  let end = 0;
  entries.forEach((entry, k) => {
    const tl = entry.timeline;
    end = Math.max(end, entry.end || 0);
    const offset = overlay ? (k / Math.max(1, entries.length - 1) - 0.5) * ROW_SPREAD : 0;
    const marks = [];
    for (const c of tl.constraints) marks.push({ x: c.t, row: MARK_ROWS.indexOf(c.kind), what: `${c.kind} constraint ${c.action}: ${c.content || ''}`, cause: c.conflict });
    for (const e of tl.expansions) marks.push({ x: e.t, row: 4, what: `expansion of ${e.object_label}: ${e.added || ''}`, cause: e.reason });
    for (const m of marks) {
      m.y = m.row + offset;
      end = Math.max(end, m.x);
      rows.push({ run: entry.uuid, kind: MARK_ROWS[m.row], t: m.x, what: m.what, cause: m.cause || '' });
    }
    if (overlay) {
      if (marks.length) {
        datasets.push({ label: entry.uuid.slice(0, 8), data: marks, backgroundColor: colour(k), borderColor: colour(k), pointStyle: k % 2 ? 'triangle' : 'circle', pointRadius: 4 });
      }
      return;
    }
    MARK_ROWS.forEach((row, r) => {
      const data = marks.filter((m) => m.row === r);
      if (data.length) datasets.push({ label: row, data, backgroundColor: OKABE_ITO[r], borderColor: OKABE_ITO[r], pointStyle: r === 4 ? 'triangle' : 'circle', pointRadius: 5 });
    });
  });
  drawChart(
    box,
    {
      type: 'scatter',
      data: { datasets },
      options: {
        plugins: {
          tooltip: {
            callbacks: {
              label: (c) => [`t = ${fmtSeconds(c.raw.x)}: ${c.raw.what}`.slice(0, 160), c.raw.cause ? `caused by: ${c.raw.cause}`.slice(0, 160) : ''].filter(Boolean),
            },
          },
        },
        scales: {
          x: { type: 'linear', min: 0, max: end > 0 ? end : undefined, title: axisTitle('time since the run started (s)') },
          y: {
            type: 'linear',
            min: -0.6,
            max: MARK_ROWS.length - 0.4,
            reverse: true,
            title: axisTitle('kind'),
            afterBuildTicks: (scale) => {
              scale.ticks = MARK_ROWS.map((_, value) => ({ value }));
            },
            ticks: { autoSkip: false, callback: (v) => MARK_ROWS[v] || '' },
          },
        },
      },
    },
    rows.length,
    'no constraints and no task space expansions in this run',
    { csv: () => ({ columns: ['run', 'kind', 't', 'what', 'cause'], rows }) },
  );
}
