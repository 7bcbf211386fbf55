// Dispatch: the controller agents connected to this server (one per arm), the current dispatch and
// its arms, and dispatching a solved run's plan or aborting every arm. Only when the server was
// built with the dispatch library; otherwise the page says so.
import { api, getToken } from '../api.js';
import { el, clear, badge, fmtNumber, errorBox, table } from '../dom.js';

export function mount(root) {
  root.append(el('h1', { text: 'Dispatch to arms' }));
  const body = el('div', {});
  root.append(body);
  let timer = 0;
  let stopped = false;
  let dispatched = false; // this page started one: show its record even after the arms let go

  (async () => {
    const health = await api.get('/api/health');
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
    const controllersBox = el('div', { 'data-testid': 'controllers' });
    const statusBox = el('div', { 'data-testid': 'dispatch-status' });
    const runInput = el('input', { type: 'text', size: 40, placeholder: 'uuid of a solved run' });
    const scale = el('input', { type: 'number', value: 2, min: 1, step: 0.5, style: 'width:5em' });
    const go = el('button', { type: 'button' }, 'Dispatch');
    const abort = el('button', { type: 'button', class: 'danger' }, 'Abort every arm');
    const message = el('div', {});
    body.append(
      el('div', { class: 'panel' }, el('h2', { text: 'Controllers' }), el('div', { class: 'muted', text: 'Agents started with `dashbench controller --server URL --robot ID --token-file ...` appear here.' }), controllersBox),
      el(
        'div',
        { class: 'panel' },
        el('h2', { text: 'Dispatch a plan' }),
        el('div', { class: 'muted', text: 'Dry-run with --driver sim agents first. time scale > 1 slows every arm alike.' }),
        el('div', { class: 'toolbar' }, runInput, el('label', {}, 'time scale', scale), go, abort),
        message,
      ),
      el('div', { class: 'panel' }, el('h2', { text: 'Current dispatch' }), statusBox),
    );
    go.addEventListener('click', async () => {
      clear(message);
      try {
        const r = await api.post('/api/dispatch', { run_id: runInput.value.trim(), options: { time_scale: Number(scale.value) } });
        dispatched = true;
        message.append(el('div', { class: 'ok', text: `dispatch ${r.dispatch_id} started; arms move in ${fmtNumber(r.start_in)} s` }));
      } catch (e) {
        message.append(errorBox(e.message));
        const checks = e.body && e.body.preflight && e.body.preflight.checks;
        if (checks) message.append(table(['name', 'robot', 'passed', 'message'], checks));
      }
    });
    abort.addEventListener('click', async () => {
      try {
        const r = await api.post('/api/dispatch/abort', { reason: 'abort from the dashboard' });
        clear(message).append(el('div', { class: 'ok', text: r.aborted ? `aborted (${r.controllers_notified} controllers told)` : 'nothing was moving' }));
      } catch (e) {
        clear(message).append(errorBox(e.message));
      }
    });

    async function refresh() {
      if (stopped) return;
      if (!getToken()) {
        clear(controllersBox).append(el('div', { class: 'muted', text: 'The controller list needs the token (Token button, top right).' }));
      } else {
        let active = dispatched;
        try {
          const c = await api.get('/api/controllers');
          active = active || c.controllers.some((x) => x.dispatch_id);
          clear(controllersBox);
          if (c.controllers.length === 0) controllersBox.append(el('div', { class: 'muted', text: 'No controller is connected.' }));
          else {
            controllersBox.append(
              table(['robot', 'driver', 'model', 'connected', 'ready', 'status', 'detail', 'state_age'], c.controllers, {
                cell: (col, v) => (col === 'status' ? badge(String(v)) : typeof v === 'boolean' ? (v ? 'yes' : 'no') : v),
              }),
            );
          }
        } catch (e) {
          clear(controllersBox).append(errorBox(e.message));
        }
        // Only when there is one: GET /api/dispatch answers 404 before the first dispatch.
        if (active) {
          try {
            const s = await api.get('/api/dispatch');
            clear(statusBox).append(
              el('div', {}, badge(s.state), ` ${s.id} — ${s.reason || ''}`),
              table(['robot', 'driver', 'status', 'done', 'deviation', 'max_deviation', 'samples'], s.arms || []),
            );
          } catch (e) {
            clear(statusBox).append(el('div', { class: 'muted', text: e.status === 404 ? 'No dispatch yet.' : e.message }));
          }
        } else {
          clear(statusBox).append(el('div', { class: 'muted', text: 'No dispatch yet.' }));
        }
      }
      timer = setTimeout(refresh, 1000);
    }
    refresh();
  })().catch((e) => body.append(errorBox(e.message)));

  return () => {
    stopped = true;
    clearTimeout(timer);
  };
}
