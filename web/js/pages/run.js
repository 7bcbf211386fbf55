// Run detail: one run's metadata, tags and note, links to its batch and downloads of its scene and
// plan; its phase breakdown; a timeline of what the planner added when (representation sizes over
// time, constraints with the conflict that caused each, task space expansions); its events, paged;
// and a 3D view of its plan with a time scrubber. Other runs can be overlaid (#/run/UUID?overlay=A,B):
// their sizes and marks join the plots and the first one's plan plays beside this one on the same
// clock. A running run's sizes grow live, and its plan appears when it ends. Keys: Space plays or
// pauses, arrows step 1 % (Shift: to the next plan point), Enter in the tag box adds the tag.
import { api, query } from '../api.js';
import { on } from '../events.js';
import { el, clear, badge, fmtNumber, fmtSeconds, fmtWork, paramsText, plannerLine, errorBox, table } from '../dom.js';
import { destroyCharts, chartPanel } from '../charts.js';
import { LAYER_STYLES } from '../palette.js';
import { drawSizesOverTime, drawMarks, LAYERS } from '../run_timeline.js';
import { readList, readNumber, readString, writeState } from '../url_state.js';
import { PlaybackControls } from '../run_playback.js';
import { mountRunDispatch } from './run_dispatch.js';
import { drawPhaseBreakdown, PHASES_HELP } from '../run_phases.js';

const MAX_OVERLAYS = 5;
// The paper's names of the representations (Lazy-DaSH, Sec. III) in the run's "sizes" line.
const SIZES_HELP = 'H_T: task space hypergraph · H_TE: task-extended hypergraph (the task plan search) · H_M: motion hypergraph · H_ME: motion-extended hypergraph (the motion query)';
const UUID_RE = /^[0-9A-Fa-f-]{8,64}$/;

const PICK_PAGE = 50;

/// Without a run in the URL: every run, newest first, a page at a time (numeric ids, durations with
/// their units); the Runs page filters and sorts them.
async function pickRun(root) {
  root.append(el('h1', { text: 'Run detail' }), el('p', {}, 'Pick a run, or filter and sort them on the ', el('a', { href: '#/runs', text: 'Runs page' }), '.'));
  const box = el('div', { class: 'panel', 'data-testid': 'run-picker' });
  root.append(box);
  const columns = ['id', 'family', 'parameters', 'config', 'status', 'total time', 'makespan'];
  const show = async (offset) => {
    const list = await api.get(`/api/runs${query({ limit: PICK_PAGE, offset, sort: 'id', order: 'desc' })}`);
    const rows = list.runs.map((r) => ({ ...r, parameters: paramsText(r.params), 'total time': fmtSeconds(r.total_time), makespan: typeof r.makespan === 'number' ? `${fmtNumber(r.makespan)} s` : '' }));
    const prev = el('button', { type: 'button', class: 'small secondary', disabled: offset === 0, onclick: () => show(Math.max(0, offset - PICK_PAGE)) }, '‹ newer');
    const next = el('button', { type: 'button', class: 'small secondary', disabled: offset + PICK_PAGE >= list.total, onclick: () => show(offset + PICK_PAGE) }, 'older ›');
    const shown = list.total ? `runs ${offset + 1}–${offset + list.runs.length} of ${list.total}, newest first` : 'no runs yet';
    clear(box).append(
      el('div', { class: 'pager', 'data-testid': 'run-picker-pager', 'data-total': list.total }, prev, el('span', { text: shown }), next),
      el('div', { class: 'table-wrap' }, table(columns, rows, {
        cell: (c, v, r) => (c === 'id' ? el('a', { href: `#/run/${r.uuid}`, title: r.uuid, text: String(v) }) : c === 'status' ? badge(v) : v),
      })),
    );
  };
  await show(0);
}

