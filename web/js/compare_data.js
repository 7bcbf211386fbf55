// The numbers behind the Compare page, computed in the browser from the runs table (/api/runs): runs
// grouped into series (planner configuration, planner, or configuration with its settings; one
// series per value of a second parameter) and x values (a scenario parameter), with quantiles per
// group; per-scene ratios of one configuration to another; and Planner Arena's fraction of runs
// solved against time, where runs that did not solve stay in the denominator (censored at their end).
import { api, query } from './api.js';

const PAGE = 5000;
const MAX_RUNS = 50000; // beyond this the browser would hold too much; the page says so

// Sums of phases the paper's time figure plots (construction, query, conflict resolution).
export const DERIVED_METRICS = [
  { name: 'time_construction', label: 'construction (task + motion) (s)', group: 'time', parts: ['time_task_construction', 'time_motion_construction'] },
  { name: 'time_query', label: 'query (task + motion) (s)', group: 'time', parts: ['time_task_query', 'time_motion_query'] },
  { name: 'time_conflicts', label: 'conflict detection and resolution (s)', group: 'time', parts: ['time_task_conflict_detection', 'time_conflict_resolution'] },
];

/// Runs of a family (and an optional filter), every column; resolves {runs, truncated, skipped}. With
/// a batch, the runs its axis stop rule skipped come too, as runs with status 'skipped' and no
/// uuid (skippedRuns), so that the success figure marks those sizes; `skipped` counts them.
export async function fetchRuns(family, filter, batch) {
  const clauses = [`family = "${family.replace(/"/g, '')}"`];
  if (batch) clauses.push(`batch = "${batch.replace(/"/g, '')}"`);
  const q = filter ? `${clauses.join(' and ')} and (${filter})` : clauses.join(' and ');
  const runs = [];
  let total = 0;
  for (let offset = 0; offset < MAX_RUNS; offset += PAGE) {
    const page = await api.get(`/api/runs${query({ q, sort: 'id', order: 'asc', limit: PAGE, offset })}`);
    total = page.total;
    runs.push(...page.runs);
    if (runs.length >= total || page.runs.length === 0) break;
  }
  for (const r of runs) {
    for (const m of DERIVED_METRICS) {
      const values = m.parts.map((p) => r[p]).filter((v) => typeof v === 'number');
      r[m.name] = values.length ? values.reduce((a, b) => a + b, 0) : null;
    }
  }
  labelSettings(runs);
  let skipped = [];
  if (batch) {
    try {
      const b = await api.get(`/api/batches/${encodeURIComponent(batch)}`);
      skipped = skippedRuns(b.runs || [], family, runs, Boolean(filter));
    } catch {
      skipped = []; // a batch name without a stored run list (an imported file): no skips to show
    }
  }
  return { runs: runs.concat(skipped), truncated: runs.length < total, skipped: skipped.length };
}

