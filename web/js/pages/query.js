// Query: a read-only SQL console on the results database (the same guards as `dashbench db query`:
// writes, ATTACH, transactions and setting PRAGMAs are refused), with saved example queries. The
// statement is in the URL (#/query?sql=...), and the result downloads as CSV.
import { api } from '../api.js';
import { el, clear, fmtNumber } from '../dom.js';
import { toCsv, download } from '../export.js';
import { writeState, readString } from '../url_state.js';

const LAST_KEY = 'dashbench.query.last';

export function mount(root, args, params = new URLSearchParams()) {
  const sql = el('textarea', { rows: 7, 'data-testid': 'sql', spellcheck: 'false' });
  sql.value = readString(params, 'sql') || localStorage.getItem(LAST_KEY) || 'SELECT status, count(*) AS runs FROM dash_runs GROUP BY status';
  let last = null; // the last result, for the CSV
  const csv = el('button', { type: 'button', class: 'secondary', disabled: true, 'data-testid': 'query-csv', title: 'the rows shown, as CSV' }, 'Download CSV');
  csv.addEventListener('click', () => last && download('query.csv', toCsv(last.columns, last.rows), 'text/csv'));
  const run = el('button', { type: 'button', 'data-testid': 'run-query' }, 'Run (Ctrl+Enter)');
  const maxRows = el('select', {}, [100, 1000, 10000].map((n) => el('option', { value: n, text: `at most ${n} rows`, selected: n === 1000 })));
  const status = el('div', { 'data-testid': 'query-status' });
  const result = el('div', { class: 'table-wrap', 'data-testid': 'query-result' });
  const examples = el('ul', { class: 'examples' });
  root.append(
    el('h1', { text: 'Query' }),
    el(
      'div',
      { class: 'row' },
      el(
        'div',
        { class: 'panel grow', style: 'flex:3' },
        el('div', { class: 'muted', text: 'One read-only SQL statement over the results database. Tables: dash_runs, dash_events, dash_constraints, dash_expansions, dash_phases, dash_counters, dash_progress, dash_batches, dash_run_tags; views: dash_timeline and Planner Arena\u2019s experiments, plannerConfigs, runs, progress.' }),
        sql,
        el('div', { class: 'toolbar', style: 'margin-top:6px' }, run, maxRows, csv, status),
        result,
      ),
      el('div', { class: 'panel grow', style: 'flex:1' }, el('h2', { text: 'Examples' }), examples),
    ),
  );

  async function execute() {
    localStorage.setItem(LAST_KEY, sql.value);
    writeState({ sql: sql.value.length <= 4000 ? sql.value : '' });
    last = null;
    csv.disabled = true;
    status.className = 'muted';
    status.textContent = 'running…';
    clear(result);
    const started = performance.now();
    try {
      const r = await api.post('/api/query', { sql: sql.value, max_rows: Number(maxRows.value) }, { auth: false });
      const ms = (performance.now() - started).toFixed(0);
      status.className = 'ok';
      status.textContent = `${r.rows.length} rows${r.truncated ? ' (stopped at the row limit)' : ''} in ${ms} ms`;
      last = r;
      csv.disabled = false;
      const head = el('tr', {}, r.columns.map((c) => el('th', { text: c })));
      const body = el(
        'tbody',
        {},
        r.rows.map((row) => el('tr', {}, row.map((v) => el('td', { class: typeof v === 'number' ? 'num' : '', text: v === null ? 'NULL' : typeof v === 'number' ? fmtNumber(v, 6) : String(v) })))),
      );
      result.append(el('table', { class: 'data' }, el('thead', {}, head), body));
    } catch (e) {
      status.className = 'error';
      status.textContent = e.message.replace(/^(refused:\s*)+/i, 'refused: ');
    }
  }
  run.addEventListener('click', execute);
  sql.addEventListener('keydown', (e) => {
    if (e.key === 'Enter' && (e.ctrlKey || e.metaKey)) {
      e.preventDefault();
      execute();
    }
  });
  api
    .get('/api/query/examples')
    .then((r) => {
      for (const ex of r.examples) {
        examples.append(
          el(
            'li',
            {},
            el('a', {
              text: ex.title,
              onclick: () => {
                sql.value = ex.sql;
                execute();
              },
            }),
          ),
        );
      }
    })
    .catch((e) => examples.append(el('li', { class: 'error', text: e.message })));
  if (params.get('sql')) execute();
  return null;
}
