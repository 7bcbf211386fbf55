// Launch: build a batch spec (family, parameter grid, planners, seeds, limits), see how many runs it
// makes and any validation error next to its field before submitting, and watch every batch's
// progress live (cancel, resume).
import { api, ApiError, getToken } from '../api.js';
import { on, debounce } from '../events.js';
import { el, clear, badge, fmtSeconds, fmtWork, errorBox, plural } from '../dom.js';
import { writeState } from '../url_state.js';
import { steadyEta } from '../batch_eta.js';
import { plannerRow, isAutoLabel } from './launch_planners.js';
import { PHASE_LABELS } from '../palette.js';

const MAX_SPEC_URL_CHARS = 4000;

/// "4, 8, 16" or "2..8" or "2..16:2" -> [numbers]; throws Error with a message for people.
export function parseValues(text) {
  const out = [];
  for (const part of text.split(',').map((s) => s.trim()).filter(Boolean)) {
    const m = part.match(/^(-?\d+)\s*\.\.\s*(-?\d+)(?:\s*:\s*(\d+))?$/);
    if (m) {
      const [a, b, step] = [Number(m[1]), Number(m[2]), Number(m[3] || 1)];
      if (step < 1 || b < a) throw new Error(`"${part}": a range is FROM..TO[:STEP] with FROM <= TO`);
      if ((b - a) / step > 1000) throw new Error(`"${part}": too many values`);
      for (let v = a; v <= b; v += step) out.push(v);
    } else if (/^-?\d+$/.test(part)) {
      out.push(Number(part));
    } else {
      throw new Error(`"${part}" is not an integer or a range like 2..8`);
    }
  }
  if (out.length === 0) throw new Error('give at least one value');
  return out;
}

function progressBar(p, id) {
  const total = Math.max(1, p.total || 0);
  const pct = (n) => `${(100 * (n || 0)) / total}%`;
  const solvedW = pct(p.solved);
  const failedW = pct(p.failed);
  const bar = el(
    'div',
    { class: 'progress', role: 'progressbar', 'aria-valuemin': 0, 'aria-valuemax': p.total, 'aria-valuenow': p.done },
    el('div', { class: 'solved', style: `width:${solvedW}` }),
    el('div', { class: 'failed', style: `left:${solvedW};width:${failedW}` }),
    el('div', { class: 'running', style: `left:calc(${solvedW} + ${failedW});width:${pct(p.running)}` }),
  );
  const parts = [`${p.done}/${p.total} done`, `${p.solved} solved`];
  if (p.failed) parts.push(`${p.failed} failed`);
  if (p.cancelled) parts.push(`${p.cancelled} cancelled`);
  if (p.running) parts.push(`${p.running} running`);
  const eta = steadyEta(id, p); // counts down while a run works (batch_eta.js)
  if (eta !== null && p.remaining > 0) parts.push(`about ${fmtSeconds(eta)} left`);
  // The running runs whose planner reports a long phase's progress (conflict resolution's steps),
  // and any other run working for 5 s or more (a DaSH construction): which run, in which phase, for
  // how long.
  const inPhase = (a) => (a.phase && a.phase !== 'other' ? `${PHASE_LABELS[a.phase] || String(a.phase).replace(/_/g, ' ')}, ` : '');
  const work = (p.active || [])
    .filter((a) => fmtWork(a.work) || a.seconds >= 5)
    .map((a) => el('div', { class: 'progress-label muted', 'data-testid': 'run-work' }, el('a', { href: `#/run/${a.uuid}`, text: a.key }), `: ${fmtWork(a.work) || `${inPhase(a)}running for ${fmtSeconds(a.seconds)}`}`));
  return [bar, el('div', { class: 'progress-label', text: parts.join(' · ') }), ...work];
}

/// The spec from the URL (#/launch?spec=JSON), or null.
function specFromUrl(params) {
  const text = params.get('spec');
  if (!text || text.length > MAX_SPEC_URL_CHARS) return null;
  try {
    const spec = JSON.parse(text);
    return spec && typeof spec === 'object' && Array.isArray(spec.scenarios) ? spec : null;
  } catch {
    return null;
  }
}

const listText = (v) => (Array.isArray(v) ? v.join(', ') : String(v));

