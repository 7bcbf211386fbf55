// A run's timeline plots, for one run or several overlaid: representation sizes over time (stepped,
// log scale; vertices, hyperarcs or both) and the constraints and task space expansions as marks on
// rows by kind. One run: colour tells the layers (and the kinds) apart. Several: colour is the run,
// line dash the layer, and each run's marks sit side by side within the kind's row.
import { drawChart, valueAxis, axisTitle } from './charts.js';
import { fmtNumber, fmtSeconds } from './dom.js';
import { LAYER_STYLES, OKABE_ITO, colour } from './palette.js';

export const LAYERS = ['task', 'task_extended', 'motion', 'motion_extended'];
const LAYER_COLOURS = { task: '#0072B2', task_extended: '#56B4E9', motion: '#D55E00', motion_extended: '#E69F00' };
export const MARK_ROWS = ['frontier', 'history', 'motion', 'interaction', 'task space expansion'];
const ROW_SPREAD = 0.5; // of a row's height, shared by the overlaid runs' marks

export const SIZE_COUNTS = ['both', 'vertices', 'hyperarcs'];
const COUNT_TEXT = { both: 'vertices and hyperarcs', vertices: 'vertices', hyperarcs: 'hyperarcs' };
const COUNT_KEY = 'dashbench.run.sizeCounts'; // the choice is kept in the browser

function savedCount() {
  try {
    const v = localStorage.getItem(COUNT_KEY);
    return SIZE_COUNTS.includes(v) ? v : 'both';
  } catch {
    return 'both';
  }
}

/// The "vertices / hyperarcs / both" choice above the sizes plot (made once per box).
function countControl(box) {
  if (box._countSelect) return box._countSelect;
  const select = document.createElement('select');
  select.dataset.testid = 'sizes-count';
  select.title = 'which counts the plot shows';
  for (const c of SIZE_COUNTS) select.append(new Option(COUNT_TEXT[c], c));
  select.value = savedCount();
  select.addEventListener('change', () => {
    try {
      localStorage.setItem(COUNT_KEY, select.value);
    } catch {
      // private mode: the choice lasts as long as the page
    }
    if (box._sizeEntries) drawSizesOverTime(box, box._sizeEntries);
  });
  const label = document.createElement('label');
  label.className = 'toolbar sizes-count';
  label.append('show ', select);
  box.before(label);
  box._countSelect = select;
  return select;
}

/// entries: [{uuid, progress: {columns, rows}, end}]; the first is the run of the page. Vertices,
/// hyperarcs or both (a control above the plot chooses; DaSH's H_M grows in hyperarcs while its
/// vertices stay flat). One run: colour is the layer, and with both counts vertices are solid lines
/// and hyperarcs dashed with hollow points. Several: colour is the run, dash the layer, and
/// hyperarcs thinner with hollow points. `count` overrides the control.
export function drawSizesOverTime(box, entries, count = null) {
  box._sizeEntries = entries;
  const mode = count || (box.parentElement ? countControl(box).value : savedCount());
  const counts = mode === 'both' ? ['vertices', 'hyperarcs'] : [mode];
  const overlay = entries.length > 1;
  const datasets = [];
  const rows = [];
  let end = 0;
  entries.forEach((entry, k) => {
    const cols = entry.progress.columns;
    const ti = cols.indexOf('t');
    end = Math.max(end, entry.end || 0);
    for (const l of LAYERS) {
      for (const what of counts) {
        const i = cols.indexOf(`${l}_${what}`);
        if (i < 0) continue;
        const data = entry.progress.rows.filter((row) => row[i] > 0).map((row) => ({ x: row[ti], y: row[i] }));
        if (!data.length) continue;
        for (const d of data) rows.push({ run: entry.uuid, layer: LAYER_STYLES[l].label, count: what, t: d.x, value: d.y });
        end = Math.max(end, data[data.length - 1].x);
        const c = overlay ? colour(k) : LAYER_COLOURS[l];
        const arcs = what === 'hyperarcs';
        const both = counts.length > 1;
        let dash = overlay ? [[], [2, 3], [7, 4], [10, 3, 2, 3]][LAYERS.indexOf(l)] : LAYER_STYLES[l].dash;
        if (!overlay && both) dash = arcs ? [6, 3] : [];
        datasets.push({
          label: overlay ? `${entry.uuid.slice(0, 8)} ${LAYER_STYLES[l].label} ${what}` : `${LAYER_STYLES[l].label} ${what}`,
          data,
          borderColor: c,
          backgroundColor: both && arcs ? '#ffffff' : c,
          borderDash: dash,
          pointStyle: LAYER_STYLES[l].point,
          pointRadius: data.length > 60 ? 0 : both && arcs ? 3 : 2,
          borderWidth: overlay && both && arcs ? 1.2 : 2,
          stepped: 'before',
        });
      }
    }
  });
  // Overlaid runs: one legend entry per run (its colour) and per layer (its dash and point), not
  // one per line (runs x layers x counts).
  const legend = overlay
    ? {
        onClick: () => {},
        labels: {
          generateLabels: () => {
            const grey = '#555555';
            const items = entries.map((entry, k) => ({ text: entry.uuid.slice(0, 8), fillStyle: colour(k), strokeStyle: colour(k), lineWidth: 2, pointStyle: 'circle', hidden: false }));
            const present = LAYERS.filter((l) => datasets.some((d) => d.label.includes(` ${LAYER_STYLES[l].label} `)));
            for (const l of present) items.push({ text: LAYER_STYLES[l].label, fillStyle: grey, strokeStyle: grey, lineWidth: 1, lineDash: [[], [2, 3], [7, 4], [10, 3, 2, 3]][LAYERS.indexOf(l)], pointStyle: LAYER_STYLES[l].point, hidden: false });
            if (counts.length > 1) items.push({ text: 'hollow, thin: hyperarcs', fillStyle: '#ffffff', strokeStyle: grey, lineWidth: 1, pointStyle: 'circle', hidden: false });
            return items;
          },
        },
      }
    : {};
  drawChart(
    box,
    {
      type: 'line',
      data: { datasets },
      options: {
        plugins: { legend, tooltip: { callbacks: { label: (c) => `${c.dataset.label}: ${fmtNumber(c.raw.y)} at ${fmtSeconds(c.raw.x)}` } } },
        scales: {
          x: { type: 'linear', min: 0, max: end > 0 ? end : undefined, title: axisTitle('time since the run started (s)') },
          y: valueAxis(`${COUNT_TEXT[mode]} (count, log scale)`, { log: true }),
        },
      },
    },
    rows.length,
    'no progress snapshots stored for this run',
    { csv: () => ({ columns: ['run', 'layer', 'count', 't', 'value'], rows }) },
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
