// The Dispatch page's live part: the reader of the server's dispatch stream (server-sent events read
// with fetch, since the stream needs the token), the current dispatch's status line and per-arm
// table, the history table, and the frame scheduler that draws only the newest status, at most once
// per animation frame (the stream sends about 12 a second; drawing each one, 3D view included, froze
// the page under software WebGL so that Abort could not be clicked: issue 41).
import { el, badge, fmtNumber, fmtSeconds } from '../dom.js';

/// Reads server-sent events from a fetch response body; calls onEvent(name, data) per event.
export async function readSse(response, onEvent) {
  const reader = response.body.getReader();
  const decoder = new TextDecoder();
  let buffer = '';
  for (;;) {
    const { value, done } = await reader.read();
    if (done) return;
    buffer += decoder.decode(value, { stream: true });
    let end;
    while ((end = buffer.indexOf('\n\n')) >= 0) {
      const frame = buffer.slice(0, end);
      buffer = buffer.slice(end + 2);
      let name = 'message';
      let data = '';
      for (const line of frame.split('\n')) {
        if (line.startsWith('event: ')) name = line.slice(7);
        else if (line.startsWith('data: ')) data += line.slice(6);
      }
      if (data) onEvent(name, data);
    }
  }
}

/// draw(value) with the newest value pushed, at most once per animation frame; values pushed in
/// between are dropped (only the newest matters for a live view).
export function latestPerFrame(draw) {
  let latest;
  let frame = 0;
  return {
    push(value) {
      latest = value;
      if (frame) return;
      frame = requestAnimationFrame(() => {
        frame = 0;
        draw(latest);
      });
    },
    cancel() {
      cancelAnimationFrame(frame);
      frame = 0;
    },
  };
}

function clamp01(v) {
  return Math.max(0, Math.min(1, v));
}

function progressBar(fraction, cls) {
  return el('div', { class: 'progress' }, el('div', { class: cls, style: `width:${(100 * clamp01(fraction)).toFixed(1)}%` }));
}

/// The line above the arms: state, id, time, overall progress, who, the run.
export function statusLine(s) {
  const overall = s.duration > 0 ? Math.max(0, s.elapsed) / s.duration : 0;
  return [
    el(
      'div',
      { class: 'toolbar' },
      badge(s.state),
      el('span', { class: 'mono', text: s.id }),
      el('span', { text: `${fmtNumber(Math.max(0, s.elapsed))} s of ${fmtNumber(s.duration)} s` }),
      progressBar(overall, s.state === 'succeeded' ? 'solved' : s.final ? 'failed' : 'running'),
      s.requested_by ? el('span', { class: 'muted', text: `by ${s.requested_by}` }) : null,
      s.run_id ? el('a', { href: `#/run/${s.run_id}`, text: 'run' }) : null,
    ),
    ...(s.reason ? [el('div', { class: s.state === 'succeeded' ? 'muted' : 'error', 'data-testid': 'dispatch-reason', text: s.reason })] : []),
  ];
}

/// Execution by dependencies: the step an arm is on ("4 / 75 motion") and what it waits for.
function stepCells(a) {
  const segments = a.segments || [];
  const current = a.step < a.steps ? segments[a.step] : null;
  const step = a.steps > 0 ? `${Math.min(a.step + 1, a.steps)} / ${a.steps}${current ? ` ${current.kind}` : ''}` : '';
  return [
    el('td', { class: 'num', 'data-testid': 'arm-step', text: step }),
    el('td', { class: a.waiting_for ? 'muted' : '', 'data-testid': 'arm-waiting', text: a.waiting_for ? `waits for ${a.waiting_for}` : a.done ? '' : 'running' }),
  ];
}

/// One row per arm: status, progress, (by dependencies: step, what it waits for,) joint error now and
/// at most, samples, result.
export function armsTable(s) {
  const tpg = s.execution === 'tpg';
  const head = ['robot', 'driver', 'status', 'progress', ...(tpg ? ['step', 'waiting for'] : []), 'joint error', 'max error', 'samples', 'result'];
  const tolerance = (s.tolerances && s.tolerances.path) || 0;
  const rows = (s.arms || []).map((a) => {
    const fraction = tpg ? (a.steps > 0 ? a.step / a.steps : 0) : a.duration > 0 ? Math.max(0, a.t) / a.duration : 0;
    const progress = a.done && a.result && a.result.name === 'SUCCESSFUL' ? 1 : fraction;
    return el(
      'tr',
      { 'data-robot': a.robot, 'data-status': a.status, 'data-result': a.done ? a.result.name : '', 'data-progress': progress.toFixed(3), 'data-step': tpg ? String(a.step) : '' },
      el('td', { text: a.robot }),
      el('td', { text: a.driver }),
      el('td', {}, badge(tpg && a.waiting_for ? 'waiting' : a.status)),
      el('td', {}, el('div', { class: 'toolbar', style: 'margin:0' }, progressBar(progress, 'running'), el('span', { text: `${Math.round(100 * clamp01(progress))} %` }))),
      ...(tpg ? stepCells(a) : []),
      el('td', { class: `num${tolerance && a.deviation > 0.5 * tolerance ? ' error' : ''}`, text: `${a.deviation.toFixed(4)} rad` }),
      el('td', { class: 'num', text: `${a.max_deviation.toFixed(4)} rad` }),
      el('td', { class: 'num', text: String(a.samples) }),
      el('td', { text: a.done ? `${a.result.name}${a.result.message ? `: ${a.result.message}` : ''}` : '' }),
    );
  });
  return el('table', { class: 'data', 'data-testid': 'arms-table' }, el('thead', {}, el('tr', {}, head.map((h) => el('th', { text: h })))), el('tbody', {}, rows));
}

/// The recorded dispatches, newest first (GET /api/dispatches).
export function historyTable(h) {
  const head = ['created', 'id', 'state', 'execution', 'who', 'client', 'run', 'planned', 'elapsed', 'arms', 'reason'];
  const row = (d) =>
    el(
      'tr',
      { 'data-dispatch': d.id, 'data-state': d.state },
      el('td', { text: d.created.replace('T', ' ').replace('Z', '') }),
      el('td', { class: 'mono', text: d.id }),
      el('td', {}, badge(d.state)),
      el('td', { text: d.execution === 'tpg' ? 'by dependencies' : 'timed' }),
      el('td', { text: d.requested_by }),
      el('td', { text: d.client }),
      el('td', {}, d.run_id ? el('a', { href: `#/run/${d.run_id}`, text: d.run_id.slice(0, 8) }) : ''),
      el('td', { class: 'num', text: fmtSeconds(d.duration) }),
      el('td', { class: 'num', text: d.started ? fmtSeconds(d.elapsed) : '' }),
      el('td', { text: d.arms.map((a) => `${a.robot}: ${a.result ? a.result.name : 'not started'}`).join(', ') }),
      el('td', { text: d.reason }),
    );
  return el(
    'div',
    { class: 'table-wrap', style: 'max-height:360px' },
    el('table', { class: 'data' }, el('thead', {}, el('tr', {}, head.map((c) => el('th', { text: c })))), el('tbody', {}, h.dispatches.map(row))),
  );
}