/// The runs of a batch's run list (GET /api/batches/ID) that the axis stop rule skipped, as rows like
/// /api/runs's (family, parameters as columns, seed, planner, config; status 'skipped'), for `family`.
/// Only those of a line the fetched runs show: the same configuration with the same parameters but
/// the stop axis; with a filter, also a size some fetched run has (the filter cannot be applied to
/// runs that never ran). Their series label and settings (so their profile) are those of their
/// configuration's runs.
export function skippedRuns(batchRuns, family, fetched, filtered) {
  const paramsKey = (r, names, except) => names.filter((n) => n !== except).map((n) => `${n}=${r[n]}`).join(' ');
  // Per (parameter names, stop axis): the fetched runs' lines (configuration + the other parameters,
  // to one of their runs) and sizes, built once (batches of thousands of runs).
  const indexes = new Map();
  const indexOf = (names, axis) => {
    const key = `${names.join(',')}|${axis}`;
    if (!indexes.has(key)) {
      const lines = new Map();
      const sizes = new Set();
      for (const r of fetched) {
        const line = `${r.config || r.planner}\u0000${paramsKey(r, names, axis)}`;
        if (!lines.has(line)) lines.set(line, r);
        sizes.add(paramsKey(r, names, null));
      }
      indexes.set(key, { lines, sizes });
    }
    return indexes.get(key);
  };
  const out = [];
  for (const b of batchRuns) {
    if (b.status !== 'skipped' || b.family !== family || !b.params || typeof b.params !== 'object') continue;
    const names = Object.keys(b.params);
    const row = { uuid: null, family: b.family, seed: b.seed, planner: b.planner, config: b.config, status: 'skipped', skipped: b.skipped, ...b.params };
    const { lines, sizes } = indexOf(names, b.stop_axis);
    const line = `${b.config}\u0000${paramsKey(row, names, b.stop_axis)}`;
    if (!lines.has(line)) continue;
    if (filtered && !sizes.has(paramsKey(row, names, null))) continue;
    row.settings_label = lines.get(line).settings_label;
    row.settings = lines.get(line).settings; // its profile, for its series name
    out.push(row);
  }
  return out;
}

/// Type-7 quantile (R's default, numpy's linear) of sorted values.
export function quantile(sorted, p) {
  if (sorted.length === 0) return null;
  const h = (sorted.length - 1) * p;
  const lo = Math.floor(h);
  const hi = Math.ceil(h);
  return sorted[lo] + (h - lo) * (sorted[hi] - sorted[lo]);
}

export function summary(values) {
  const v = values.filter((x) => typeof x === 'number' && Number.isFinite(x)).sort((a, b) => a - b);
  return { n: v.length, values: v, median: quantile(v, 0.5), q1: quantile(v, 0.25), q3: quantile(v, 0.75), min: v[0] ?? null, max: v[v.length - 1] ?? null };
}

const FINISHED = new Set(['solved', 'timeout', 'infeasible', 'crashed', 'memory', 'error', 'out_of_memory']);
export function isFinished(run) {
  return run.status !== 'running' && run.status !== 'queued' && run.status !== 'cancelled' && run.status !== 'skipped' && (FINISHED.has(run.status) || run.end_time);
}

/// The series a run belongs to. Grouped by "configuration and its settings", a run's label is the
/// one labelSettings gave it (its configuration and the parameters that differ within it), or, for
/// a run not labelled, its configuration and its settings as given.
export function groupKey(run, groupBy) {
  if (groupBy === 'planner') return run.planner;
  if (groupBy === 'settings') {
    if (typeof run.settings_label === 'string') return run.settings_label;
    const given = settingsText(Object.fromEntries(Object.entries(parseSettings(run.settings)).filter(([k, v]) => k !== 'parameters' && (v === null || typeof v !== 'object'))));
    return given ? `${run.config} ${given}` : run.config;
  }
  return seriesName(run.config || run.planner, run.settings);
}

/// A configuration's series name: its label, followed by the profile its runs ran under (`--profile`,
/// recorded in the run's settings) unless the label already names it: `lazy-dash (default)`,
/// `dash-paper`. So the two profiles of one planner are two series, and each says which it is.
/// `dashbench report --figures` names series by the same rule (server/figures/figure_data.cpp).
export function seriesName(config, settings) {
  const profile = parseSettings(settings).profile;
  if (typeof profile !== 'string' || profile === '') return config;
  return String(config).split(/[^A-Za-z0-9_]+/).includes(profile) ? config : `${config} (${profile})`;
}

function parseSettings(text) {
  if (text && typeof text === 'object') return text;
  try {
    const v = JSON.parse(text || '{}');
    return v && typeof v === 'object' && !Array.isArray(v) ? v : {};
  } catch {
    return {};
  }
}

function settingsText(obj) {
  return Object.keys(obj)
    .sort()
    .map((k) => `${k}=${obj[k] !== null && typeof obj[k] === 'object' ? JSON.stringify(obj[k]) : obj[k]}`)
    .join(' ');
}

