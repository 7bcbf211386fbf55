// "Dispatch this plan" on the Run detail page: the pre-flight checks of this run's plan against the
// controllers connected now (on request, and again whenever the time scale changes after a check;
// nothing is sent to the arms), their result check by check, and a Dispatch button that is enabled
// only while the result shown passed for the options shown. The server checks again before anything moves (POST
// /api/dispatch with {"run_id"}); the live view and Abort are on the Dispatch page. Below it, the
// recorded dispatches of this plan: planned against executed makespan, timed or by dependencies.
import { api } from '../api.js';
import { el, clear, fmtNumber, fmtSeconds, errorBox, table } from '../dom.js';

const USER_KEY = 'dashbench.dispatch.user'; // shared with the Dispatch page

const HISTORY_LIMIT = 200;

/// Two bars per recorded dispatch of this run: the planned makespan (at its time scale) and the time
/// it took, on one scale.
function makespanPlot(dispatches) {
  const longest = Math.max(...dispatches.map((d) => Math.max(d.duration, d.elapsed)), 1e-9);
  const bar = (value, cls, label) =>
    el('div', { class: 'toolbar', style: 'margin:0' }, el('div', { class: 'progress', style: 'width:320px' }, el('div', { class: cls, style: `width:${((100 * value) / longest).toFixed(1)}%` })), el('span', { text: label }));
  const rows = dispatches.map((d) =>
    el(
      'tr',
      { 'data-dispatch': d.id, 'data-execution': d.execution, 'data-planned': d.duration.toFixed(3), 'data-executed': d.elapsed.toFixed(3) },
      el('td', { text: `${d.created.replace('T', ' ').replace('Z', '')} ${d.execution === 'tpg' ? 'by dependencies' : 'timed'} (${d.state})` }),
      el('td', {}, bar(d.duration, 'solved', `planned ${fmtSeconds(d.duration)} (time scale ${fmtNumber(d.time_scale)})`), bar(d.elapsed, d.state === 'succeeded' ? 'running' : 'failed', `executed ${fmtSeconds(d.elapsed)}${d.duration > 0 ? ` (${fmtNumber(d.elapsed / d.duration)} ×)` : ''}`)),
    ),
  );
  return el('table', { class: 'data' }, el('tbody', {}, rows));
}

async function loadMakespans(box, runId) {
  try {
    const h = await api.get(`/api/dispatches?limit=${HISTORY_LIMIT}`);
    const mine = h.dispatches.filter((d) => d.run_id === runId && d.started);
    clear(box);
    if (mine.length === 0) return;
    box.append(el('h3', { text: 'Planned and executed makespan' }), el('div', { class: 'muted', text: `This plan's dispatches among the last ${HISTORY_LIMIT} recorded, newest first. Executed: from the common start to the last arm's end.` }), makespanPlot(mine));
  } catch {
    clear(box); // the history needs the token and a recording server; the panel works without it
  }
}

function checksTable(report) {
  return table(['name', 'robot', 'passed', 'message'], report.checks || [], {
    cell: (c, v) => (c === 'passed' ? (v ? '✓' : '✗') : v),
  });
}

/// Mounts the panel for run `runId` into `slot` (the run page's place for it).
export function mountRunDispatch(slot, runId) {
  const scale = el('input', { type: 'number', value: 1, min: 0.1, step: 0.1, style: 'width:5em', 'data-testid': 'run-dispatch-scale' });
  const execution = el('select', { 'data-testid': 'run-dispatch-execution' }, el('option', { value: 'timed', text: 'timed' }), el('option', { value: 'tpg', text: 'by dependencies (tpg)' }));
  const user = el('input', { type: 'text', size: 12, placeholder: 'your name', value: localStorage.getItem(USER_KEY) || '', 'data-testid': 'run-dispatch-user' });
  const recheck = el('button', { type: 'button', class: 'secondary', 'data-testid': 'run-dispatch-check' }, 'Pre-flight check');
  const go = el('button', { type: 'button', disabled: true, 'data-testid': 'run-dispatch-start' }, 'Dispatch this plan');
  const result = el('div', { 'data-testid': 'run-dispatch-preflight' });
  const message = el('div', { 'data-testid': 'run-dispatch-message' });
  const makespans = el('div', { 'data-testid': 'run-dispatch-makespans' });
  const panel = el(
    'div',
    { class: 'panel', 'data-testid': 'run-dispatch' },
    el('h2', { text: 'Dispatch this plan' }),
    el('div', { class: 'muted', text: 'Pre-flight: every arm of the plan connected, ready and at its start, speeds within limits at this time scale, the plan valid. Nothing moves until you press Dispatch; watch and abort on the Dispatch page.' }),
    el('div', { class: 'toolbar' }, el('label', {}, 'time scale', scale), el('label', {}, 'execution', execution), el('label', {}, 'who', user), recheck, go, el('a', { href: '#/dispatch', text: 'Dispatch page' })),
    result,
    message,
    makespans,
  );
  slot.replaceChildren(panel);
  loadMakespans(makespans, runId);

  let passedFor = ''; // the options the result shown passed for
  let sequence = 0;   // answers to older checks are dropped
  const options = () => ({ time_scale: Number(scale.value) || 1, execution: execution.value });

  async function check() {
    const mine = ++sequence;
    const opts = options();
    go.disabled = true;
    passedFor = '';
    clear(message);
    clear(result).append(el('div', { class: 'muted', text: 'Checking…' }));
    delete result.dataset.passed;
    try {
      const report = await api.post('/api/dispatch/preflight', { run_id: runId, options: opts });
      if (mine !== sequence) return;
      result.dataset.passed = report.passed ? '1' : '0';
      clear(result).append(
        el('div', { class: report.passed ? 'ok' : 'error', text: report.passed ? 'Pre-flight checks passed.' : `Pre-flight refused: ${report.reason}` }),
        checksTable(report),
      );
      if (report.passed) {
        passedFor = JSON.stringify(opts);
        go.disabled = false;
      }
    } catch (e) {
      if (mine !== sequence) return;
      clear(result);
      const why = e.status === 404 ? 'this run has no stored plan, or this server cannot dispatch' : e.message + (e.body && e.body.reason ? `: ${e.body.reason}` : '');
      message.append(errorBox(why));
    }
  }

  go.addEventListener('click', async () => {
    const opts = options();
    if (JSON.stringify(opts) !== passedFor) {
      check();
      return;
    }
    go.disabled = true;
    clear(message);
    const label = user.value.trim();
    localStorage.setItem(USER_KEY, label);
    try {
      const r = await api.post('/api/dispatch', { run_id: runId, options: opts, user: label || undefined });
      message.append(
        el('div', { class: 'ok', 'data-testid': 'run-dispatch-started' }, `dispatch ${r.dispatch_id} started; arms move in ${fmtNumber(r.start_in)} s. `, el('a', { href: '#/dispatch', text: 'Watch it' })),
      );
    } catch (e) {
      message.append(errorBox(e.message + (e.body && e.body.reason ? `: ${e.body.reason}` : '')));
      if (e.body && e.body.preflight) {
        result.dataset.passed = e.body.preflight.passed ? '1' : '0';
        clear(result).append(checksTable(e.body.preflight));
      }
    }
  });
  recheck.addEventListener('click', check);
  execution.addEventListener('change', () => {
    if (result.dataset.passed !== undefined) check();
  });
  scale.addEventListener('change', () => {
    if (result.dataset.passed !== undefined) check(); // keep the result shown true to the options shown
  });
  return panel;
}
