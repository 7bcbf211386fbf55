// Run detail: one run's metadata, tags and note; its phase breakdown; a timeline of what the planner
// added when (representation sizes over time, constraints with the conflict that caused each, task
// space expansions); its events, paged; and a 3D view of its plan with a time scrubber. A running
// run's sizes grow live.
import { api, query } from '../api.js';
import { on } from '../events.js';
import { el, clear, badge, fmtNumber, fmtSeconds, paramsText, errorBox, table } from '../dom.js';
import { drawChart, valueAxis, axisTitle, destroyCharts } from '../charts.js';
import { PHASE_COLOURS, PHASE_LABELS, LAYER_STYLES, OKABE_ITO } from '../palette.js';
import { mountRunDispatch } from './run_dispatch.js';

const LAYERS = ['task', 'task_extended', 'motion', 'motion_extended'];
const LAYER_COLOURS = { task: '#0072B2', task_extended: '#56B4E9', motion: '#D55E00', motion_extended: '#E69F00' };
const MARK_ROWS = ['frontier', 'history', 'motion', 'interaction', 'task space expansion'];

async function pickRun(root) {
  root.append(el('h1', { text: 'Run detail' }), el('p', { class: 'muted', text: 'Pick a run (or open one from the Runs page).' }));
  const list = await api.get('/api/runs?limit=25&sort=id&order=desc');
  root.append(
    el(
      'div',
      { class: 'panel' },
      table(['run', 'family', 'config', 'status', 'total_time'], list.runs, {
        cell: (c, v, r) => (c === 'run' ? el('a', { href: `#/run/${r.uuid}`, class: 'mono', text: r.uuid.slice(0, 8) }) : c === 'status' ? badge(v) : v),
      }),
    ),
  );
}

