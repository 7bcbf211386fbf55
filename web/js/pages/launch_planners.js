// Launch's planner configurations: one row per configuration with its planner, label, "task only",
// and every named planner parameter (the names of `dashbench plan --params`; left blank, a parameter
// keeps the planner's default), with the paper and default profiles one click away. A parameter
// given a list of values ("0.002, 0.005") is a sweep: the row makes one configuration per value (per
// combination when several parameters have lists), each labelled with its values. A row reads back
// a spec's planner entry (a #/launch?spec= link) with every setting it carries.
import { el, clear } from '../dom.js';

/// The configurations one row may make (a sweep's combinations): a batch of more is a typing slip.
export const MAX_CONFIGS_PER_ROW = 64;
const LABEL_SETTINGS = 3; // settings spelled out in an automatic label; more are counted

/// The JSON value text of a parameter as a spec writes it ("0.005", "true").
const valueText = (v) => String(v);

/// One value of parameter `info` from text; Error with a message for people.
function parseOne(info, text) {
  if (info.type === 'bool') {
    if (text === 'true' || text === 'false') return text === 'true';
    throw new Error(`"${text}" is not true or false`);
  }
  const v = Number(text);
  if (text === '' || !Number.isFinite(v)) throw new Error(`"${text}" is not a number`);
  if (info.type === 'int' && !Number.isInteger(v)) throw new Error(`"${text}" is not an integer`);
  if (v < info.min || v > info.max) throw new Error(`${text} is out of range ${info.min}..${info.max}`);
  return v;
}

/// The values a parameter's field holds: [] (blank: the default), one, or a list (a sweep).
export function parseParamValues(info, text) {
  const parts = String(text).split(',').map((s) => s.trim()).filter(Boolean);
  const values = parts.map((p) => parseOne(info, p));
  if (new Set(values.map(valueText)).size !== values.length) throw new Error('a value is listed twice');
  return values;
}

/// The settings of the paper's algorithm: every extension at its paper value.
export function paperSettings(parameters) {
  return Object.fromEntries(parameters.filter((p) => p.paper !== '').map((p) => [p.name, p.type === 'bool' ? p.paper === 'true' : Number(p.paper)]));
}

/// The label a configuration gets when none is typed: the planner (lazy-task when task only),
/// "-paper" when every extension is at its paper value, then the other settings ("clearance=0.005").
export function autoLabel(name, taskOnly, settings, parameters) {
  const base = taskOnly ? `${name.replace(/-dash$/, '')}-task` : name;
  const paper = paperSettings(parameters);
  const paperKeys = Object.keys(paper);
  const isPaper = paperKeys.length > 0 && paperKeys.every((k) => k in settings && valueText(settings[k]) === valueText(paper[k]));
  const rest = Object.keys(settings).filter((k) => !(isPaper && k in paper));
  const shown = rest.slice(0, LABEL_SETTINGS).map((k) => `${k}=${valueText(settings[k])}`);
  if (rest.length > LABEL_SETTINGS) shown.push(`+${rest.length - LABEL_SETTINGS} settings`);
  return [isPaper ? `${base}-paper` : base, ...shown].join(' ');
}

/// The spec entries of one row: fixed settings plus every combination of the swept ones.
/// row: {name, label ('' for automatic), taskOnly, fixed: {k: v}, swept: [[k, [v...]]], extra: {k: v}}.
export function expandConfigurations(row, parameters) {
  let combos = [{}];
  for (const [k, values] of row.swept) combos = combos.flatMap((c) => values.map((v) => ({ ...c, [k]: v })));
  if (combos.length > MAX_CONFIGS_PER_ROW) throw new Error(`the sweep makes ${combos.length} configurations (at most ${MAX_CONFIGS_PER_ROW} per row)`);
  return combos.map((combo) => {
    const settings = { ...row.extra, ...row.fixed, ...combo };
    if (row.taskOnly) settings.task_only = true;
    const sweptText = Object.entries(combo).map(([k, v]) => `${k}=${valueText(v)}`).join(' ');
    const base = row.label || autoLabel(row.name, row.taskOnly, row.fixed, parameters);
    const entry = { name: row.name, label: sweptText ? `${base} ${sweptText}` : base };
    if (Object.keys(settings).length) entry.settings = settings;
    return entry;
  });
}

/// One parameter's field: bools as a list (default, on, off, both: a sweep), numbers as text.
function paramField(info, value, onChange) {
  const title = `${info.description} (default ${info.default}${info.paper !== '' ? `; paper ${info.paper}` : ''})`;
  let input;
  if (info.type === 'bool') {
    input = el(
      'select',
      { 'data-setting': info.name, title },
      el('option', { value: '', text: `default (${info.default})` }),
      el('option', { value: 'true', text: 'true' }),
      el('option', { value: 'false', text: 'false' }),
      el('option', { value: 'true, false', text: 'both (sweep)' }),
    );
  } else {
    const range = `${info.min}..${info.max}`;
    input = el('input', { type: 'text', size: 9, placeholder: info.default, 'data-setting': info.name, title: `${title}; ${range}` });
  }
  input.value = value;
  // 'input' only: a 'change' on leaving the field would disable Launch under the click that left it.
  input.addEventListener('input', onChange);
  const paper = info.paper !== '' ? `, paper ${info.paper}` : '';
  return el('label', { class: 'field param-field', dataset: { key: `setting:${info.name}` } }, el('span', { text: `${info.name} (${info.default}${paper})` }), input, el('span', { class: 'error-text' }));
}

