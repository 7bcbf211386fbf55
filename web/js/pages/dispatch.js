// Dispatch: the controller agents connected to this server (one per arm), the pre-flight checks and
// Start for a solved run's plan, the live progress of the current dispatch per arm (planned against
// actual: numbers, and a 3D view with a ghost of the planned configuration next to the measured one),
// Abort, and the recorded history. Abort stays on screen (a bar that sticks under the top bar) and
// answers the Esc key; its handler sends the request before anything is drawn, and the live view is
// drawn at most once per animation frame (dispatch_live.js), so a busy 3D view cannot delay it.
// Only when the server was built with the dispatch library; otherwise the page says so.
import { api, getToken, query } from '../api.js';
import { writeState } from '../url_state.js';
import { el, clear, badge, fmtNumber, fmtSeconds, errorBox, table } from '../dom.js';
import { readSse, latestPerFrame, statusLine, armsTable, historyTable } from './dispatch_live.js';

const USER_KEY = 'dashbench.dispatch.user';

// The page's elements, in the order they are shown: Abort first and sticky; then what is moving
// (the 3D view high up), then the checks and the rest.
function buildPage(body) {
  const ui = {
    controllersBox: el('div', { 'data-testid': 'controllers' }, el('div', { class: 'muted', text: 'Connecting…' })),
    runInput: el('input', { type: 'text', size: 40, placeholder: 'uuid of a solved run', list: 'dispatch-runs', 'data-testid': 'dispatch-run' }),
    runList: el('datalist', { id: 'dispatch-runs' }),
    scale: el('input', { type: 'number', value: 1, min: 0.1, step: 0.5, style: 'width:5em', 'data-testid': 'time-scale' }),
    execution: el(
      'select',
      { 'data-testid': 'execution', title: 'timed: every arm follows the plan’s clock; by dependencies: each arm moves on when what it waits for is done (docs/dispatch.md)' },
      el('option', { value: 'timed', text: 'timed' }),
      el('option', { value: 'tpg', text: 'by dependencies (tpg)' }),
    ),
    user: el('input', { type: 'text', size: 12, placeholder: 'your name', value: localStorage.getItem(USER_KEY) || '', 'data-testid': 'dispatch-user' }),
    check: el('button', { type: 'button', class: 'secondary', 'data-testid': 'preflight' }, 'Pre-flight check'),
    start: el('button', { type: 'button', disabled: true, 'data-testid': 'start' }, 'Start'),
    abort: el('button', { type: 'button', class: 'danger', 'data-testid': 'abort', title: 'Esc', 'aria-keyshortcuts': 'Escape' }, 'Abort every arm (Esc)'),
    abortMessage: el('span', { 'data-testid': 'abort-message' }),
    preflightBox: el('div', { 'data-testid': 'preflight-result' }),
    message: el('div', { 'data-testid': 'dispatch-message' }),
    statusBox: el('div', { 'data-testid': 'dispatch-status' }, el('div', { class: 'muted', text: 'No dispatch yet.' })),
    armsBox: el('div', {}),
    viewerNote: el('div', { class: 'muted' }),
    viewerBox: el('div', { class: 'viewer', 'data-testid': 'dispatch-viewer', hidden: true }),
    historyBox: el('div', { 'data-testid': 'dispatch-history' }),
  };
  body.append(
    el('div', { class: 'abort-bar', 'data-testid': 'abort-bar' }, ui.abort, el('span', { class: 'muted', text: 'stops every arm now; Esc does the same anywhere on this page' }), ui.abortMessage),
    el(
      'div',
      { class: 'panel' },
      el('h2', { text: 'Dispatch a plan' }),
      el('div', { class: 'muted', text: 'Dry-run with --driver sim agents first. Check, then Start; a time scale > 1 slows every arm alike. By dependencies, a lagging arm makes the arms that depend on it wait instead of stopping them all.' }),
      el('div', { class: 'toolbar' }, ui.runInput, ui.runList, el('label', {}, 'time scale', ui.scale), el('label', {}, 'execution', ui.execution), el('label', {}, 'who', ui.user), ui.check, ui.start),
      ui.preflightBox,
      ui.message,
    ),
    el('div', { class: 'panel', 'data-testid': 'current-dispatch' }, el('h2', { text: 'Current dispatch' }), ui.statusBox, ui.viewerNote, ui.viewerBox, ui.armsBox),
    el('div', { class: 'panel' }, el('h2', { text: 'Controllers' }), el('div', { class: 'muted', text: 'Agents started with `dashbench controller --server URL --robot ID --token-file ...` appear here.' }), ui.controllersBox),
    el('div', { class: 'panel' }, el('h2', { text: 'History' }), ui.historyBox),
  );
  return ui;
}

