// The Compare page's paired statistics of two configurations on the same scenes and seeds: per size
// (and split value) and over all of them, the seed-paired time ratio with its 95 % t interval, the
// sign test on Gehan's pair scores with unsolved runs censored at their time limit, and each side's
// success rate with its 95 % Wilson interval (definitions: paired_stats.js). A table, since each row
// is a test, with its CSV; the same numbers as `dashbench report`'s "Paired comparison".
import { el, clear, fmtNumber } from './dom.js';
import { toCsv, download, fileStem } from './export.js';
import { scenePairs } from './compare_data.js';
import { pairedStats, observation } from './paired_stats.js';

export const STATS_COLUMNS = ['split', 'x', 'pairs', 'both_solved', 'ratio', 'ratio_low', 'ratio_high', 'a_faster', 'b_faster', 'undecided', 'p_value', 'a_solved', 'a_rate', 'a_low', 'a_high', 'b_solved', 'b_rate', 'b_low', 'b_high'];

/// Rows of statistics: one per (split value, x) in numeric order, then "all" over every pair.
export function statsRows(ctx, numerator, denominator) {
  const pairs = scenePairs(ctx.runs, { numerator, denominator, x: ctx.x, split: ctx.split, groupBy: ctx.groupBy, params: ctx.params });
  const groups = new Map();
  for (const p of pairs) {
    const key = `${p.split}\u0000${p.x}`;
    if (!groups.has(key)) groups.set(key, { split: p.split, x: p.x, pairs: [] });
    groups.get(key).pairs.push(p);
  }
  const ordered = [...groups.values()].sort((a, b) => (a.split ?? 0) - (b.split ?? 0) || a.x - b.x);
  if (pairs.length) ordered.push({ split: ctx.split ? 'all' : null, x: 'all', pairs });
  return ordered.map((g) => {
    const s = pairedStats(g.pairs.map((p) => ({ a: observation(p.a), b: observation(p.b) })));
    return {
      split: g.split,
      x: g.x,
      ...s,
      a_rate: s.a_success.rate,
      a_low: s.a_success.low,
      a_high: s.a_success.high,
      b_rate: s.b_success.rate,
      b_low: s.b_success.low,
      b_high: s.b_success.high,
    };
  });
}

const pct = (v) => `${fmtNumber(100 * v, 2)}%`;

function cells(r) {
  const ratio = r.ratio === null ? '–' : `${fmtNumber(r.ratio)}${r.ratio_low === null ? '' : ` [${fmtNumber(r.ratio_low)}, ${fmtNumber(r.ratio_high)}]`}`;
  const p = r.p_value === null ? '–' : r.p_value < 0.001 ? '< 0.001' : fmtNumber(r.p_value, 2);
  const rate = (solved, low, high) => `${solved}/${r.pairs} [${pct(low)}, ${pct(high)}]`;
  return [String(r.pairs), String(r.both_solved), ratio, `${r.a_faster} / ${r.b_faster} / ${r.undecided}`, p, rate(r.a_solved, r.a_low, r.a_high), rate(r.b_solved, r.b_low, r.b_high)];
}

/// Fills `box` with the table of statsRows; box.dataset.rows: how many rows (0: no pairs).
export function drawStats(box, ctx, { numerator, denominator }) {
  clear(box);
  const rows = statsRows(ctx, numerator, denominator);
  box.dataset.rows = String(rows.length);
  box._csv = () => ({ columns: STATS_COLUMNS, rows });
  if (!rows.length) {
    box.append(el('div', { class: 'chart-empty', text: `no scene has a finished run of both ${numerator} and ${denominator}` }));
    return;
  }
  const head = [ctx.split ? ctx.split : null, ctx.x, 'pairs', 'both solved', `time ratio ${numerator} / ${denominator} [95% CI]`, `${numerator} faster / ${denominator} faster / undecided`, 'sign test p', `${numerator} solved [95% CI]`, `${denominator} solved [95% CI]`].filter((h) => h !== null);
  const body = rows.map((r) =>
    el(
      'tr',
      { class: r.x === 'all' ? 'total' : '', 'data-x': String(r.x) },
      (ctx.split ? [String(r.split)] : []).concat([String(r.x)]).map((t) => el('td', { text: t })),
      cells(r).map((t) => el('td', { class: 'num', text: t })),
    ),
  );
  box.append(el('div', { class: 'table-wrap' }, el('table', { class: 'data', 'data-testid': 'paired-stats-table' }, el('thead', {}, el('tr', {}, head.map((h) => el('th', { text: h })))), el('tbody', {}, body))));
}

/// The CSV button of the statistics panel.
export function statsCsvButton(box, name) {
  return el('button', { type: 'button', class: 'small secondary', 'data-testid': 'paired-stats-csv', title: 'the statistics as CSV', onclick: () => box._csv && download(`${fileStem(name, box.dataset.exportName)}.csv`, toCsv(box._csv().columns, box._csv().rows), 'text/csv') }, 'CSV');
}