export function mount(root, args) {
  const uuid = args[0];
  if (!uuid) {
    pickRun(root).catch((e) => root.append(errorBox(e.message)));
    return null;
  }
  let viewer = null;
  let playing = false;
  let raf = 0;
  let progress = null; // the timeline's size series, extended live
  const header = el('div', { class: 'panel', 'data-testid': 'run-header' });
  const phasesBox = el('div', { class: 'chart-box', 'data-testid': 'chart-phases', 'data-points': '0' });
  const phaseTable = el('div', {});
  const sizesBox = el('div', { class: 'chart-box', 'data-testid': 'chart-timeline', 'data-points': '0' });
  const marksBox = el('div', { class: 'chart-box', 'data-testid': 'chart-marks', 'data-points': '0', style: 'height:230px' });
  const constraintsBox = el('div', {});
  const eventsBox = el('div', { 'data-testid': 'events' });
  const viewerBox = el('div', { class: 'viewer', 'data-testid': 'viewer' });
  const viewerNote = el('div', { class: 'muted' });
  const scrub = el('input', { type: 'range', min: 0, max: 1000, value: 0, step: 1, 'data-testid': 'scrubber' });
  const play = el('button', { type: 'button', 'data-testid': 'play' }, 'Play');
  const speed = el('select', {}, [0.5, 1, 2, 5, 10].map((s) => el('option', { value: s, text: `${s}×`, selected: s === 2 })));
  const timeLabel = el('span', { class: 'mono', 'data-testid': 'time-label', text: 't = 0.00 s' });

  root.append(
    header,
    el(
      'div',
      { class: 'grid2' },
      el('div', { class: 'panel' }, el('h2', { text: 'Phase breakdown' }), el('div', { class: 'muted', text: 'Seconds per phase in each planning iteration (stacked).' }), phasesBox, phaseTable),
      el(
        'div',
        { class: 'panel' },
        el('h2', { text: 'Representation sizes over time' }),
        el('div', { class: 'muted', text: 'Vertices of each representation at each progress snapshot (log scale).' }),
        sizesBox,
      ),
    ),
    el(
      'div',
      { class: 'panel' },
      el('h2', { text: 'Timeline: constraints and expansions' }),
      el('div', { class: 'muted', text: 'Each mark is a constraint (by kind) or a task space expansion; hover for what it says and the conflict that caused it.' }),
      marksBox,
      constraintsBox,
    ),
    el(
      'div',
      { class: 'panel' },
      el('h2', { text: 'Plan in 3D' }),
      viewerNote,
      viewerBox,
      el('div', { class: 'scrubber' }, play, el('label', {}, 'speed', speed), scrub, timeLabel),
      el('div', { class: 'muted', text: 'Drag to orbit, scroll to zoom, right-drag to pan. Robots are drawn from their collision bodies (data/robots); outlines mark object goals.' }),
    ),
    el('div', { class: 'panel' }, el('h2', { text: 'Events' }), eventsBox),
  );
  mountRunDispatch(header, uuid);

  function renderHeader(d) {
    const r = d.run;
    const tags = el('span', { 'data-testid': 'tags' });
    for (const t of d.tags) {
      tags.append(
        el('span', { class: 'chip' }, t, el('button', { type: 'button', title: `remove ${t}`, onclick: () => editTags([], [t]) }, '×')),
      );
    }
    const tagInput = el('input', { type: 'text', size: 12, placeholder: 'new tag', 'data-testid': 'tag-input' });
    const tagAdd = el('button', { type: 'button', class: 'small', 'data-testid': 'tag-add' }, 'Add tag');
    tagAdd.addEventListener('click', () => tagInput.value.trim() && editTags([tagInput.value.trim()], []));
    const note = el('textarea', { rows: 2, 'data-testid': 'note', placeholder: 'a note about this run' });
    note.value = d.note || '';
    const noteSave = el('button', { type: 'button', class: 'small', 'data-testid': 'note-save' }, 'Save note');
    const noteStatus = el('span', { class: 'muted' });
    noteSave.addEventListener('click', async () => {
      try {
        await api.put(`/api/runs/${uuid}/note`, { note: note.value });
        noteStatus.textContent = 'saved';
      } catch (e) {
        noteStatus.textContent = e.message;
      }
    });
    const kv = [
      ['uuid', r.uuid],
      ['status', r.status],
      ['family', `${r.family}  ${paramsText(d.params)}  seed ${r.seed}`],
      ['planner', `${r.planner} (${r.config})  ${JSON.stringify(d.settings)}`],
      ['batch', r.batch || '—'],
      ['scene', r.scene || '—'],
      ['total time', r.total_time === null ? '—' : fmtSeconds(r.total_time)],
      ['makespan', r.makespan === null ? '—' : `${fmtNumber(r.makespan)} s`],
      ['sizes', LAYERS.map((l) => `${LAYER_STYLES[l].label} ${fmtNumber(r[`${l}_vertices`])}/${fmtNumber(r[`${l}_hyperarcs`])}`).join('  ')],
      ['events', Object.entries(d.event_counts).map(([k, v]) => `${k} ${v}`).join(', ')],
    ];
    if (r.error) kv.push(['error', r.error]);
    clear(header).append(
      el('h1', {}, 'Run ', el('span', { class: 'mono', text: r.uuid.slice(0, 8) }), ' ', badge(r.status)),
      el('dl', { class: 'kv' }, kv.map(([k, v]) => [el('dt', { text: k }), el('dd', { text: String(v) })])),
      el('div', { class: 'toolbar', style: 'margin-top:8px' }, tags, tagInput, tagAdd),
      el('div', { class: 'toolbar' }, note, noteSave, noteStatus),
    );
  }

  async function editTags(add, remove) {
    try {
      await api.post(`/api/runs/${uuid}/tags`, { add, remove });
      await loadDetail();
    } catch (e) {
      header.append(errorBox(e.message));
    }
  }

  function renderPhases(d) {
    const iterations = [...new Set(d.phase_iterations.map((p) => p.iteration))].sort((a, b) => a - b);
    const phases = Object.keys(PHASE_COLOURS);
    const datasets = phases
      .map((p) => ({
        label: PHASE_LABELS[p],
        backgroundColor: PHASE_COLOURS[p],
        data: iterations.map((it) => d.phase_iterations.filter((x) => x.iteration === it && x.phase === p).reduce((s, x) => s + x.seconds, 0)),
      }))
      .filter((ds) => ds.data.some((v) => v > 0));
    drawChart(
      phasesBox,
      {
        type: 'bar',
        data: { labels: iterations.map(String), datasets },
        options: {
          plugins: { tooltip: { mode: 'index', callbacks: { label: (c) => `${c.dataset.label}: ${fmtSeconds(c.raw)}` } } },
          scales: { x: { stacked: true, title: axisTitle('iteration') }, y: valueAxis('time (s)', { stacked: true }) },
        },
      },
      datasets.reduce((n, ds) => n + ds.data.filter((v) => v > 0).length, 0),
    );
    const total = d.run.total_time || 0;
    const rows = phases.map((p) => ({ phase: PHASE_LABELS[p], seconds: d.phases[p], share: total && d.phases[p] !== null ? `${((100 * d.phases[p]) / total).toFixed(1)}%` : '' }));
    rows.push({ phase: 'total', seconds: d.run.total_time, share: '' });
    clear(phaseTable).append(table(['phase', 'seconds', 'share'], rows, { cell: (c, v) => (c === 'seconds' && typeof v === 'number' ? fmtSeconds(v) : v) }));
  }

  function drawSizes() {
    const cols = progress.columns;
    const ti = cols.indexOf('t');
    const datasets = LAYERS.map((l) => {
      const i = cols.indexOf(`${l}_vertices`);
      return {
        label: `${LAYER_STYLES[l].label} vertices`,
        data: progress.rows.filter((row) => row[i] > 0).map((row) => ({ x: row[ti], y: row[i] })),
        borderColor: LAYER_COLOURS[l],
        backgroundColor: LAYER_COLOURS[l],
        borderDash: LAYER_STYLES[l].dash,
        pointRadius: 2,
        stepped: 'before',
      };
    }).filter((ds) => ds.data.length > 0);
    drawChart(
      sizesBox,
      {
        type: 'line',
        data: { datasets },
        options: {
          plugins: { tooltip: { callbacks: { label: (c) => `${c.dataset.label}: ${fmtNumber(c.raw.y)} at ${fmtSeconds(c.raw.x)}` } } },
          scales: { x: { type: 'linear', title: axisTitle('time since the run started (s)') }, y: valueAxis('vertices (count, log scale)', { log: true }) },
        },
      },
      datasets.reduce((n, ds) => n + ds.data.length, 0),
    );
  }

  function renderTimeline(tl) {
    progress = tl.progress;
    drawSizes();
    const marks = [];
    for (const c of tl.constraints) marks.push({ x: c.t, y: MARK_ROWS.indexOf(c.kind), item: c, what: `${c.kind} constraint ${c.action}: ${c.content || ''}`, cause: c.conflict });
    for (const e of tl.expansions) marks.push({ x: e.t, y: 4, item: e, what: `expansion of ${e.object_label}: ${e.added || ''}`, cause: e.reason });
    const datasets = MARK_ROWS.map((row, k) => ({
      label: row,
      data: marks.filter((m) => m.y === k),
      backgroundColor: OKABE_ITO[k],
      borderColor: OKABE_ITO[k],
      pointStyle: k === 4 ? 'triangle' : 'circle',
      pointRadius: 5,
    })).filter((ds) => ds.data.length > 0);
    drawChart(
      marksBox,
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
            x: { type: 'linear', title: axisTitle('time since the run started (s)') },
            y: { min: -0.5, max: 4.5, title: axisTitle('kind'), ticks: { stepSize: 1, callback: (v) => MARK_ROWS[v] || '' } },
          },
        },
      },
      marks.length,
      'no constraints and no task space expansions in this run',
    );
    clear(constraintsBox);
    if (tl.constraints.length) {
      constraintsBox.append(
        el('h3', { text: `Constraints (${tl.constraints.length}${tl.truncated.constraints ? '+' : ''})` }),
        el('div', { class: 'table-wrap', style: 'max-height:260px' }, table(['t', 'iteration', 'kind', 'action', 'content', 'conflict'], tl.constraints, { cell: (c, v) => (c === 't' ? fmtSeconds(v) : v) })),
      );
    }
    if (tl.expansions.length) {
      constraintsBox.append(
        el('h3', { text: `Task space expansions (${tl.expansions.length})` }),
        el('div', { class: 'table-wrap', style: 'max-height:200px' }, table(['t', 'iteration', 'object_label', 'added', 'reason'], tl.expansions, { cell: (c, v) => (c === 't' ? fmtSeconds(v) : v) })),
      );
    }
    if (tl.additions.length) {
      constraintsBox.append(
        el(
          'details',
          {},
          el('summary', { text: 'What was added in each iteration' }),
          table(['iteration', 'layer', 'kind', 'added', 'removed', 't_first', 't_last'], tl.additions, { cell: (c, v) => (c.startsWith('t_') ? fmtSeconds(v) : v) }),
        ),
      );
    }
  }

  const events = { type: 'all', offset: 0, limit: 100 };
  async function loadEvents() {
    const d = await api.get(`/api/runs/${uuid}/events${query(events)}`);
    const typeSelect = el('select', {}, ['all', 'representation', 'constraint', 'task_space_expansion', 'phase', 'counter'].map((t) => el('option', { value: t, text: t, selected: t === events.type })));
    typeSelect.addEventListener('change', () => {
      events.type = typeSelect.value;
      events.offset = 0;
      loadEvents();
    });
    const prev = el('button', { type: 'button', class: 'small secondary', disabled: events.offset === 0, onclick: () => ((events.offset = Math.max(0, events.offset - events.limit)), loadEvents()) }, '‹ prev');
    const next = el('button', { type: 'button', class: 'small secondary', disabled: events.offset + events.limit >= d.total, onclick: () => ((events.offset += events.limit), loadEvents()) }, 'next ›');
    clear(eventsBox).append(
      el('div', { class: 'toolbar' }, typeSelect, prev, el('span', { class: 'muted', text: `${d.total ? events.offset + 1 : 0}–${Math.min(d.total, events.offset + events.limit)} of ${d.total}` }), next),
      el('div', { class: 'table-wrap', style: 'max-height:360px' }, table(['t', 'iteration', 'type', 'what', 'id', 'detail'], d.events, { cell: (c, v) => (c === 't' ? fmtSeconds(v) : v) })),
    );
  }

  async function loadViewer(d) {
    try {
      const [scene, models] = await Promise.all([api.get(`/api/runs/${uuid}/scene`), api.get('/api/robots')]);
      let plan = null;
      try {
        plan = await api.get(`/api/runs/${uuid}/plan`);
      } catch (e) {
        if (e.status !== 404) throw e;
      }
      const { PlanViewer } = await import('../viewer3d.js');
      viewer = new PlanViewer(viewerBox, scene, plan, models.models);
      viewerBox.dataset.ready = '1';
      viewerBox.dataset.hasPlan = plan ? '1' : '0';
      if (!plan) {
        viewerNote.textContent = `This run has no motion plan (${d.run.status}${d.settings && d.settings.task_only ? ', task only' : ''}): the robots stand at home.`;
        scrub.disabled = true;
        play.disabled = true;
      } else {
        viewerNote.textContent = `${scene.name}: ${scene.robots.length} robots, ${scene.objects.length} objects; makespan ${fmtNumber(viewer.player.duration)} s.`;
      }
    } catch (e) {
      viewerNote.textContent = '';
      viewerBox.append(errorBox(`3D view: ${e.message}`));
    }
  }

  function showTime(t) {
    if (!viewer) return;
    viewer.setTime(t);
    timeLabel.textContent = `t = ${viewer.time.toFixed(2)} s / ${viewer.player.duration.toFixed(2)} s`;
    scrub.value = String(Math.round((1000 * viewer.time) / Math.max(1e-9, viewer.player.duration)));
  }
  scrub.addEventListener('input', () => {
    if (viewer) showTime((Number(scrub.value) / 1000) * viewer.player.duration);
  });
  play.addEventListener('click', () => {
    if (!viewer) return;
    playing = !playing;
    play.textContent = playing ? 'Pause' : 'Play';
    if (!playing) return;
    if (viewer.time >= viewer.player.duration) showTime(0);
    let last = performance.now();
    const step = (now) => {
      if (!playing) return;
      showTime(viewer.time + ((now - last) / 1000) * Number(speed.value));
      last = now;
      if (viewer.time >= viewer.player.duration) {
        playing = false;
        play.textContent = 'Play';
        return;
      }
      raf = requestAnimationFrame(step);
    };
    raf = requestAnimationFrame(step);
  });

  async function loadDetail() {
    const d = await api.get(`/api/runs/${uuid}`);
    renderHeader(d);
    renderPhases(d);
    return d;
  }

  const offs = [
    on('sizes', (m) => {
      if (m.uuid !== uuid || !progress || m.t === null) return;
      const row = progress.columns.map((c) => m[c] ?? null);
      progress.rows.push(row);
      drawSizes();
    }),
    on('run', async (m) => {
      if (m.uuid !== uuid) return;
      const d = await loadDetail();
      renderTimeline(await api.get(`/api/runs/${uuid}/timeline`));
      if (d.run.status !== 'running' && !viewer) loadViewer(d);
    }),
  ];

  (async () => {
    try {
      const d = await loadDetail();
      renderTimeline(await api.get(`/api/runs/${uuid}/timeline`));
      await loadEvents();
      await loadViewer(d);
    } catch (e) {
      root.prepend(errorBox(e.message));
    }
  })();

  return () => {
    playing = false;
    cancelAnimationFrame(raf);
    offs.forEach((off) => off());
    destroyCharts(root);
    if (viewer) viewer.dispose();
  };
}