// Abort: the request leaves before anything is drawn; the answer is shown when it comes.
function wireAbort(ui, page) {
  function sendAbort(how) {
    const who = ui.user.value.trim();
    const sent = api.post('/api/dispatch/abort', { reason: `abort from the dashboard${who ? ` (${who})` : ''}${how}` });
    ui.abort.dataset.sent = String((Number(ui.abort.dataset.sent) || 0) + 1);
    sent.then(
      (r) => clear(ui.abortMessage).append(el('span', { class: 'ok', 'data-testid': 'abort-result', text: r.aborted ? `aborted (${r.controllers_notified} controllers told)` : 'nothing was moving' })),
      (e) => clear(ui.abortMessage).append(errorBox(e.message)),
    );
  }
  ui.abort.addEventListener('click', () => sendAbort(''));
  const onKey = (e) => {
    if (e.key !== 'Escape' || e.repeat) return;
    e.preventDefault();
    sendAbort(' by the Esc key');
  };
  document.addEventListener('keydown', onKey);
  page.cleanups.push(() => document.removeEventListener('keydown', onKey));
}

// The verdict in one line; the table of checks (one row per check and arm) folded away when they
// passed, open when one failed, so that it does not push the live view off the screen.
function showChecks(preflightBox, report) {
  clear(preflightBox);
  if (!report) return;
  preflightBox.dataset.passed = report.passed ? '1' : '0';
  const checks = report.checks || [];
  const failed = checks.filter((c) => !c.passed).length;
  preflightBox.append(
    el('div', { class: report.passed ? 'ok' : 'error', text: report.passed ? 'Pre-flight checks passed.' : `Pre-flight refused: ${report.reason}` }),
    el(
      'details',
      { 'data-testid': 'preflight-details', open: !report.passed || undefined },
      el('summary', { text: `${checks.length} checks${failed ? `, ${failed} failed` : ', all passed'}` }),
      table(['name', 'robot', 'passed', 'message'], checks, { cell: (c, v) => (c === 'passed' ? (v ? '✓' : '✗') : v) }),
    ),
  );
}

// The run, the time scale and the execution are in the URL (#/dispatch?run=UUID&scale=2&execution=tpg):
// a link from a run's page. Any change of them asks for a new check before Start.
function wireForm(ui, params) {
  if (params.get('run')) ui.runInput.value = params.get('run').slice(0, 64);
  if (Number(params.get('scale')) > 0) ui.scale.value = params.get('scale');
  if (params.get('execution') === 'tpg') ui.execution.value = 'tpg';
  const saveUrl = () => writeState({ run: ui.runInput.value.trim(), scale: ui.scale.value, execution: ui.execution.value }, { scale: '1', execution: 'timed' });
  ui.runInput.addEventListener('input', saveUrl);
  ui.scale.addEventListener('input', saveUrl);
  ui.execution.addEventListener('change', saveUrl);
  ui.runInput.addEventListener('input', () => {
    ui.start.disabled = true;
    clear(ui.preflightBox);
    delete ui.preflightBox.dataset.passed;
  });
  ui.scale.addEventListener('input', () => (ui.start.disabled = true));
  ui.execution.addEventListener('change', () => (ui.start.disabled = true));
}