export function mount(root, args, params = new URLSearchParams()) {
  const uuid = args[0];
  if (!uuid) {
    pickRun(root).catch((e) => root.append(errorBox(e.message)));
    return null;
  }
  let overlays = readList(params, 'overlay').filter((u) => UUID_RE.test(u) && u !== uuid).slice(0, MAX_OVERLAYS);
  let viewer = null;
  let overlayViewer = null;
  let viewerStatus = null; // the run status the 3D view was built for
  let progress = null; // the timeline's size series, extended live
  let timeline = null;
  let detail = null;
  // A long phase's latest progress (conflict resolution: steps scheduled of the plan's), live.
  const workLine = el('span', { 'data-testid': 'run-work', text: '—' });
  const showWork = (w) => {
    workLine.textContent = fmtWork(w, { ended: true }) || '—';
  };
  const others = new Map(); // overlaid uuid -> {progress, timeline, end}
  // The URL keeps the overlays, the plan time and the events shown (#/run/UUID?overlay=A&t=12.5&events=constraint).
  const view = { t: Math.max(0, readNumber(params, 't', 0)), events: readString(params, 'events', 'all'), offset: Math.max(0, Math.floor(readNumber(params, 'offset', 0))) };
  const saveView = () => writeState({ overlay: overlays, t: view.t > 0 ? view.t.toFixed(2) : '', events: view.events, offset: view.offset }, { events: 'all', offset: 0 });
  const playback = new PlaybackControls((t) => {
    view.t = t;
    saveView();
  });

  const header = el('div', { class: 'panel', 'data-testid': 'run-header' });
  const phases = chartPanel({ title: 'Phase breakdown', testid: 'chart-phases', name: `run-${uuid.slice(0, 8)}-phases`, help: PHASES_HELP });
  const phaseTable = el('div', {});
  phases.panel.append(phaseTable);
  const sizes = chartPanel({ title: 'Representation sizes over time', testid: 'chart-timeline', name: `run-${uuid.slice(0, 8)}-sizes`, help: 'Vertices and hyperarcs (choose below) of each representation at each stored progress snapshot (log scale); overlaid runs in their own colours, layers by line style.' });
  const marks = chartPanel({ title: 'Timeline: constraints and expansions', testid: 'chart-marks', name: `run-${uuid.slice(0, 8)}-constraints`, help: 'Each mark is a constraint (by kind) or a task space expansion; hover for what it says and the conflict that caused it.' });
  marks.box.style.height = '260px';
  const constraintsBox = el('div', {});
  marks.panel.append(constraintsBox);
  const overlayInput = el('input', { type: 'text', size: 44, placeholder: 'uuids of runs to overlay, comma separated', 'data-testid': 'overlay-input', value: overlays.join(', ') });
  const overlayApply = el('button', { type: 'button', class: 'small', 'data-testid': 'overlay-apply' }, 'Overlay');
  const overlayStatus = el('span', { class: 'error', 'data-testid': 'overlay-status' });
  const eventsBox = el('div', { 'data-testid': 'events' });
  const viewerBox = el('div', { class: 'viewer', 'data-testid': 'viewer' });
  const overlayBox = el('div', { class: 'viewer', 'data-testid': 'viewer-overlay', hidden: true });
  const viewers = el('div', { class: 'viewers' }, viewerBox, overlayBox);
  const viewerNote = el('div', { class: 'muted', 'data-testid': 'viewer-note' });
  const planHeading = el('h2', { 'data-testid': 'plan-heading', text: 'Plan in 3D' });
  // The 3D view's code starts loading now, while the run's data comes (not after it).
  const viewerModule = import('../viewer3d.js');
  viewerModule.catch(() => {}); // reported where it is used
  // "Dispatch this plan" (run_dispatch.js), below the plan it would send.
  const dispatchSlot = el('div', { 'data-testid': 'run-dispatch-slot' });

  root.append(
    header,
    el('div', { class: 'panel toolbar' }, el('strong', { text: 'Overlay other runs' }), overlayInput, overlayApply, overlayStatus),
    el('div', { class: 'grid2' }, phases.panel, sizes.panel),
    marks.panel,
    el(
      'div',
      { class: 'panel' },
      planHeading,
      viewerNote,
      viewers,
      playback.element,
      el('div', { class: 'muted', text: 'Drag to orbit, scroll to zoom, right-drag to pan. Space plays or pauses; ← → step 1 %, Shift+← → to the next plan point. Robots are drawn from their collision bodies (data/robots); outlines mark object goals.' }),
    ),
    dispatchSlot,
    el('div', { class: 'panel' }, el('h2', { text: 'Events' }), eventsBox),
  );
  // "Dispatch this plan" only for a run that has a plan (a timed-out run has none to send).
  let dispatchMounted = false;
  function showDispatch(d) {
    if (dispatchMounted || !d.run.has_plan) return;
    dispatchMounted = true;
    mountRunDispatch(dispatchSlot, uuid);
  }

  function renderHeader(d) {
    const r = d.run;
    const tags = el('span', { 'data-testid': 'tags' });
    for (const t of d.tags) {
      tags.append(el('span', { class: 'chip' }, t, el('button', { type: 'button', title: `remove ${t}`, onclick: () => editTags([], [t]) }, '×')));
    }
    const tagInput = el('input', { type: 'text', size: 12, placeholder: 'new tag (Enter)', 'data-testid': 'tag-input' });
    const tagAdd = el('button', { type: 'button', class: 'small', 'data-testid': 'tag-add' }, 'Add tag');
    const addTag = () => tagInput.value.trim() && editTags([tagInput.value.trim()], []);
    tagAdd.addEventListener('click', addTag);
    tagInput.addEventListener('keydown', (e) => {
      if (e.key === 'Enter') {
        e.preventDefault();
        addTag();
      }
    });
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
    const batch = r.batch
      ? el(
          'span',
          {},
          el('a', { href: `#/runs?q=${encodeURIComponent(`batch = "${r.batch}"`)}`, 'data-testid': 'batch-link', class: 'mono', text: r.batch }),
          ' · ',
          el('a', { href: `#/compare?family=${encodeURIComponent(r.family)}&batch=${encodeURIComponent(r.batch)}`, text: 'compare this batch' }),
        )
      : '—';
    const downloads = el(
      'span',
      {},
      el('a', { href: `/api/runs/${uuid}/scene`, download: `scene-${uuid.slice(0, 8)}.json`, 'data-testid': 'download-scene' }, 'scene JSON'),
      r.has_plan
        ? [' · ', el('a', { href: `/api/runs/${uuid}/plan`, download: `plan-${uuid.slice(0, 8)}.json`, 'data-testid': 'download-plan' }, 'plan JSON'), ' · ', el('a', { href: `#/dispatch?run=${uuid}`, 'data-testid': 'dispatch-link' }, 'dispatch this plan to arms')]
        : el('span', { class: 'muted', text: ' · no plan' }),
    );
    const kv = [
      ['uuid', r.uuid],
      ['status', r.status],
      ['family', `${r.family}  ${paramsText(d.params)}  seed ${r.seed}`],
      ['planner', plannerLine(r, d.settings)],
      ['batch', batch],
      ['scene', r.scene || '—'],
      ['total time', el('span', { 'data-testid': 'run-total-time' }, r.total_time === null ? '—' : fmtSeconds(r.total_time), typeof r.wall_time === 'number' ? el('span', { class: 'muted', text: ` (the sum of the phases; wall time ${fmtSeconds(r.wall_time)})` }) : '')],
      ['makespan', r.makespan === null ? '—' : `${fmtNumber(r.makespan)} s`],
      ['scheduling', workLine],
      [
        'sizes (vertices/hyperarcs)',
        el(
          'span',
          { 'data-testid': 'run-sizes' },
          LAYERS.map((l) => `${LAYER_STYLES[l].label} ${fmtNumber(r[`${l}_vertices`])}/${fmtNumber(r[`${l}_hyperarcs`])}`).join('  '),
          el('div', { class: 'muted', style: 'font: 12px/1.4 system-ui, sans-serif; word-break: normal', text: SIZES_HELP }),
        ),
      ],
      ['events', Object.entries(d.event_counts).map(([k, v]) => `${k} ${v}`).join(', ')],
      ['download', downloads],
    ];
    if (r.error) kv.push(['error', r.error]);
    clear(header).append(
      el('h1', {}, 'Run ', el('span', { class: 'mono', text: r.uuid.slice(0, 8) }), ' ', badge(r.status)),
      el('dl', { class: 'kv' }, kv.map(([k, v]) => [el('dt', { text: k }), el('dd', {}, v instanceof Node ? v : String(v))])),
      el('div', { class: 'toolbar', style: 'margin-top:8px' }, tags, tagInput, tagAdd),
      el('div', { class: 'toolbar' }, note, noteSave, noteStatus),
    );
  }

  async function editTags(add, remove) {
    try {
      await api.post(`/api/runs/${uuid}/tags`, { add, remove });
      await loadDetail();
      header.querySelector('[data-testid=tag-input]')?.focus();
    } catch (e) {
      header.append(errorBox(e.message));
    }
  }

  function runEnd() {
    return detail && typeof detail.run.total_time === 'number' ? detail.run.total_time : 0;
  }

  function drawTimelines() {
    if (!progress || !timeline) return;
    const list = overlays.filter((u) => others.has(u)).map((u) => ({ uuid: u, ...others.get(u) }));
    drawSizesOverTime(sizes.box, [{ uuid, progress, end: runEnd() }, ...list]);
    drawMarks(marks.box, [{ uuid, timeline, end: runEnd() }, ...list]);
  }

  function renderTimeline(tl) {
    timeline = tl;
    progress = tl.progress;
    const last = progress.rows[progress.rows.length - 1];
    if (last) {
      const col = (c) => last[progress.columns.indexOf(c)];
      showWork({ phase: col('progress_phase'), done: col('progress_done'), total: col('progress_total'), rate: col('progress_rate'), current: col('progress_current') });
    }
    drawTimelines();
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

  async function loadOverlays() {
    overlayStatus.textContent = '';
    saveView();
    const failed = [];
    await Promise.all(
      overlays.map(async (u) => {
        if (others.has(u)) return;
        try {
          const [d, tl] = await Promise.all([api.get(`/api/runs/${u}`), api.get(`/api/runs/${u}/timeline`)]);
          others.set(u, { progress: tl.progress, timeline: tl, end: d.run.total_time || 0, detail: d });
        } catch (e) {
          failed.push(`${u.slice(0, 8)}: ${e.message}`);
        }
      }),
    );
    overlays = overlays.filter((u) => others.has(u));
    overlayStatus.textContent = failed.join('; ');
    drawTimelines();
  }

  const EVENT_TYPES = ['all', 'representation', 'constraint', 'task_space_expansion', 'phase', 'counter'];
  const events = { type: EVENT_TYPES.includes(view.events) ? view.events : 'all', offset: view.offset, limit: 100 };
  async function loadEvents() {
    view.events = events.type;
    view.offset = events.offset;
    saveView();
    const d = await api.get(`/api/runs/${uuid}/events${query(events)}`);
    const typeSelect = el('select', { 'data-testid': 'events-type' }, EVENT_TYPES.map((t) => el('option', { value: t, text: t, selected: t === events.type })));
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

  /// A viewer of run `id` in `box`; plan only when the run has one (no request that must fail).
  async function buildViewer(box, id, run, stale = () => false) {
    const [scene, models] = await Promise.all([api.get(`/api/runs/${id}/scene`), api.get('/api/robots')]);
    const plan = run.has_plan ? await api.get(`/api/runs/${id}/plan`) : null;
    const { PlanViewer } = await viewerModule;
    if (stale()) return null;
    if (box === viewerBox && viewer) {
      viewer.dispose();
      viewer = null;
    }
    clear(box);
    const v = new PlanViewer(box, scene, plan, models.models);
    box.dataset.ready = '1';
    box.dataset.hasPlan = plan ? '1' : '0';
    return { viewer: v, scene, plan };
  }

  let viewerSeq = 0; // the latest loadViewer wins (a run that ends while its page is loading)
  async function loadViewer(d) {
    const seq = ++viewerSeq;
    viewerStatus = d.run.status;
    try {
      const built = await buildViewer(viewerBox, uuid, d.run, () => seq !== viewerSeq);
      if (!built) return;
      viewer = built.viewer; // buildViewer disposed the one before
      planHeading.textContent = built.plan ? 'Plan in 3D' : 'Scene in 3D (no plan)';
      playback.element.hidden = !built.plan;
      let note = built.plan
        ? `${built.scene.name}: ${built.scene.robots.length} robots, ${built.scene.objects.length} objects; makespan ${fmtNumber(viewer.player.duration)} s.`
        : `This run has no motion plan (${d.run.status}${d.settings && d.settings.task_only ? ', task only' : ''}): the robots stand at home.${d.run.status === 'running' ? ' The plan appears here when the run ends.' : ''}`;
      if (overlayViewer) overlayViewer.dispose();
      overlayViewer = null;
      overlayBox.hidden = true;
      const first = overlays.find((u) => others.get(u)?.detail?.run.has_plan);
      if (first) {
        overlayBox.hidden = false;
        const o = await buildViewer(overlayBox, first, others.get(first).detail.run, () => seq !== viewerSeq);
        if (!o) return;
        overlayViewer = o.viewer;
        note += ` Right: ${first.slice(0, 8)} (makespan ${fmtNumber(overlayViewer.player.duration)} s), on the same clock.`;
      }
      viewerNote.textContent = note;
      playback.setViewers([viewer, overlayViewer], view.t);
    } catch (e) {
      viewerNote.textContent = '';
      viewerBox.append(errorBox(`3D view: ${e.message}`));
    }
  }

  async function loadDetail() {
    const d = await api.get(`/api/runs/${uuid}`);
    detail = d;
    renderHeader(d);
    showDispatch(d);
    drawPhaseBreakdown(phases.box, phaseTable, d);
    return d;
  }

  overlayApply.addEventListener('click', async () => {
    overlays = overlayInput.value.split(/[\s,]+/).map((s) => s.trim()).filter((u) => UUID_RE.test(u) && u !== uuid).slice(0, MAX_OVERLAYS);
    await loadOverlays();
    overlayInput.value = overlays.join(', ');
    if (detail) await loadViewer(detail);
  });
  overlayInput.addEventListener('keydown', (e) => e.key === 'Enter' && overlayApply.click());

  const offs = [
    on('sizes', (m) => {
      if (m.uuid !== uuid || !progress || m.t === null || m.t === undefined) return;
      showWork({ phase: m.progress_phase, done: m.progress_done, total: m.progress_total, rate: m.progress_rate, current: m.progress_current });
      const ti = progress.columns.indexOf('t');
      const last = progress.rows[progress.rows.length - 1];
      if (last && last[ti] >= m.t) return; // the same snapshot again (its event count changed)
      progress.rows.push(progress.columns.map((c) => m[c] ?? null));
      drawTimelines();
    }),
    on('run', async (m) => {
      if (m.uuid !== uuid) return;
      const d = await loadDetail();
      renderTimeline(await api.get(`/api/runs/${uuid}/timeline`));
      if (d.run.status !== 'running') loadEvents().catch(() => {}); // the events written since
      // A run opened while running: build the 3D view again once it has ended (with its plan).
      if (d.run.status !== 'running' && viewerStatus !== d.run.status) await loadViewer(d);
    }),
  ];

  (async () => {
    try {
      const d = await loadDetail();
      if (overlays.length) await loadOverlays();
      // The 3D view builds while the timeline and the events load (it used to wait for both).
      await Promise.all([
        loadViewer(detail || d),
        (async () => {
          renderTimeline(await api.get(`/api/runs/${uuid}/timeline`));
          await loadEvents();
        })(),
      ]);
    } catch (e) {
      root.prepend(errorBox(e.message));
    }
  })();

  return () => {
    playback.dispose();
    offs.forEach((off) => off());
    destroyCharts(root);
    if (viewer) viewer.dispose();
    if (overlayViewer) overlayViewer.dispose();
  };
}
