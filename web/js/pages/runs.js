// Runs: every run in one sortable, filterable table (text filter: `planner = lazy-dash and (robots = 4
// or robots = 8) and status = solved`), a column chooser, tags on the selected runs, CSV export of
// what is shown, and live updates as runs start and finish. Filter, sort and page are in the URL
// (#/runs?q=...&sort=total_time&order=asc). Selected runs go to Compare (plots and side by side).
import { api, query } from '../api.js';
import { on, debounce } from '../events.js';
import { el, clear, badge, fmtNumber, fmtSeconds, errorBox, plural } from '../dom.js';
import { writeState, readString, readNumber, readList } from '../url_state.js';

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

const PAGE_SIZES = [25, 50, 100, 250, 1000];
const MAX_COMPARE_SELECTION = 40; // runs a "compare selected" link names one by one
const MAX_URL_SELECTION = 50; // selected runs kept in the URL

export function mount(root, args, urlParams = new URLSearchParams()) {
  const state = {
    columns: [],
    shown: null,
    filter: readString(urlParams, 'q', args[0] || ''),
    sort: readString(urlParams, 'sort', 'id'),
    order: readString(urlParams, 'order', 'desc') === 'asc' ? 'asc' : 'desc',
    limit: PAGE_SIZES.includes(readNumber(urlParams, 'limit', 50)) ? readNumber(urlParams, 'limit', 50) : 50,
    offset: Math.max(0, Math.floor(readNumber(urlParams, 'offset', 0))),
    total: 0,
    selected: new Set(urlParams.has('sel') ? readList(urlParams, 'sel').slice(0, MAX_URL_SELECTION) : selectedRuns()),
    families: new Map(), // uuid -> family of the runs seen, for the compare link
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
        'Filter: FIELD OP VALUE joined by "and" and "or", grouped with ( ); OP is = != < <= > >= ~ (contains) !~. Fields are the columns (parameters too) and tag. Click or press Enter on a column header to sort.',
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
    saveState();
    const uuids = [...state.selected];
    const family = state.families.get(uuids[0]);
    let href = `#/compare?runs=${uuids.slice(0, 50).join(',')}`;
    if (uuids.length && uuids.length <= MAX_COMPARE_SELECTION) {
      href += `&q=${encodeURIComponent(uuids.map((u) => `uuid = "${u}"`).join(' or '))}`;
      if (family) href += `&family=${encodeURIComponent(family)}`;
    }
    compareLink.href = href;
  }

  // A load (or a debounced reload) that ends after the page was left must not write its state into
  // the next page's URL (the Compare link lost its ?batch= that way).
  let mounted = true;
  function saveState() {
    if (!mounted) return;
    const sel = [...state.selected];
    writeState({ q: state.filter, sort: state.sort, order: state.order, limit: state.limit, offset: state.offset, sel: sel.length <= MAX_URL_SELECTION ? sel : [] }, { sort: 'id', order: 'desc', limit: 50, offset: 0 });
  }

  /// The chosen columns; by default the usual ones, less parameters that none of the listed runs has
  /// (a parameter of another family) so that the table fits the screen.
  function shownColumns(list = state.lastList) {
    if (state.shown) return state.columns.filter((c) => state.shown.includes(c.name));
    return state.columns.filter((c) => c.shown && (c.group !== 'param' || !list || list.runs.some((r) => r[c.name] !== null && r[c.name] !== undefined)));
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

  /// A column's header: its label less what the cells say themselves (durations carry their unit,
  /// "9.8 ms", so "total time", not "total time (s)"); the run id is "id" (the label is its title).
  function headerText(col) {
    if (col.name === 'id') return 'id';
    return col.group === 'time' ? col.label.replace(/\s*\(s\)$/, '') : col.label;
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
        const sorted = state.sort === c.name;
        const th = el('th', {
          class: `sortable ${sorted ? `sorted-${state.order}` : ''}`,
          title: `${c.label} (${c.name}): click or Enter to sort`,
          text: headerText(c),
          tabindex: 0,
          'data-column': c.name,
          'aria-sort': sorted ? (state.order === 'asc' ? 'ascending' : 'descending') : 'none',
        });
        const sortBy = () => {
          state.order = state.sort === c.name && state.order === 'desc' ? 'asc' : 'desc';
          state.sort = c.name;
          state.offset = 0;
          state.focus = c.name;
          load();
        };
        th.addEventListener('click', sortBy);
        th.addEventListener('keydown', (e) => {
          if (e.key === 'Enter' || e.key === ' ') {
            e.preventDefault();
            sortBy();
          }
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
    if (state.focus) {
      tableBox.querySelector(`th[data-column="${state.focus}"]`)?.focus();
      state.focus = null;
    }
    for (const r of list.runs) state.families.set(r.uuid, r.family);
    updateSelectionInfo();
    total.textContent = plural(list.total, 'run');
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
    const size = el('select', {}, PAGE_SIZES.map((n) => el('option', { value: n, text: `${n} per page`, selected: n === state.limit })));
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

  // Answers can come back out of order (a slow query for the previous filter after the new one's):
  // only the latest request's answer is shown.
  let latestLoad = 0;
  async function load() {
    if (!mounted) return;
    saveState();
    const mine = ++latestLoad;
    try {
      const list = await api.get(`/api/runs${query({ ...params(), limit: state.limit, offset: state.offset })}`);
      if (!mounted || mine !== latestLoad) return;
      state.lastList = list;
      csvLink.href = `/api/runs.csv${query({ ...params(), columns: shownColumns(list).map((c) => c.name).join(',') })}`;
      filterError.textContent = '';
      filterInput.classList.remove('invalid');
      render(list);
    } catch (e) {
      if (!mounted || mine !== latestLoad) return;
      // No table under an error: the old rows would look like the answer to the new filter.
      state.lastList = null;
      filterError.textContent = e.message;
      filterInput.classList.add('invalid');
      clear(tableBox);
      clear(pager);
      total.textContent = '';
      delete total.dataset.total;
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
  return () => {
    mounted = false;
    offs.forEach((off) => off());
  };
}