// Pre-flight check, then Start with exactly what was checked.
function wireCheckAndStart(ui) {
  const requestBody = () => {
    const label = ui.user.value.trim();
    localStorage.setItem(USER_KEY, label);
    return { run_id: ui.runInput.value.trim(), options: { time_scale: Number(ui.scale.value) || 1, execution: ui.execution.value }, user: label || undefined };
  };
  let checkedFor = '';
  ui.check.addEventListener('click', async () => {
    clear(ui.message);
    clear(ui.preflightBox).append(el('div', { class: 'muted', text: 'Checking…' }));
    delete ui.preflightBox.dataset.passed;
    ui.start.disabled = true;
    try {
      const req = requestBody();
      const report = await api.post('/api/dispatch/preflight', req);
      showChecks(ui.preflightBox, report);
      checkedFor = JSON.stringify([req.run_id, req.options]);
      ui.start.disabled = !report.passed;
    } catch (e) {
      clear(ui.preflightBox);
      ui.message.append(errorBox(e.message));
    }
  });
  ui.start.addEventListener('click', async () => {
    clear(ui.message);
    const req = requestBody();
    ui.start.disabled = true;
    if (JSON.stringify([req.run_id, req.options]) !== checkedFor) {
      ui.message.append(errorBox('The plan, the time scale or the execution changed since the check: check again.'));
      return;
    }
    try {
      const r = await api.post('/api/dispatch', req);
      showChecks(ui.preflightBox, r.preflight);
      ui.message.append(el('div', { class: 'ok', 'data-testid': 'dispatch-started', text: `dispatch ${r.dispatch_id} started; arms move in ${fmtNumber(r.start_in)} s` }));
    } catch (e) {
      ui.message.append(errorBox(e.message + (e.body && e.body.reason ? `: ${e.body.reason}` : '')));
      if (e.body && e.body.preflight) showChecks(ui.preflightBox, e.body.preflight);
    }
  });
}

function renderControllers(controllersBox, list) {
  clear(controllersBox);
  if (list.length === 0) {
    controllersBox.append(el('div', { class: 'muted', text: 'No controller is connected.' }));
    return;
  }
  controllersBox.append(
    table(['robot', 'driver', 'model', 'connected', 'ready', 'status', 'detail', 'state_age'], list, {
      cell: (col, v) => (col === 'status' ? badge(String(v)) : typeof v === 'boolean' ? (v ? 'yes' : 'no') : col === 'state_age' && typeof v === 'number' ? fmtSeconds(v) : v),
    }),
  );
}

// The 3D view of the dispatched run: measured arms solid, the planned configuration as a ghost.
function makeViewer(ui, page) {
  const live = { viewer: null, run: '', lastStatus: null };
  live.draw = (s) => {
    if (!live.viewer) return;
    const arms = {};
    for (const a of s.arms || []) arms[a.robot] = { planned: a.planned, actual: a.actual };
    live.viewer.setLive(arms, Math.max(0, s.elapsed) / (s.time_scale || 1));
  };
  live.load = async (runId) => {
    live.run = runId;
    if (live.viewer) {
      live.viewer.dispose();
      live.viewer = null;
    }
    ui.viewerBox.hidden = !runId;
    ui.viewerNote.textContent = runId ? '' : 'A plan sent with its request has no stored scene here: no 3D view.';
    if (!runId) return;
    try {
      const [scene, plan, models] = await Promise.all([api.get(`/api/runs/${runId}/scene`), api.get(`/api/runs/${runId}/plan`), api.get('/api/robots')]);
      const { PlanViewer } = await import('../viewer3d.js');
      if (page.stopped || live.run !== runId) return;
      live.viewer = new PlanViewer(ui.viewerBox, scene, plan, models.models, { live: true });
      ui.viewerBox.dataset.ready = '1';
      ui.viewerNote.textContent = 'Solid: where each arm is (measured). Orange ghost: where the plan wants it now.';
      if (live.lastStatus) live.draw(live.lastStatus);
    } catch (e) {
      ui.viewerNote.textContent = '';
      ui.viewerBox.append(errorBox(`3D view: ${e.message}`));
    }
  };
  page.cleanups.push(() => {
    if (live.viewer) live.viewer.dispose();
  });
  return live;
}

async function loadHistory(ui, page) {
  if (page.stopped || !getToken()) return;
  try {
    const h = await api.get('/api/dispatches?limit=20');
    clear(ui.historyBox);
    if (h.dispatches.length === 0) {
      ui.historyBox.append(el('div', { class: 'muted', text: 'No dispatch recorded yet.' }));
      return;
    }
    ui.historyBox.dataset.total = String(h.total);
    ui.historyBox.append(el('div', { class: 'muted', text: `${h.total} recorded; newest first.` }), historyTable(h));
  } catch (e) {
    clear(ui.historyBox).append(errorBox(e.message));
  }
}

async function loadRuns(runList) {
  try {
    const r = await api.get(`/api/runs${query({ limit: 50, q: 'has_plan = 1 and status = solved' })}`);
    clear(runList).append(r.runs.map((x) => el('option', { value: x.uuid, text: `${x.family} ${JSON.stringify(x.params || {})} ${x.config || x.planner || ''}` })));
  } catch {
    // The list is a convenience: a uuid typed in still works.
  }
}