/// A run's settings as one flat object: its effective parameters (`parameters`, which batch runs
/// store) overlaid with the settings as given.
export function flatSettings(settings) {
  const s = parseSettings(settings);
  const p = s.parameters && typeof s.parameters === 'object' && !Array.isArray(s.parameters) ? s.parameters : {};
  const out = { ...p };
  for (const [k, v] of Object.entries(s)) if (k !== 'parameters') out[k] = v;
  return out;
}

/// Sets run.settings_label on every run: its configuration followed by the settings whose values
/// differ among that configuration's runs (a sweep reads `lazy-dash clearance=0.005`); a
/// configuration that ran with one set of settings is labelled by its name alone.
export function labelSettings(runs) {
  const byConfig = new Map();
  for (const r of runs) {
    const config = r.config || r.planner;
    if (!byConfig.has(config)) byConfig.set(config, new Map());
    const distinct = byConfig.get(config);
    const raw = typeof r.settings === 'string' ? r.settings : JSON.stringify(r.settings ?? {});
    if (!distinct.has(raw)) distinct.set(raw, flatSettings(raw));
  }
  const labels = new Map();
  for (const [config, distinct] of byConfig) {
    const flats = [...distinct.values()];
    const keys = [...new Set(flats.flatMap((f) => Object.keys(f)))];
    const differing = keys.filter((k) => new Set(flats.map((f) => JSON.stringify(f[k]))).size > 1);
    for (const [raw, flat] of distinct) {
      const shown = Object.fromEntries(differing.filter((k) => k !== 'profile' && flat[k] !== undefined).map((k) => [k, flat[k]]));
      const text = settingsText(shown);
      const name = seriesName(config, raw);
      labels.set(`${config}\u0000${raw}`, text ? `${name} ${text}` : name);
    }
  }
  for (const r of runs) {
    const raw = typeof r.settings === 'string' ? r.settings : JSON.stringify(r.settings ?? {});
    r.settings_label = labels.get(`${r.config || r.planner}\u0000${raw}`);
  }
  return runs;
}

/// The x axis the runs call for, picked as `dashbench report --figures` picks it
/// (server/figures/figure_data.cpp): objects when they take more than one value, else the parameter
/// with the most distinct values (the first by name on a tie); null without runs. A batch that
/// varies robots opens on robots, not on a column of points at one object count.
export function defaultAxis(runs, params) {
  const distinct = (p) => new Set(runs.map((r) => r[p]).filter((v) => typeof v === 'number')).size;
  if (params.includes('objects') && distinct('objects') > 1) return 'objects';
  let best = null;
  let most = 0;
  for (const p of [...params].sort()) {
    const n = distinct(p);
    if (n > most) {
      best = p;
      most = n;
    }
  }
  return best;
}

/// Scenario parameters that some run of the list has (the family's parameters).
export function parametersOf(runs, columns) {
  return columns.filter((c) => c.group === 'param' && runs.some((r) => r[c.name] !== null && r[c.name] !== undefined)).map((c) => c.name);
}

/// {series: [label], xs: [values], cells: Map("label|x" -> {runs, solved, finished})} of the runs.
export function groupRuns(runs, { x, split, groupBy }) {
  const cells = new Map();
  const series = new Set();
  const xs = new Set();
  for (const r of runs) {
    const xv = r[x];
    if (typeof xv !== 'number') continue;
    const label = split && r[split] !== null && r[split] !== undefined ? `${groupKey(r, groupBy)} · ${split}=${r[split]}` : groupKey(r, groupBy);
    series.add(label);
    xs.add(xv);
    const key = `${label}|${xv}`;
    if (!cells.has(key)) cells.set(key, { series: label, x: xv, group: groupKey(r, groupBy), splitValue: split ? r[split] : null, runs: [] });
    cells.get(key).runs.push(r);
  }
  return { series: [...series].sort((a, b) => a.localeCompare(b, 'en', { numeric: true })), xs: [...xs].sort((a, b) => a - b), cells };
}

