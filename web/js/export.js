// Exports of a plot at publication size: SVG (vector, real text) and PNG (300 dpi), with fonts and
// line widths chosen to survive a two-column paper (8 pt text, 1 pt lines at 3.5 in wide); and the
// aggregated data behind a plot, or any table, as CSV.
import { Chart } from './charts.js';
import { SvgContext } from './svg_context.js';
import { toCsv } from './csv.js';

export { toCsv };

const CSS_PX_PER_INCH = 96;
const PNG_DPI = 300;
// Paper sizes: a column of a two-column paper, and the full text width.
export const EXPORT_SIZES = {
  column: { label: 'column (3.5 × 2.6 in)', width: 3.5, height: 2.6 },
  page: { label: 'page width (7 × 3.2 in)', width: 7, height: 3.2 },
};
const FONT_PX = 8 * (CSS_PX_PER_INCH / 72); // 8 pt
const LEGEND_FONT_PX = 7 * (CSS_PX_PER_INCH / 72); // 7 pt
const LINE_PX = 1.2 * (CSS_PX_PER_INCH / 72); // about 1.2 pt
const POINT_RADIUS_PX = 2.6;
// Point styles drawn with strokes only (an asterisk, crosses) read as a dot at the filled shapes'
// size: they keep this radius, so that validation's asterisk prints as an asterisk.
const STROKED_POINTS = new Set(['star', 'cross', 'crossRot']);
const STROKED_RADIUS_PX = 4.2;

/// A copy of a Chart.js config: plain objects and arrays copied, functions and other values shared.
export function cloneConfig(value) {
  if (Array.isArray(value)) return value.map(cloneConfig);
  if (value && typeof value === 'object' && Object.getPrototypeOf(value) === Object.prototype) {
    const out = {};
    for (const [k, v] of Object.entries(value)) out[k] = cloneConfig(v);
    return out;
  }
  return value;
}

/// The config adjusted for print: thinner lines, smaller points, a compact legend (beside the plot at
/// page width), no animation, fixed size.
function printConfig(config, dpr, size) {
  const c = cloneConfig(config);
  c.options = c.options || {};
  Object.assign(c.options, { responsive: false, maintainAspectRatio: false, animation: false, devicePixelRatio: dpr, events: [] });
  c.options.plugins = { ...(c.options.plugins || {}) };
  c.options.plugins.tooltip = { enabled: false };
  c.options.plugins.legend = { ...(c.options.plugins.legend || {}) };
  c.options.plugins.legend.labels = { ...(c.options.plugins.legend.labels || {}), boxWidth: 6, boxHeight: 6, padding: 4, font: { size: LEGEND_FONT_PX } };
  if (size === 'page') c.options.plugins.legend.position = 'right';
  for (const axis of Object.values(c.options.scales || {})) {
    axis.ticks = { ...(axis.ticks || {}), font: { size: FONT_PX } };
    if (axis.title) axis.title = { ...axis.title, font: { size: FONT_PX, weight: '600' } };
    axis.grid = { lineWidth: 0.5, ...(axis.grid || {}) };
  }
  for (const ds of c.data?.datasets || []) {
    const width = typeof ds.borderWidth === 'number' ? ds.borderWidth : 3;
    if (ds.type !== 'bar' && c.type !== 'bar') ds.borderWidth = Math.min(width, LINE_PX);
    if (typeof ds.pointRadius === 'number') ds.pointRadius = Math.min(ds.pointRadius, STROKED_POINTS.has(ds.pointStyle) ? STROKED_RADIUS_PX : POINT_RADIUS_PX);
    if (Array.isArray(ds.borderDash)) ds.borderDash = ds.borderDash.map((d) => d * 0.6);
    if (typeof ds.outlierRadius === 'number') ds.outlierRadius = Math.min(ds.outlierRadius, 2);
    // Lines drawn segment by segment: Chart.js otherwise strokes a cached Path2D, which the SVG
    // recorder cannot read.
    if (!ds.segment) ds.segment = {};
  }
  return c;
}

/// Draws `config` once on a detached canvas of the given CSS size; `getContext` may substitute the
/// 2D context (the SVG recorder). Returns what `read(chart, canvas)` returns.
function renderOffscreen(config, size, dpr, read, context = null) {
  const { widthPx, heightPx } = sizeOf(size);
  const holder = document.createElement('div');
  holder.style.cssText = `position:fixed;left:-20000px;top:0;width:${widthPx}px;height:${heightPx}px;`;
  const canvas = document.createElement('canvas');
  canvas.width = widthPx;
  canvas.height = heightPx;
  canvas.style.width = `${widthPx}px`;
  canvas.style.height = `${heightPx}px`;
  if (context) {
    const svg = context(canvas);
    canvas.getContext = () => svg;
  }
  holder.append(canvas);
  document.body.append(holder);
  const fontSize = Chart.defaults.font.size;
  Chart.defaults.font.size = FONT_PX;
  let chart = null;
  try {
    chart = new Chart(canvas, printConfig(config, dpr, size));
    return read(chart, canvas);
  } finally {
    Chart.defaults.font.size = fontSize;
    if (chart) chart.destroy();
    holder.remove();
  }
}