export function mount(root, args, params = new URLSearchParams()) {
  const fromUrl = specFromUrl(params);
  const state = { families: [], planners: [], family: null, lastSpec: null };
  const form = el('div', { class: 'panel grow', 'data-testid': 'launch-form' });
  const batchesBox = el('div', { class: 'panel grow', 'data-testid': 'batches' });
  root.append(el('h1', { text: 'Launch a batch' }), el('div', { class: 'row' }, form, batchesBox));

  const nameInput = el('input', { type: 'text', value: 'web', size: 16, 'data-testid': 'batch-name' });
  const familySelect = el('select', { 'data-testid': 'family' });
  const familySummary = el('div', { class: 'muted', 'data-testid': 'family-summary' });
  const paramsBox = el('div', { class: 'row' });
  const plannersBox = el('div', {});
  const seedFrom = el('input', { type: 'number', value: 1, min: 0, style: 'width:6em', 'data-testid': 'seed-from' });
  const seedCount = el('input', { type: 'number', value: 2, min: 1, style: 'width:6em', 'data-testid': 'seed-count' });
  const timeLimit = el('input', { type: 'number', value: 30, min: 1, step: 'any', style: 'width:7em', 'data-testid': 'time-limit' });
  const memoryLimit = el('input', { type: 'number', value: 4096, min: 0, style: 'width:7em' });
  const workers = el('input', { type: 'number', value: 1, min: 1, style: 'width:5em', 'data-testid': 'workers' });
  // Backend: the local runner, or a Slurm job array where the server has sbatch on its PATH
  // (GET /api/batches/backends); the Slurm fields show only then.
  const backendSelect = el('select', { 'data-testid': 'backend' }, el('option', { value: 'local', text: 'local (this machine)' }));
  const partition = el('input', { type: 'text', size: 10, placeholder: 'default', 'data-testid': 'slurm-partition' });
  const account = el('input', { type: 'text', size: 10, placeholder: 'default', 'data-testid': 'slurm-account' });
  const maxParallel = el('input', { type: 'number', value: 0, min: 0, style: 'width:6em', 'data-testid': 'slurm-max-parallel' });
  const slurmBox = el(
    'div',
    { class: 'row', hidden: true, 'data-testid': 'slurm-options' },
    el('label', { class: 'field', dataset: { key: 'partition' } }, el('span', { text: 'partition' }), partition, el('span', { class: 'error-text' })),
    el('label', { class: 'field', dataset: { key: 'account' } }, el('span', { text: 'account' }), account, el('span', { class: 'error-text' })),
    el('label', { class: 'field', dataset: { key: 'max_parallel' } }, el('span', { text: 'array tasks at once (0: no limit)' }), maxParallel, el('span', { class: 'error-text' })),
  );
  const backendField = el('label', { class: 'field', hidden: true, dataset: { key: 'backend' } }, el('span', { text: 'backend' }), backendSelect, el('span', { class: 'error-text' }));
  const workersField = el('label', { class: 'field', dataset: { key: 'workers' } }, el('span', { text: 'runs at once' }), workers, el('span', { class: 'error-text' }));
  backendSelect.addEventListener('change', () => {
    const slurm = backendSelect.value === 'slurm';
    slurmBox.hidden = !slurm;
    workersField.hidden = slurm;
  });
  const runCount = el('div', { 'data-testid': 'run-count', class: 'muted', text: 'runs: …' });
  const formError = el('div', { class: 'error', 'data-testid': 'launch-error' });
  const submit = el('button', { type: 'button', 'data-testid': 'submit' }, 'Launch');
  const submitted = el('div', { class: 'ok', 'data-testid': 'launch-result' });
  const specPreview = el('pre', { class: 'mono', 'data-testid': 'spec-preview', style: 'white-space:pre-wrap;max-height:240px;overflow:auto' });

  const field = (label, input, key) =>
    el('label', { class: 'field', dataset: { key } }, el('span', { text: label }), input, el('span', { class: 'error-text' }));
  form.append(
    el('h2', { text: 'New batch' }),
    el('div', { class: 'row' }, field('name', nameInput, 'name'), field('scenario family', familySelect, 'family')),
    familySummary,
    el('h3', { text: 'Parameter grid' }),
    el('div', { class: 'muted', text: 'Each parameter: one value, a list (4, 8, 16) or a range (2..8 or 2..16:2).' }),
    paramsBox,
    el('h3', { text: 'Planner configurations' }),
    el('div', { class: 'muted', text: 'Each row is one configuration; open its parameters to set any of `dashbench plan --params` (a list of values sweeps).' }),
    plannersBox,
    el('h3', { text: 'Seeds and limits' }),
    el(
      'div',
      { class: 'row' },
      field('first seed', seedFrom, 'seeds'),
      field('seeds', seedCount, 'seeds'),
      field('time limit per run (s)', timeLimit, 'time_limit'),
      field('memory limit per run (MB, 0: none)', memoryLimit, 'memory_limit'),
      workersField,
    ),
    el('div', { class: 'row' }, backendField),
    slurmBox,
    runCount,
    formError,
    el('div', { class: 'toolbar' }, submit, submitted),
    el('details', {}, el('summary', { text: 'spec JSON (what is sent; the same format as experiments/*.json)' }), specPreview),
  );

  const newRow = (entry) => plannerRow(state.planners, entry, changed);
  const addPlanner = el('button', { type: 'button', class: 'small secondary', text: '+ planner configuration' });
  addPlanner.addEventListener('click', () => {
    plannersBox.insertBefore(newRow({ name: state.planners[0]?.name || 'lazy-dash', label: '' }), addPlanner);
    changed();
  });

  function renderParams() {
    clear(paramsBox);
    const fam = state.families.find((f) => f.name === familySelect.value);
    state.family = fam;
    familySummary.textContent = fam ? fam.summary : '';
    for (const p of fam ? fam.params : []) {
      const input = el('input', { type: 'text', value: String(p.default), size: 10, 'data-param': p.name, title: p.meaning });
      input.addEventListener('input', changed);
      paramsBox.append(field(`${p.name} (${p.range}; default ${p.default})`, input, `param:${p.name}`));
    }
  }

  function clearErrors() {
    formError.textContent = '';
    for (const f of form.querySelectorAll('.field')) {
      f.classList.remove('invalid');
      f.querySelector('.error-text').textContent = '';
    }
  }

  function showError(message) {
    // The server names the field ("spec: scenarios[0].params.robots[1]: 40 is out of range 2..64").
    let key = null;
    const pm = message.match(/params\.([A-Za-z0-9_.-]+?)(\[|:)/);
    if (pm) key = `param:${pm[1]}`;
    else if (/seeds/.test(message)) key = 'seeds';
    else if (/time_limit/.test(message)) key = 'time_limit';
    else if (/memory_limit/.test(message)) key = 'memory_limit';
    else if (/^workers/.test(message)) key = 'workers';
    else if (/name/.test(message) && !/planners/.test(message)) key = 'name';
    const target = key ? form.querySelector(`.field[data-key="${CSS.escape(key)}"]`) : null;
    if (target) {
      target.classList.add('invalid');
      target.querySelector('.error-text').textContent = message;
    } else {
      formError.textContent = message;
    }
  }

  function buildSpec() {
    const params = {};
    for (const input of paramsBox.querySelectorAll('input[data-param]')) {
      try {
        const values = parseValues(input.value);
        params[input.dataset.param] = values.length === 1 ? values[0] : values;
      } catch (e) {
        throw Object.assign(new Error(`params.${input.dataset.param}: ${e.message}`), { local: true });
      }
    }
    const planners = [...plannersBox.querySelectorAll('.planner-row')].flatMap((r) => r._get());
    return {
      name: nameInput.value.trim() || 'web',
      description: 'launched from the dashboard',
      time_limit: Number(timeLimit.value),
      memory_limit: Number(memoryLimit.value),
      scenarios: [{ family: familySelect.value, params }],
      planners,
      seeds: { from: Number(seedFrom.value), count: Number(seedCount.value) },
    };
  }

  let validateSeq = 0;
  const validate = debounce(async () => {
    const seq = ++validateSeq;
    clearErrors();
    let spec;
    try {
      spec = buildSpec();
    } catch (e) {
      showError(e.message);
      runCount.textContent = 'runs: —';
      submit.disabled = true;
      return;
    }
    specPreview.textContent = JSON.stringify(spec, null, 2);
    try {
      const r = await api.post('/api/batches/validate', spec, { auth: false });
      if (seq !== validateSeq) return;
      if (!r.valid) {
        runCount.textContent = 'runs: —';
        delete runCount.dataset.runs;
        submit.disabled = true;
        showError(r.error);
        return;
      }
      state.lastSpec = spec;
      writeState({ spec: JSON.stringify(spec).length <= MAX_SPEC_URL_CHARS ? JSON.stringify(spec) : '' });
      if (launching) return;
      runCount.textContent = `runs: ${r.runs} (${plural(r.runs, 'process', 'processes')}, up to ${fmtSeconds(r.runs * r.time_limit)} of planning in total)`;
      runCount.dataset.runs = r.runs;
      submit.disabled = launching;
    } catch (e) {
      if (seq !== validateSeq) return;
      runCount.textContent = 'runs: —';
      delete runCount.dataset.runs;
      submit.disabled = true;
      showError(e.message);
    }
  }, 250);
  function changed() {
    submit.disabled = true;
    validate();
  }
  let launching = false; // one launch at a time: a second click while the first is in flight does nothing
  for (const i of [nameInput, seedFrom, seedCount, timeLimit, memoryLimit]) i.addEventListener('input', changed);
  familySelect.addEventListener('change', () => {
    renderParams();
    changed();
  });

  submit.addEventListener('click', async () => {
    if (launching) return;
    submitted.textContent = '';
    delete submitted.dataset.batch;
    clearErrors();
    if (!getToken()) {
      formError.textContent = 'Launching needs the server token: use the Token button (top right).';
      return;
    }
    submit.disabled = true;
    launching = true;
    try {
      const body =
        backendSelect.value === 'slurm'
          ? {
              spec: buildSpec(),
              backend: 'slurm',
              slurm: { partition: partition.value.trim(), account: account.value.trim(), max_parallel: Number(maxParallel.value) || 0 },
            }
          : { spec: buildSpec(), workers: Number(workers.value) };
      const r = await api.post('/api/batches', body);
      submitted.dataset.batch = r.batch_id;
      submitted.dataset.runs = r.runs;
      showSubmitted(r.batch_id, r.status, null);
      loadBatches();
    } catch (e) {
      showError(e instanceof ApiError ? e.message : String(e));
    } finally {
      launching = false;
      submit.disabled = !state.lastSpec;
    }
  });

  /// The line under Launch follows the batch it launched until that batch ends.
  function showSubmitted(id, status, progress) {
    if (submitted.dataset.batch !== id) return;
    const runs = submitted.dataset.runs;
    const done = progress ? ` · ${progress.done}/${progress.total} done` : '';
    submitted.textContent = `batch ${id} ${status}: ${plural(Number(runs), 'run')}${done}`;
    submitted.dataset.status = status;
  }

  // ---- batches ----
  const rows = new Map(); // batch id -> {progressCell, statusCell}
  async function loadBatches() {
    let list;
    try {
      list = (await api.get('/api/batches')).batches;
    } catch (e) {
      clear(batchesBox).append(el('h2', { text: 'Batches' }), errorBox(e.message));
      return;
    }
    clear(batchesBox);
    rows.clear();
    batchesBox.append(el('h2', { text: 'Batches' }));
    if (list.length === 0) batchesBox.append(el('div', { class: 'muted', text: 'No batches yet.' }));
    const body = el('tbody');
    for (const b of list) {
      const statusCell = el('td', {}, badge(b.status));
      if (b.backend === 'slurm') {
        // Slurm's array task states next to the batch's status: "slurm: 3 completed, 1 running".
        const states = Object.entries(b.slurm || {}).map(([state, n]) => `${n} ${state}`).join(', ');
        statusCell.append(el('div', { class: 'muted', 'data-testid': 'slurm-states', text: `slurm: ${states}` }));
      }
      const progressCell = el('td', {}, progressBar(b.progress, b.id));
      const actions = el('td', {});
      if (b.cancellable) {
        actions.append(
          el('button', { type: 'button', class: 'small danger', 'data-testid': 'cancel', onclick: () => act(b.id, 'cancel') }, 'Cancel'),
        );
      }
      if (b.resumable) {
        actions.append(
          el('button', { type: 'button', class: 'small', 'data-testid': 'resume', onclick: () => act(b.id, 'resume') }, 'Resume'),
        );
      }
      actions.append(
        ' ',
        el('a', { href: `#/runs?q=${encodeURIComponent(`batch = "${b.id}"`)}`, text: 'runs' }),
        ' · ',
        el('a', { href: `#/compare?batch=${encodeURIComponent(b.id)}`, 'data-testid': 'compare-batch', text: 'compare this batch' }),
      );
      body.append(
        el(
          'tr',
          { 'data-batch': b.id, 'data-status': b.status },
          el('td', {}, el('div', { text: b.name }), el('div', { class: 'muted mono', text: b.id })),
          statusCell,
          progressCell,
          actions,
        ),
      );
      rows.set(b.id, { statusCell, progressCell, row: body.lastChild });
    }
    batchesBox.append(
      el('div', { class: 'table-wrap' }, el('table', { class: 'data' }, el('thead', {}, el('tr', {}, ['batch', 'status', 'progress', ''].map((h) => el('th', { text: h })))), body)),
    );
  }
  async function act(id, what) {
    try {
      await api.post(`/api/batches/${encodeURIComponent(id)}/${what}`, {});
    } catch (e) {
      batchesBox.prepend(errorBox(`${what} ${id}: ${e.message}`));
    }
    loadBatches();
  }
  const reload = debounce(loadBatches, 300);
  const offs = [
    on('batch', (m) => {
      if (m.status) showSubmitted(m.id, m.status, m.progress);
      const r = rows.get(m.id);
      if (!r) return reload();
      if (m.progress) clear(r.progressCell).append(...progressBar(m.progress, m.id));
      if (m.status) {
        clear(r.statusCell).append(badge(m.status));
        r.row.dataset.status = m.status;
        if (!['running', 'cancelling', 'queued', 'submitted'].includes(m.status)) {
          for (const b of r.row.querySelectorAll('button')) b.remove();
          reload();
        }
      }
    }),
    on('batches', reload),
    on('resync', reload),
  ];

  (async () => {
    try {
      const { backends } = await api.get('/api/batches/backends');
      if (backends.includes('slurm')) {
        backendSelect.append(el('option', { value: 'slurm', text: 'Slurm (job array)' }));
        backendField.hidden = false;
      }
    } catch {
      // An older server without the route: local only.
    }
  })();
  (async () => {
    try {
      const cat = await api.get('/api/scenarios');
      state.families = cat.families;
      state.planners = cat.planners;
      for (const f of cat.families) familySelect.append(el('option', { value: f.name, text: f.name }));
      familySelect.value = cat.families.some((f) => f.name === 'sorting') ? 'sorting' : cat.families[0]?.name;
      const scenario = fromUrl && fromUrl.scenarios[0];
      if (scenario && cat.families.some((f) => f.name === scenario.family)) familySelect.value = scenario.family;
      renderParams();
      if (fromUrl) {
        // A shared link: the form as the spec in the URL says (what it does not say stays default).
        for (const [k, v] of Object.entries((scenario && scenario.params) || {})) {
          const input = paramsBox.querySelector(`input[data-param="${CSS.escape(k)}"]`);
          if (input) input.value = listText(v);
        }
        if (typeof fromUrl.name === 'string') nameInput.value = fromUrl.name;
        if (Number.isFinite(fromUrl.time_limit)) timeLimit.value = fromUrl.time_limit;
        if (Number.isFinite(fromUrl.memory_limit)) memoryLimit.value = fromUrl.memory_limit;
        if (fromUrl.seeds && Number.isFinite(fromUrl.seeds.from)) seedFrom.value = fromUrl.seeds.from;
        if (fromUrl.seeds && Number.isFinite(fromUrl.seeds.count)) seedCount.value = fromUrl.seeds.count;
      }
      // Every planner entry of a link with every setting it carries; a label that is what the row
      // would call the entry by itself stays automatic (it follows later edits).
      const planners = fromUrl && Array.isArray(fromUrl.planners) && fromUrl.planners.length ? fromUrl.planners.slice(0, 20) : [{ name: 'lazy-dash' }];
      for (const p of planners) {
        const entry = { name: String(p.name), label: typeof p.label === 'string' ? p.label : '', settings: p.settings && typeof p.settings === 'object' ? p.settings : {} };
        if (isAutoLabel(entry, state.planners)) entry.label = '';
        plannersBox.append(newRow(entry));
      }
      plannersBox.append(addPlanner);
      changed();
    } catch (e) {
      form.append(errorBox(e.message));
    }
  })();
  loadBatches();
  return () => offs.forEach((off) => off());
}
