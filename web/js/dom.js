// Small DOM helpers. Text always goes in through textContent: tags, notes and SQL results are data.
export function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (v === undefined || v === null || v === false) continue;
    if (k === 'class') node.className = v;
    else if (k === 'text') node.textContent = v;
    else if (k === 'dataset') Object.assign(node.dataset, v);
    else if (k.startsWith('on') && typeof v === 'function') node.addEventListener(k.slice(2), v);
    else if (k === 'value') node.value = v;
    else if (k === 'checked' || k === 'disabled' || k === 'selected' || k === 'hidden') node[k] = Boolean(v);
    else node.setAttribute(k, v === true ? '' : String(v));
  }
  for (const c of children.flat(Infinity)) {
    if (c === null || c === undefined || c === false) continue;
    node.append(c instanceof Node ? c : document.createTextNode(String(c)));
  }
  return node;
}

export function clear(node) {
  while (node.firstChild) node.removeChild(node.firstChild);
  return node;
}

/// A number for people: integers with thousands separators, others with `digits` significant digits
/// and no trailing zeros ("0.0015", "7.022", never "0.00150" or "7.02200").
export function fmtNumber(v, digits = 3) {
  if (v === null || v === undefined || v === '') return '';
  if (typeof v !== 'number') return String(v);
  if (!Number.isFinite(v)) return String(v);
  if (Number.isInteger(v)) return v.toLocaleString('en-US');
  if (Math.abs(v) >= 10 ** digits) return Math.round(v).toLocaleString('en-US');
  // Thousands separated as for integers ("1,144", not "1144" beside "1,233").
  if (Math.abs(v) >= 1000) return Number(v.toPrecision(digits)).toLocaleString('en-US', { maximumFractionDigits: 20 });
  return trimZeros(v.toPrecision(digits));
}

function trimZeros(text) {
  if (/e/i.test(text)) return text.replace(/\.?0+e/, 'e');
  return text.includes('.') ? text.replace(/\.?0+$/, '') : text;
}

/// A duration for people: "45 µs", "9.8 ms", "12.34 s", "2 min 5 s", "1 h 51 min" (never "6666 min 40 s").
export function fmtSeconds(s) {
  if (s === null || s === undefined) return '';
  if (s < 1e-3) return `${(s * 1e6).toFixed(0)} µs`;
  if (s < 1) return `${(s * 1e3).toFixed(1)} ms`;
  if (s < 120) return `${s.toFixed(2)} s`;
  const whole = Math.round(s);
  if (whole < 3600) return `${Math.floor(whole / 60)} min ${whole % 60} s`;
  const minutes = Math.round(s / 60);
  return `${Math.floor(minutes / 60)} h ${minutes % 60} min`;
}

/// "1 run", "2 runs": a count with its noun (`many` when the plural is not noun + "s").
export function plural(n, one, many = `${one}s`) {
  return `${typeof n === 'number' ? n.toLocaleString('en-US') : n} ${n === 1 ? one : many}`;
}

/// A long phase's progress as the planner reported it (dash_progress's progress_* columns, or a
/// batch's running run): "conflict resolution: steps 37/146 (ur5e_3, ur5e_7) · 4.2 steps/s"; '' when
/// there is none, or its work ended (`current` empty) and `ended` is not asked for.
export function fmtWork(w, { ended = false } = {}) {
  if (!w || w.phase === null || w.phase === undefined || w.total === null || w.total === undefined) return '';
  const running = typeof w.current === 'string' && w.current !== '';
  if (!running && !ended) return '';
  const name = String(w.phase).replace(/_/g, ' ');
  const unit = w.phase === 'conflict_resolution' ? 'steps ' : '';
  const rate = typeof w.rate === 'number' && w.phase === 'conflict_resolution' ? ` · ${w.rate.toFixed(1)} steps/s` : '';
  return `${name}: ${unit}${w.done}/${w.total}${running ? ` (${w.current})` : ''}${rate}`;
}

export function badge(status) {
  return el('span', { class: `badge ${status}`, text: status });
}

/// `k=v k=v` for scenario parameters or planner settings as given. Nested objects are left out: a
/// batch run's settings carry `parameters`, the run's full effective parameter set (see
/// plannerLine, which shows it on request); lists print as `a,b`.
export function paramsText(params) {
  if (!params || typeof params !== 'object') return '';
  return Object.entries(params)
    .filter(([, v]) => v === null || typeof v !== 'object' || Array.isArray(v))
    .map(([k, v]) => `${k}=${Array.isArray(v) ? v.join(',') : v}`)
    .join(' ');
}

/// The effective parameter set a run's settings carry (`settings.parameters`), or null.
export function effectiveParameters(settings) {
  const p = settings && typeof settings === 'object' ? settings.parameters : null;
  return p && typeof p === 'object' && !Array.isArray(p) ? p : null;
}

/// A run's planner line: `planner (config)  settings as given`, and the full effective parameter
/// set (when the run stored it) in a closed <details> beside it, one `name = value` a line.
export function plannerLine(run, settings) {
  const given = paramsText(settings);
  const line = el('span', { 'data-testid': 'planner-line' }, `${run.planner} (${run.config})${given ? `  ${given}` : ''}`);
  const params = effectiveParameters(settings);
  if (!params || !Object.keys(params).length) return line;
  const entries = Object.entries(params).sort(([a], [b]) => a.localeCompare(b));
  const details = el(
    'details',
    { class: 'params-details', 'data-testid': 'planner-parameters' },
    el('summary', { class: 'muted', text: `all ${entries.length} parameters` }),
    el('pre', { class: 'mono', text: entries.map(([k, v]) => `${k} = ${typeof v === 'object' ? JSON.stringify(v) : v}`).join('\n') }),
  );
  return el('span', {}, line, ' ', details);
}

/// A table from column names and row objects; `cell(column, value, row)` may return a Node.
export function table(columns, rows, { cell, header } = {}) {
  const thead = el('thead', {}, el('tr', {}, columns.map((c) => (header ? header(c) : el('th', { text: c })))));
  const tbody = el(
    'tbody',
    {},
    rows.map((r) =>
      el(
        'tr',
        {},
        columns.map((c) => {
          const v = Array.isArray(r) ? r[columns.indexOf(c)] : r[c];
          const content = cell ? cell(c, v, r) : v;
          const numeric = typeof v === 'number';
          return el('td', { class: numeric ? 'num' : '' }, content instanceof Node ? content : fmtCell(content));
        }),
      ),
    ),
  );
  return el('table', { class: 'data' }, thead, tbody);
}

function fmtCell(v) {
  if (v === null || v === undefined) return '';
  if (typeof v === 'number') return fmtNumber(v, 4);
  if (typeof v === 'object') return JSON.stringify(v);
  return String(v);
}

export function errorBox(message) {
  return el('div', { class: 'error', role: 'alert', text: message });
}