/// Values of `metric` in a cell: solved runs only unless includeUnsolved.
export function cellValues(cell, metric, includeUnsolved) {
  return cell.runs.filter((r) => includeUnsolved || r.status === 'solved').map((r) => r[metric]);
}

export function successOf(cell) {
  const finished = cell.runs.filter(isFinished);
  const solved = finished.filter((r) => r.status === 'solved').length;
  const skipped = cell.runs.filter((r) => r.status === 'skipped').length;
  return { finished: finished.length, solved, skipped, rate: finished.length ? solved / finished.length : null };
}

/// The scene a run planned: family, parameters and seed (the same scene for every planner).
export function sceneKey(run, params) {
  return [run.family, ...params.map((p) => `${p}=${run[p]}`), `seed=${run.seed}`].join(' ');
}

/// Per scene where both configurations have a value of `metric`: {scene, x, split, a, b, ratio}.
export function ratios(runs, { metric, numerator, denominator, x, split, groupBy, params, includeUnsolved }) {
  const byScene = new Map();
  for (const r of runs) {
    if (!includeUnsolved && r.status !== 'solved') continue;
    if (typeof r[metric] !== 'number' || r[metric] <= 0) continue;
    const g = groupKey(r, groupBy);
    if (g !== numerator && g !== denominator) continue;
    const key = sceneKey(r, params);
    if (!byScene.has(key)) byScene.set(key, { scene: key, x: r[x], split: split ? r[split] : null, uuids: [] });
    const s = byScene.get(key);
    s[g === numerator ? 'a' : 'b'] = r[metric];
    s.uuids.push(r.uuid);
  }
  return [...byScene.values()].filter((s) => typeof s.a === 'number' && typeof s.b === 'number' && typeof s.x === 'number').map((s) => ({ ...s, ratio: s.a / s.b }));
}

/// Per scene (family, parameters, seed) where both configurations have a finished run: {scene, x,
/// split, a, b} with the numerator's and the denominator's run (the first finished one of each, by
/// id). Unsolved runs stay in: the paired statistics (paired_stats.js) censor them.
export function scenePairs(runs, { numerator, denominator, x, split, groupBy, params }) {
  const byScene = new Map();
  for (const r of runs) {
    if (!isFinished(r)) continue;
    const g = groupKey(r, groupBy);
    const side = g === numerator ? 'a' : g === denominator ? 'b' : null;
    if (!side || numerator === denominator) continue;
    const key = sceneKey(r, params);
    if (!byScene.has(key)) byScene.set(key, { scene: key, x: r[x], split: split ? r[split] : null });
    const s = byScene.get(key);
    if (!s[side] || r.id < s[side].id) s[side] = r;
  }
  return [...byScene.values()].filter((s) => s.a && s.b);
}

/// Planner Arena's "fraction of runs solved against time": for each series, the share of its finished
/// runs solved by time t. Runs that did not solve never count as solved, but stay in the denominator
/// (right-censored at their end), so a planner that times out often ends below 100 %.
export function solvedCurve(runs) {
  const finished = runs.filter(isFinished);
  const times = finished.filter((r) => r.status === 'solved' && typeof r.total_time === 'number').map((r) => r.total_time).sort((a, b) => a - b);
  const n = finished.length;
  const points = times.map((t, i) => ({ x: t, y: (100 * (i + 1)) / n }));
  const limits = finished.map((r) => r.time_limit).filter((v) => typeof v === 'number');
  const end = limits.length ? Math.max(...limits) : times[times.length - 1];
  if (points.length && end > points[points.length - 1].x) points.push({ x: end, y: points[points.length - 1].y });
  return { points, finished: n, solved: times.length, censored: n - times.length, end };
}
