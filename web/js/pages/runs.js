// Runs: every run in one sortable, filterable table (text filter: `planner = lazy-dash and robots >= 8
// and status = solved`), a column chooser, tags on the selected runs, CSV export of what is shown,
// and live updates as runs start and finish. Selected runs go to Compare's "diff only" view.
import { api, query } from '../api.js';
import { on, debounce } from '../events.js';
import { el, clear, badge, fmtNumber, fmtSeconds, errorBox } from '../dom.js';

const COLUMNS_KEY = 'dashbench.runs.columns';
export const SELECTED_KEY = 'dashbench.selected';

export function selectedRuns() {
  try {
    return JSON.parse(sessionStorage.getItem(SELECTED_KEY) || '[]');
  } catch {
    return [];
  }
}

function saveSelected(list) {
  sessionStorage.setItem(SELECTED_KEY, JSON.stringify(list));
}

export function mount(root, args) {
  const state = {
    columns: [],
    shown: null,
    filter: args[0] || '',
    sort: 'id',
    order: 'desc',
    limit: 50,
    offset: 0,
    total: 0,
    selected: new Set(selectedRuns()),
  };
  const filterInput = el('input', {
    type: 'text',
    value: state.filter,
    size: 70,
    placeholder: 'planner = lazy-dash and robots >= 8 and status = solved',
    'data-testid': 'filter',
  });
  const apply = el('button', { type: 'button', 'data-testid': 'apply-filter' }, 'Filter');
  const filterError = el('div', { class: 'error', 'data-testid': 'filter-error' });
  const columnsButton = el('button', { type: 'button', class: 'secondary' }, 'Columns');
  const columnsPanel = el('div', { class: 'columns-panel', hidden: true, 'data-testid': 'columns-panel' });
  const csvLink = el('a', { href: '#', download: 'runs.csv', 'data-testid': 'csv' }, 'Export CSV');
  const tagInput = el('input', { type: 'text', size: 14, placeholder: 'tag' });
  const tagAdd = el('button', { type: 'button', class: 'small' }, 'Tag selected');
  const tagRemove = el('button', { type: 'button', class: 'small secondary' }, 'Untag selected');
  const compareLink = el('a', { href: '#/compare', 'data-testid': 'compare-selected' }, 'Compare selected');
  const selectionInfo = el('span', { class: 'muted' });
  const tableBox = el('div', { class: 'table-wrap', 'data-testid': 'runs-table' });
  const pager = el('div', { class: 'pager' });
  const total = el('span', { class: 'muted', 'data-testid': 'runs-total' });

  root.append(
    el('h1', { text: 'Runs' }),
    el(
      'div',
      { class: 'panel' },
      el('div', { class: 'toolbar' }, filterInput, apply, columnsButton, csvLink, total),
      el(
        'div',
        { class: 'muted' },
        'Filter: FIELD OP VALUE joined by "and"; OP is = != < <= > >= ~ (contains) !~. Fields are the columns (parameters too) and tag.',
      ),
      filterError,
      columnsPanel,
      el('div', { class: 'toolbar' }, tagInput, tagAdd, tagRemove, compareLink, selectionInfo),
      tableBox,
      pager,
    ),
  );

  function updateSelectionInfo() {
    selectionInfo.textContent = state.selected.size ? `${state.selected.size} selected` : '';
    saveSelected([...state.selected]);
  }

  function shownColumns() {
    if (state.shown) return state.columns.filter((c) => state.shown.includes(c.name));
    return state.columns.filter((c) => c.shown);
  }

  function renderColumnsPanel() {
    clear(columnsPanel);
    const names = shownColumns().map((c) => c.name);
    for (const c of state.columns) {
      const box = el('input', { type: 'checkbox', checked: names.includes(c.name), 'data-column': c.name });
      box.addEventListener('change', () => {
        state.shown = [...columnsPanel.querySelectorAll('input:checked')].map((i) => i.dataset.column);
        localStorage.setItem(COLUMNS_KEY, JSON.stringify(state.shown));
        load();
      });
      columnsPanel.append(el('label', { title: c.name }, box, `${c.label}`));
    }
  }

  function cell(col, value, run) {
    if (col.name === 'status') return badge(value);
    if (col.name === 'uuid' || col.name === 'id') {
      return el('a', { href: `#/run/${run.uuid}`, class: 'mono', text: col.name === 'uuid' ? value.slice(0, 8) : String(value) });
    }
    if (col.name === 'tags') return el('span', {}, (value ? value.split(',') : []).map((t) => el('span', { class: 'chip', text: t })));
    if (value === null || value === undefined) return el('span', { class: 'muted', text: '' });
    if (typeof value === 'number') return document.createTextNode(col.group === 'time' ? fmtSeconds(value) : fmtNumber(value, 4));
    return document.createTextNode(String(value));
  }

  function render(list) {
    const cols = shownColumns();
    const head = el(
      'tr',
      {},
      el('th', {}, ''),
      cols.map((c) => {
        const th = el('th', { class: `sortable ${state.sort === c.name ? `sorted-${state.order}` : ''}`, title: c.name, text: c.label });
        th.addEventListener('click', () => {
          state.order = state.sort === c.name && state.order === 'desc' ? 'asc' : 'desc';
          state.sort = c.name;
          state.offset = 0;
          load();
        });
        return th;
      }),
    );
    const body = el(
      'tbody',
      {},
      list.runs.map((r) => {
        const box = el('input', { type: 'checkbox', checked: state.selected.has(r.uuid), title: 'select' });
        box.addEventListener('change', () => {
          if (box.checked) state.selected.add(r.uuid);
          else state.selected.delete(r.uuid);
          updateSelectionInfo();
        });
        return el(
          'tr',
          { 'data-uuid': r.uuid, 'data-status': r.status },
          el('td', {}, box),
          cols.map((c) => el('td', { class: typeof r[c.name] === 'number' ? 'num' : '' }, cell(c, r[c.name], r))),
        );
      }),
    );
    clear(tableBox).append(el('table', { class: 'data' }, el('thead', {}, head), body));
    total.textContent = `${list.total} runs`;
    total.dataset.total = list.total;
    clear(pager);
    const pages = Math.max(1, Math.ceil(list.total / state.limit));
    const page = Math.floor(state.offset / state.limit) + 1;
    const prev = el('button', { type: 'button', class: 'small secondary', disabled: page <= 1 }, '‹ prev');
    const next = el('button', { type: 'button', class: 'small secondary', disabled: page >= pages }, 'next ›');
    prev.addEventListener('click', () => {
      state.offset = Math.max(0, state.offset - state.limit);
      load();
    });
    next.addEventListener('click', () => {
      state.offset += state.limit;
      load();
    });
    const size = el('select', {}, [25, 50, 100, 250, 1000].map((n) => el('option', { value: n, text: `${n} per page`, selected: n === state.limit })));
    size.addEventListener('change', () => {
      state.limit = Number(size.value);
      state.offset = 0;
      load();
    });
    pager.append(prev, el('span', { text: `page ${page} of ${pages}` }), next, size);
  }

  function params() {
    return { q: state.filter, sort: state.sort, order: state.order };
  }

  async function load() {
    csvLink.href = `/api/runs.csv${query({ ...params(), columns: shownColumns().map((c) => c.name).join(',') })}`;
    try {
      const list = await api.get(`/api/runs${query({ ...params(), limit: state.limit, offset: state.offset })}`);
      filterError.textContent = '';
      filterInput.classList.remove('invalid');
      render(list);
    } catch (e) {
      filterError.textContent = e.message;
      filterInput.classList.add('invalid');
    }
  }

  async function tagSelected(add) {
    const tag = tagInput.value.trim();
    if (!tag || state.selected.size === 0) return;
    try {
      for (const uuid of state.selected) {
        await api.post(`/api/runs/${uuid}/tags`, add ? { add: [tag] } : { remove: [tag] });
      }
      load();
    } catch (e) {
      filterError.textContent = e.message;
    }
  }

  apply.addEventListener('click', () => {
    state.filter = filterInput.value.trim();
    state.offset = 0;
    history.replaceState(null, '', `#/runs/${encodeURIComponent(state.filter)}`);
    load();
  });
  filterInput.addEventListener('keydown', (e) => {
    if (e.key === 'Enter') apply.click();
  });
  columnsButton.addEventListener('click', () => {
    columnsPanel.hidden = !columnsPanel.hidden;
  });
  tagAdd.addEventListener('click', () => tagSelected(true));
  tagRemove.addEventListener('click', () => tagSelected(false));

  const reload = debounce(load, 500);
  const offs = [on('run', reload), on('resync', reload)];

  (async () => {
    try {
      const cols = await api.get('/api/runs/columns');
      state.columns = cols.columns;
      const saved = JSON.parse(localStorage.getItem(COLUMNS_KEY) || 'null');
      if (Array.isArray(saved)) state.shown = saved.filter((n) => state.columns.some((c) => c.name === n));
      if (state.shown && state.shown.length === 0) state.shown = null;
      renderColumnsPanel();
      updateSelectionInfo();
      await load();
    } catch (e) {
      root.append(errorBox(e.message));
    }
  })();
  return () => offs.forEach((off) => off());
}