function sizeOf(name) {
  const s = EXPORT_SIZES[name] || EXPORT_SIZES.column;
  return { ...s, widthPx: Math.round(s.width * CSS_PX_PER_INCH), heightPx: Math.round(s.height * CSS_PX_PER_INCH) };
}

/// The plot as an SVG document, `size` one of EXPORT_SIZES.
export function chartSvg(config, size = 'column') {
  const s = sizeOf(size);
  let recorder = null;
  return renderOffscreen(
    config,
    size,
    1,
    () => recorder.serialize(`${s.width}in`, `${s.height}in`),
    (canvas) => (recorder = new SvgContext(s.widthPx, s.heightPx, canvas)),
  );
}

/// The plot as a PNG blob at 300 dpi, on white.
export function chartPng(config, size = 'column') {
  const s = sizeOf(size);
  const dpr = PNG_DPI / CSS_PX_PER_INCH;
  const white = { id: 'whitePage', beforeDraw: (chart) => {
    const { ctx } = chart;
    ctx.save();
    ctx.globalCompositeOperation = 'destination-over';
    ctx.fillStyle = '#ffffff';
    ctx.fillRect(0, 0, chart.width, chart.height);
    ctx.restore();
  } };
  const withWhite = { ...config, plugins: [...(config.plugins || []), white] };
  const url = renderOffscreen(withWhite, size, dpr, (chart, canvas) => canvas.toDataURL('image/png'));
  const bytes = atob(url.split(',')[1]);
  const out = new Uint8Array(bytes.length);
  for (let i = 0; i < bytes.length; i++) out[i] = bytes.charCodeAt(i);
  return new Blob([out], { type: 'image/png' });
}

/// Saves `content` (a string or a Blob) as a file the browser downloads.
export function download(filename, content, type = 'text/plain') {
  const blob = content instanceof Blob ? content : new Blob([content], { type });
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = filename;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10000);
}

/// "compare-sizes-sorting" -> a safe file name stem.
export function fileStem(...parts) {
  return parts.filter(Boolean).join('-').replace(/[^A-Za-z0-9_.-]+/g, '_').slice(0, 120) || 'plot';
}

/// Several plots as one figure (panels in a grid, `columns` wide), each panel at `size`: one SVG with
/// a nested <svg> per panel (their clip ids made unique), or one 300 dpi PNG.
export function figureSvg(configs, size = 'column', columns = 2) {
  const s = sizeOf(size);
  const rows = Math.ceil(configs.length / columns);
  const panels = configs.map((config, k) => {
    const one = chartSvg(config, size)
      .replace(/^<\?xml[^>]*>\s*/, '')
      .replace(/id="clip(\d+)"/g, `id="p${k}clip$1"`)
      .replace(/url\(#clip(\d+)\)/g, `url(#p${k}clip$1)`);
    const x = (k % columns) * s.widthPx;
    const y = Math.floor(k / columns) * s.heightPx;
    return one.replace(/^<svg[^>]*>/, `<svg x="${x}" y="${y}" width="${s.widthPx}" height="${s.heightPx}" viewBox="0 0 ${s.widthPx} ${s.heightPx}">`);
  });
  const width = columns * s.widthPx;
  const height = rows * s.heightPx;
  return (
    `<?xml version="1.0" encoding="UTF-8"?>\n<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="${columns * s.width}in" height="${rows * s.height}in" viewBox="0 0 ${width} ${height}">\n` +
    `<rect width="100%" height="100%" fill="#ffffff"/>\n${panels.join('\n')}\n</svg>\n`
  );
}

export async function figurePng(configs, size = 'column', columns = 2) {
  const s = sizeOf(size);
  const dpr = PNG_DPI / CSS_PX_PER_INCH;
  const rows = Math.ceil(configs.length / columns);
  const canvas = document.createElement('canvas');
  canvas.width = Math.round(columns * s.widthPx * dpr);
  canvas.height = Math.round(rows * s.heightPx * dpr);
  const ctx = canvas.getContext('2d');
  ctx.fillStyle = '#ffffff';
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  for (let k = 0; k < configs.length; k++) {
    const bitmap = await createImageBitmap(chartPng(configs[k], size));
    ctx.drawImage(bitmap, Math.round((k % columns) * s.widthPx * dpr), Math.round(Math.floor(k / columns) * s.heightPx * dpr));
  }
  return new Promise((resolve) => canvas.toBlob(resolve, 'image/png'));
}