/// A planner configuration row. planners: /api/scenarios' planners (with "parameters");
/// entry: a spec planner entry {name, label, settings}; changed(): called on every edit.
export function plannerRow(planners, entry, changed) {
  const paramsOf = (name) => (planners.find((p) => p.name === name) || { parameters: [] }).parameters || [];
  const name = el('select', { 'data-testid': 'planner-name' }, planners.map((p) => el('option', { value: p.name, text: p.name })));
  name.value = entry.name;
  const settings = entry.settings && typeof entry.settings === 'object' ? entry.settings : {};
  const taskOnly = el('input', { type: 'checkbox', checked: settings.task_only === true, 'data-testid': 'task-only' });
  const label = el('input', { type: 'text', value: entry.label || '', size: 18, placeholder: 'label (automatic)', 'data-testid': 'planner-label' });
  const fieldsBox = el('div', { class: 'param-grid' });
  const summary = el('summary', { 'data-testid': 'planner-params-summary' });
  const paperButton = el('button', { type: 'button', class: 'small secondary', 'data-testid': 'profile-paper', title: 'every extension beyond the published algorithm off (`--profile paper`)' }, 'paper profile');
  const defaultButton = el('button', { type: 'button', class: 'small secondary', 'data-testid': 'profile-default', title: 'every parameter at the planner\'s default' }, 'defaults');
  const remove = el('button', { type: 'button', class: 'small danger', text: 'remove' });
  const details = el(
    'details',
    { class: 'planner-params', 'data-testid': 'planner-params' },
    summary,
    el('div', { class: 'toolbar' }, paperButton, defaultButton, el('span', { class: 'muted', text: 'blank: the default; a list (0.002, 0.005) sweeps: one configuration per value' })),
    fieldsBox,
  );
  const row = el('div', { class: 'planner-row', 'data-testid': 'planner-row' }, el('div', { class: 'toolbar' }, name, el('label', {}, 'label', label), el('label', { title: 'stop after the task layer (no motions)' }, taskOnly, 'task only'), remove), details);

  // Settings the planner does not name (test_fault, or a parameter of another build) are kept as given.
  const extra = {};
  const known = new Set(paramsOf(entry.name).map((p) => p.name));
  for (const [k, v] of Object.entries(settings)) if (k !== 'task_only' && !known.has(k)) extra[k] = v;

  function renderFields(values) {
    clear(fieldsBox).append(...paramsOf(name.value).map((info) => paramField(info, values[info.name] ?? '', onEdit)));
    if (Object.keys(extra).length) fieldsBox.append(el('div', { class: 'muted', 'data-testid': 'extra-settings', text: `kept as given: ${JSON.stringify(extra)}` }));
    updateSummary();
  }
  const fieldValues = () => Object.fromEntries([...fieldsBox.querySelectorAll('[data-setting]')].map((i) => [i.dataset.setting, i.value.trim()]));
  function updateSummary() {
    const set = Object.values(fieldValues()).filter(Boolean).length;
    summary.textContent = `parameters: ${set ? `${set} set` : 'defaults'}`;
    row.dataset.settingsSet = String(set);
  }
  function onEdit() {
    updateSummary();
    changed();
  }
  renderFields(Object.fromEntries(Object.entries(settings).filter(([k]) => known.has(k)).map(([k, v]) => [k, valueText(v)])));
  if (Object.keys(extra).length || Object.keys(settings).some((k) => known.has(k))) details.open = true;

  name.addEventListener('change', () => {
    renderFields(fieldValues()); // values of parameters both planners have are kept
    changed();
  });
  paperButton.addEventListener('click', () => {
    // As `--profile paper --set ...`: every extension at its paper value, budgets and clearance kept.
    const paper = Object.fromEntries(Object.entries(paperSettings(paramsOf(name.value))).map(([k, v]) => [k, valueText(v)]));
    renderFields({ ...fieldValues(), ...paper });
    changed();
  });
  defaultButton.addEventListener('click', () => {
    renderFields({});
    changed();
  });
  for (const i of [label, taskOnly]) i.addEventListener('input', changed);
  remove.addEventListener('click', () => {
    row.remove();
    changed();
  });

  /// The row's spec entries; Error naming the parameter when a field is wrong.
  row._get = () => {
    const fixed = {};
    const swept = [];
    for (const input of fieldsBox.querySelectorAll('[data-setting]')) {
      input.classList.remove('invalid');
      const info = paramsOf(name.value).find((p) => p.name === input.dataset.setting);
      let values;
      try {
        values = parseParamValues(info, input.value);
      } catch (e) {
        input.classList.add('invalid');
        details.open = true;
        throw Object.assign(new Error(`planner ${name.value}: ${info.name}: ${e.message}`), { local: true });
      }
      if (values.length === 1) fixed[info.name] = values[0];
      else if (values.length > 1) swept.push([info.name, values]);
    }
    return expandConfigurations({ name: name.value, label: label.value.trim(), taskOnly: taskOnly.checked, fixed, swept, extra }, paramsOf(name.value));
  };
  return row;
}

/// Whether `label` is what the row would have called `entry` by itself (then it stays automatic).
export function isAutoLabel(entry, planners) {
  const parameters = (planners.find((p) => p.name === entry.name) || { parameters: [] }).parameters || [];
  const settings = { ...(entry.settings || {}) };
  const taskOnly = settings.task_only === true;
  delete settings.task_only;
  return entry.label === autoLabel(entry.name, taskOnly, settings, parameters);
}
