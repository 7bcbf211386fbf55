// CSV (RFC 4180) of a plot's aggregated data or any table, for the exports. Numbers are written to 9
// significant digits, which keeps every digit a measurement has and drops floating-point noise
// (619.695, never 619.6950000000055); integers are written whole.
const CSV_DIGITS = 9;

/// A number as the CSV writes it.
export function csvNumber(v) {
  if (!Number.isFinite(v)) return '';
  if (Number.isInteger(v)) return String(v);
  return String(Number(v.toPrecision(CSV_DIGITS)));
}

function csvField(v) {
  if (v === null || v === undefined) return '';
  const s = typeof v === 'number' ? csvNumber(v) : typeof v === 'object' ? JSON.stringify(v) : String(v);
  return /[",\n\r]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s;
}

/// RFC 4180 CSV from column names and rows (arrays or objects keyed by column).
export function toCsv(columns, rows) {
  const lines = [columns.map(csvField).join(',')];
  for (const r of rows) lines.push(columns.map((c, i) => csvField(Array.isArray(r) ? r[i] : r[c])).join(','));
  return `${lines.join('\r\n')}\r\n`;
}