// The status of the current dispatch, drawn at most once per animation frame; the history is read
// again when a dispatch starts (its record is written as it starts) and when it ends.
function makeStatusView(ui, page, live) {
  let lastFinalId = '';
  let lastSeenId = '';
  return (s) => {
    live.lastStatus = s;
    Object.assign(ui.statusBox.dataset, { state: s.state, id: s.id, final: s.final ? '1' : '0' });
    clear(ui.statusBox).append(...statusLine(s));
    clear(ui.armsBox).append(armsTable(s));
    if ((s.run_id || '') !== live.run) live.load(s.run_id || '');
    live.draw(s);
    if (s.id !== lastSeenId) {
      lastSeenId = s.id;
      setTimeout(() => loadHistory(ui, page), 300);
    }
    if (s.final && s.id !== lastFinalId) {
      lastFinalId = s.id;
      setTimeout(() => loadHistory(ui, page), 300); // the record is written just after the end
    }
  };
}

// The live stream (server-sent events): dispatch status and controllers; reconnects every second.
async function stream(ui, page, frames) {
  if (page.stopped) return;
  clearTimeout(page.retryTimer);
  if (page.streamAbort) page.streamAbort.abort();
  if (!getToken()) {
    clear(ui.controllersBox).append(el('div', { class: 'muted', text: 'The dispatch view needs the token (Token button, top right).' }));
    return;
  }
  const controller = new AbortController();
  page.streamAbort = controller;
  try {
    const res = await fetch('/api/dispatch/stream', { headers: { Authorization: `Bearer ${getToken()}` }, signal: controller.signal });
    if (!res.ok) throw new Error(`${res.status} ${res.statusText}`);
    await readSse(res, (name, data) => {
      const value = JSON.parse(data);
      if (name === 'dispatch') frames.status.push(value);
      else if (name === 'controllers') frames.controllers.push(value.controllers);
    });
  } catch (e) {
    if (controller.signal.aborted || page.stopped) return;
    const why = e instanceof TypeError ? "the dashboard's server does not answer (is `dashbench serve` still running?)" : e.message;
    clear(ui.controllersBox).append(errorBox(`live stream: ${why}; reconnecting every second`));
  }
  if (!page.stopped && !controller.signal.aborted) page.retryTimer = setTimeout(() => stream(ui, page, frames), 1000);
}

async function showPage(body, params, page) {
  const health = await api.get('/api/health');
  if (page.stopped) return;
  if (!health.dispatch) {
    body.append(
      el(
        'div',
        { class: 'panel', 'data-testid': 'dispatch-missing' },
        'The dispatch API is not part of this server build, so no controllers can connect here. Build dashbench with server/dispatch to drive arms.',
      ),
    );
    return;
  }
  const ui = buildPage(body);
  wireAbort(ui, page);
  wireForm(ui, params);
  wireCheckAndStart(ui);
  const live = makeViewer(ui, page);
  const frames = {
    status: latestPerFrame(makeStatusView(ui, page, live)),
    controllers: latestPerFrame((list) => renderControllers(ui.controllersBox, list)),
  };
  page.cleanups.push(() => frames.status.cancel(), () => frames.controllers.cancel());
  const onToken = () => {
    stream(ui, page, frames);
    loadHistory(ui, page);
  };
  window.addEventListener('dashbench-token', onToken);
  page.cleanups.push(() => window.removeEventListener('dashbench-token', onToken));
  onToken();
  loadRuns(ui.runList);
}

export function mount(root, args, params = new URLSearchParams()) {
  root.append(el('h1', { text: 'Dispatch to arms' }));
  const topbar = document.querySelector('.topbar'); // the abort bar sticks just under it
  if (topbar) root.style.setProperty('--topbar-height', `${topbar.offsetHeight}px`);
  const body = el('div', {});
  root.append(body);
  const page = { stopped: false, streamAbort: null, retryTimer: 0, cleanups: [] };
  showPage(body, params, page).catch((e) => body.append(errorBox(e.message)));
  return () => {
    page.stopped = true;
    clearTimeout(page.retryTimer);
    if (page.streamAbort) page.streamAbort.abort();
    for (const fn of page.cleanups) fn();
  };
}
