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

export function mount(root, args, params = new URLSearchParams()) {
  root.append(el('h1', { text: 'Dispatch to arms' }));
  const topbar = document.querySelector('.topbar'); // the abort bar sticks just under it
  if (topbar) root.style.setProperty('--topbar-height', `${topbar.offsetHeight}px`);
  const body = el('div', {});
  root.append(body);
  let stopped = false;
  let streamAbort = null;
  let retryTimer = 0;
  const cleanups = [];

  (async () => {
    const health = await api.get('/api/health');
    if (stopped) return;
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
    const controllersBox = el('div', { 'data-testid': 'controllers' }, el('div', { class: 'muted', text: 'Connecting…' }));
    const runInput = el('input', { type: 'text', size: 40, placeholder: 'uuid of a solved run', list: 'dispatch-runs', 'data-testid': 'dispatch-run' });
    const runList = el('datalist', { id: 'dispatch-runs' });
    const scale = el('input', { type: 'number', value: 1, min: 0.1, step: 0.5, style: 'width:5em', 'data-testid': 'time-scale' });
    const execution = el(
      'select',
      { 'data-testid': 'execution', title: 'timed: every arm follows the plan’s clock; by dependencies: each arm moves on when what it waits for is done (docs/dispatch.md)' },
      el('option', { value: 'timed', text: 'timed' }),
      el('option', { value: 'tpg', text: 'by dependencies (tpg)' }),
    );
    const user = el('input', { type: 'text', size: 12, placeholder: 'your name', value: localStorage.getItem(USER_KEY) || '', 'data-testid': 'dispatch-user' });
    const check = el('button', { type: 'button', class: 'secondary', 'data-testid': 'preflight' }, 'Pre-flight check');
    const start = el('button', { type: 'button', disabled: true, 'data-testid': 'start' }, 'Start');
    const abort = el('button', { type: 'button', class: 'danger', 'data-testid': 'abort', title: 'Esc', 'aria-keyshortcuts': 'Escape' }, 'Abort every arm (Esc)');
    const abortMessage = el('span', { 'data-testid': 'abort-message' });
    const preflightBox = el('div', { 'data-testid': 'preflight-result' });
    const message = el('div', { 'data-testid': 'dispatch-message' });
    const statusBox = el('div', { 'data-testid': 'dispatch-status' }, el('div', { class: 'muted', text: 'No dispatch yet.' }));
    const armsBox = el('div', {});
    const viewerNote = el('div', { class: 'muted' });
    const viewerBox = el('div', { class: 'viewer', 'data-testid': 'dispatch-viewer', hidden: true });
    const historyBox = el('div', { 'data-testid': 'dispatch-history' });
    // Abort first and sticky; then what is moving (the 3D view high up), then the checks and the rest.
    body.append(
      el('div', { class: 'abort-bar', 'data-testid': 'abort-bar' }, abort, el('span', { class: 'muted', text: 'stops every arm now; Esc does the same anywhere on this page' }), abortMessage),
      el(
        'div',
        { class: 'panel' },
        el('h2', { text: 'Dispatch a plan' }),
        el('div', { class: 'muted', text: 'Dry-run with --driver sim agents first. Check, then Start; a time scale > 1 slows every arm alike. By dependencies, a lagging arm makes the arms that depend on it wait instead of stopping them all.' }),
        el('div', { class: 'toolbar' }, runInput, runList, el('label', {}, 'time scale', scale), el('label', {}, 'execution', execution), el('label', {}, 'who', user), check, start),
        preflightBox,
        message,
      ),
      el('div', { class: 'panel', 'data-testid': 'current-dispatch' }, el('h2', { text: 'Current dispatch' }), statusBox, viewerNote, viewerBox, armsBox),
      el('div', { class: 'panel' }, el('h2', { text: 'Controllers' }), el('div', { class: 'muted', text: 'Agents started with `dashbench controller --server URL --robot ID --token-file ...` appear here.' }), controllersBox),
      el('div', { class: 'panel' }, el('h2', { text: 'History' }), historyBox),
    );

    // ---------------------------------------------------------------- abort
    // The request leaves before anything is drawn; the answer is shown when it comes.
    function sendAbort(how) {
      const who = user.value.trim();
      const sent = api.post('/api/dispatch/abort', { reason: `abort from the dashboard${who ? ` (${who})` : ''}${how}` });
      abort.dataset.sent = String((Number(abort.dataset.sent) || 0) + 1);
      sent.then(
        (r) => clear(abortMessage).append(el('span', { class: 'ok', 'data-testid': 'abort-result', text: r.aborted ? `aborted (${r.controllers_notified} controllers told)` : 'nothing was moving' })),
        (e) => clear(abortMessage).append(errorBox(e.message)),
      );
    }
    abort.addEventListener('click', () => sendAbort(''));
    const onKey = (e) => {
      if (e.key !== 'Escape' || e.repeat) return;
      e.preventDefault();
      sendAbort(' by the Esc key');
    };
    document.addEventListener('keydown', onKey);
    cleanups.push(() => document.removeEventListener('keydown', onKey));

    // ---------------------------------------------------------------- requests
    function requestBody() {
      const label = user.value.trim();
      localStorage.setItem(USER_KEY, label);
      return { run_id: runInput.value.trim(), options: { time_scale: Number(scale.value) || 1, execution: execution.value }, user: label || undefined };
    }

    // The verdict in one line; the table of checks (one row per check and arm) folded away when they
    // passed, open when one failed, so that it does not push the live view off the screen.
    function showChecks(report) {
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

    // The run and the time scale are in the URL (#/dispatch?run=UUID&scale=2): a link from a run's page.
    if (params.get('run')) runInput.value = params.get('run').slice(0, 64);
    if (Number(params.get('scale')) > 0) scale.value = params.get('scale');
    if (params.get('execution') === 'tpg') execution.value = 'tpg';
    const saveUrl = () => writeState({ run: runInput.value.trim(), scale: scale.value, execution: execution.value }, { scale: '1', execution: 'timed' });
    runInput.addEventListener('input', saveUrl);
    scale.addEventListener('input', saveUrl);
    execution.addEventListener('change', saveUrl);

    let checkedFor = '';
    runInput.addEventListener('input', () => {
      start.disabled = true;
      clear(preflightBox);
      delete preflightBox.dataset.passed;
    });
    scale.addEventListener('input', () => (start.disabled = true));
    execution.addEventListener('change', () => (start.disabled = true));

    check.addEventListener('click', async () => {
      clear(message);
      clear(preflightBox).append(el('div', { class: 'muted', text: 'Checking…' }));
      delete preflightBox.dataset.passed;
      start.disabled = true;
      try {
        const req = requestBody();
        const report = await api.post('/api/dispatch/preflight', req);
        showChecks(report);
        checkedFor = JSON.stringify([req.run_id, req.options]);
        start.disabled = !report.passed;
      } catch (e) {
        clear(preflightBox);
        message.append(errorBox(e.message));
      }
    });

    start.addEventListener('click', async () => {
      clear(message);
      const req = requestBody();
      if (JSON.stringify([req.run_id, req.options]) !== checkedFor) {
        start.disabled = true;
        message.append(errorBox('The plan, the time scale or the execution changed since the check: check again.'));
        return;
      }
      start.disabled = true;
      try {
        const r = await api.post('/api/dispatch', req);
        showChecks(r.preflight);
        message.append(el('div', { class: 'ok', 'data-testid': 'dispatch-started', text: `dispatch ${r.dispatch_id} started; arms move in ${fmtNumber(r.start_in)} s` }));
      } catch (e) {
        message.append(errorBox(e.message + (e.body && e.body.reason ? `: ${e.body.reason}` : '')));
        if (e.body && e.body.preflight) showChecks(e.body.preflight);
      }
    });

    // ---------------------------------------------------------------- live view
    function renderControllers(list) {
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

    let viewer = null;
    let viewerRun = '';
    async function loadViewer(runId) {
      viewerRun = runId;
      if (viewer) {
        viewer.dispose();
        viewer = null;
      }
      viewerBox.hidden = !runId;
      viewerNote.textContent = runId ? '' : 'A plan sent with its request has no stored scene here: no 3D view.';
      if (!runId) return;
      try {
        const [scene, plan, models] = await Promise.all([api.get(`/api/runs/${runId}/scene`), api.get(`/api/runs/${runId}/plan`), api.get('/api/robots')]);
        const { PlanViewer } = await import('../viewer3d.js');
        if (stopped || viewerRun !== runId) return;
        viewer = new PlanViewer(viewerBox, scene, plan, models.models, { live: true });
        viewerBox.dataset.ready = '1';
        viewerNote.textContent = 'Solid: where each arm is (measured). Orange ghost: where the plan wants it now.';
        if (lastStatus) drawLive(lastStatus);
      } catch (e) {
        viewerNote.textContent = '';
        viewerBox.append(errorBox(`3D view: ${e.message}`));
      }
    }

    function drawLive(s) {
      if (!viewer) return;
      const arms = {};
      for (const a of s.arms || []) arms[a.robot] = { planned: a.planned, actual: a.actual };
      viewer.setLive(arms, Math.max(0, s.elapsed) / (s.time_scale || 1));
    }

    let lastStatus = null;
    let lastFinalId = '';
    let lastSeenId = '';
    function renderStatus(s) {
      lastStatus = s;
      Object.assign(statusBox.dataset, { state: s.state, id: s.id, final: s.final ? '1' : '0' });
      clear(statusBox).append(...statusLine(s));
      clear(armsBox).append(armsTable(s));
      if ((s.run_id || '') !== viewerRun) loadViewer(s.run_id || '');
      drawLive(s);
      if (s.id !== lastSeenId) {
        lastSeenId = s.id;
        setTimeout(loadHistory, 300); // a new dispatch: its record (started) is written as it starts
      }
      if (s.final && s.id !== lastFinalId) {
        lastFinalId = s.id;
        setTimeout(loadHistory, 300); // the record is written just after the end
      }
    }
    const statusFrames = latestPerFrame(renderStatus);
    const controllerFrames = latestPerFrame(renderControllers);
    cleanups.push(() => statusFrames.cancel(), () => controllerFrames.cancel());

    async function loadHistory() {
      if (stopped || !getToken()) return;
      try {
        const h = await api.get('/api/dispatches?limit=20');
        clear(historyBox);
        if (h.dispatches.length === 0) {
          historyBox.append(el('div', { class: 'muted', text: 'No dispatch recorded yet.' }));
          return;
        }
        historyBox.dataset.total = String(h.total);
        historyBox.append(el('div', { class: 'muted', text: `${h.total} recorded; newest first.` }), historyTable(h));
      } catch (e) {
        clear(historyBox).append(errorBox(e.message));
      }
    }

    async function loadRuns() {
      try {
        const r = await api.get(`/api/runs${query({ limit: 50, q: 'has_plan = 1 and status = solved' })}`);
        clear(runList).append(r.runs.map((x) => el('option', { value: x.uuid, text: `${x.family} ${JSON.stringify(x.params || {})} ${x.config || x.planner || ''}` })));
      } catch {
        // The list is a convenience: a uuid typed in still works.
      }
    }

    async function stream() {
      if (stopped) return;
      clearTimeout(retryTimer);
      if (streamAbort) streamAbort.abort();
      if (!getToken()) {
        clear(controllersBox).append(el('div', { class: 'muted', text: 'The dispatch view needs the token (Token button, top right).' }));
        return;
      }
      const controller = new AbortController();
      streamAbort = controller;
      try {
        const res = await fetch('/api/dispatch/stream', { headers: { Authorization: `Bearer ${getToken()}` }, signal: controller.signal });
        if (!res.ok) throw new Error(`${res.status} ${res.statusText}`);
        await readSse(res, (name, data) => {
          const value = JSON.parse(data);
          if (name === 'dispatch') statusFrames.push(value);
          else if (name === 'controllers') controllerFrames.push(value.controllers);
        });
      } catch (e) {
        if (controller.signal.aborted || stopped) return;
        const why = e instanceof TypeError ? "the dashboard's server does not answer (is `dashbench serve` still running?)" : e.message;
        clear(controllersBox).append(errorBox(`live stream: ${why}; reconnecting every second`));
      }
      if (!stopped && !controller.signal.aborted) retryTimer = setTimeout(stream, 1000);
    }

    const onToken = () => {
      stream();
      loadHistory();
    };
    window.addEventListener('dashbench-token', onToken);
    cleanups.push(() => window.removeEventListener('dashbench-token', onToken));
    stream();
    loadHistory();
    loadRuns();
    cleanups.push(() => {
      if (viewer) viewer.dispose();
    });
  })().catch((e) => body.append(errorBox(e.message)));

  return () => {
    stopped = true;
    clearTimeout(retryTimer);
    if (streamAbort) streamAbort.abort();
    for (const fn of cleanups) fn();
  };
}
