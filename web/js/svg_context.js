// A CanvasRenderingContext2D look-alike that records what Chart.js draws as SVG elements, so a plot
// exports as vector graphics with real text (editable in Inkscape, sharp in a paper). It covers the
// calls Chart.js 4 and the box-plot plugin make: paths (lines, arcs, ellipses, curves, rectangles),
// fill and stroke with dashes, text, transforms, clipping, save and restore. Text is measured by a
// real 2D context with the same font. Arcs under a rotation or uneven scale become polylines.
const XMLNS = 'http://www.w3.org/2000/svg';
const ARC_SEGMENTS_MIN = 12;

function escapeXml(text) {
  return String(text).replace(/[&<>"']/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&apos;' })[c]);
}

function num(v) {
  return Number.isFinite(v) ? String(Math.round(v * 100) / 100) : '0';
}

/// "#0072B255", "rgba(0,114,178,.3)", "red" -> {colour, opacity} (SVG 1.1 knows no alpha in colours).
export function splitColour(style) {
  if (typeof style !== 'string') return { colour: '#000000', opacity: 1 };
  const s = style.trim();
  let m = s.match(/^#([0-9a-f]{3,8})$/i);
  if (m) {
    let h = m[1];
    if (h.length === 3 || h.length === 4) h = [...h].map((c) => c + c).join('');
    if (h.length === 8) return { colour: `#${h.slice(0, 6)}`, opacity: parseInt(h.slice(6), 16) / 255 };
    return { colour: `#${h.slice(0, 6)}`, opacity: 1 };
  }
  m = s.match(/^rgba?\(\s*([\d.]+)[\s,]+([\d.]+)[\s,]+([\d.]+)(?:[\s,/]+([\d.]+%?))?\s*\)$/i);
  if (m) {
    const a = m[4] === undefined ? 1 : m[4].endsWith('%') ? parseFloat(m[4]) / 100 : parseFloat(m[4]);
    const hex = [m[1], m[2], m[3]].map((v) => Math.max(0, Math.min(255, Math.round(Number(v)))).toString(16).padStart(2, '0')).join('');
    return { colour: `#${hex}`, opacity: a };
  }
  if (s === 'transparent') return { colour: '#000000', opacity: 0 };
  return { colour: s, opacity: 1 };
}

/// "600 12px system-ui, sans-serif" -> {weight, style, size, family}.
function parseFont(font) {
  const m = String(font).match(/^\s*((?:(?:italic|oblique|normal|bold|bolder|lighter|\d{3})\s+)*)([\d.]+)px\s+(.+)$/i);
  if (!m) return { weight: 'normal', style: 'normal', size: 10, family: 'sans-serif' };
  const words = m[1].trim().split(/\s+/).filter(Boolean);
  return {
    weight: words.find((w) => /^(bold|bolder|lighter|\d{3})$/i.test(w)) || 'normal',
    style: words.find((w) => /^(italic|oblique)$/i.test(w)) || 'normal',
    size: Number(m[2]),
    family: m[3].replace(/"/g, "'"),
  };
}

function multiply(m, n) {
  // 2D affine [a b c d e f] as canvas uses them: x' = a x + c y + e, y' = b x + d y + f.
  return [m[0] * n[0] + m[2] * n[1], m[1] * n[0] + m[3] * n[1], m[0] * n[2] + m[2] * n[3], m[1] * n[2] + m[3] * n[3], m[0] * n[4] + m[2] * n[5] + m[4], m[1] * n[4] + m[3] * n[5] + m[5]];
}

export class SvgContext {
  /// width, height: the drawing's size in CSS pixels; canvas: the element Chart.js is given.
  constructor(width, height, canvas) {
    this.width = width;
    this.height = height;
    this.canvas = canvas;
    this.measurer = document.createElement('canvas').getContext('2d');
    this.parts = [];
    this.defs = [];
    this.clipCount = 0;
    this.path = [];
    this.stack = [];
    this.state = {
      transform: [1, 0, 0, 1, 0, 0],
      fillStyle: '#000000',
      strokeStyle: '#000000',
      lineWidth: 1,
      lineCap: 'butt',
      lineJoin: 'miter',
      lineDash: [],
      lineDashOffset: 0,
      font: '10px sans-serif',
      textAlign: 'start',
      textBaseline: 'alphabetic',
      globalAlpha: 1,
      direction: 'ltr',
      miterLimit: 10,
      openGroups: 0,
    };
  }

  // ---- state ----
  save() {
    this.stack.push({ ...this.state, lineDash: [...this.state.lineDash], openGroups: 0 });
  }
  restore() {
    const closing = this.state.openGroups;
    for (let i = 0; i < closing; i++) this.parts.push('</g>');
    this.state.openGroups = 0;
    if (this.stack.length) this.state = this.stack.pop();
  }
  get fillStyle() { return this.state.fillStyle; }
  set fillStyle(v) { this.state.fillStyle = v; }
  get strokeStyle() { return this.state.strokeStyle; }
  set strokeStyle(v) { this.state.strokeStyle = v; }
  get lineWidth() { return this.state.lineWidth; }
  set lineWidth(v) { if (Number.isFinite(v) && v >= 0) this.state.lineWidth = v; }
  get lineCap() { return this.state.lineCap; }
  set lineCap(v) { this.state.lineCap = v; }
  get lineJoin() { return this.state.lineJoin; }
  set lineJoin(v) { this.state.lineJoin = v; }
  get miterLimit() { return this.state.miterLimit; }
  set miterLimit(v) { this.state.miterLimit = v; }
  get lineDashOffset() { return this.state.lineDashOffset; }
  set lineDashOffset(v) { this.state.lineDashOffset = Number(v) || 0; }
  get font() { return this.state.font; }
  set font(v) { this.state.font = v; }
  get textAlign() { return this.state.textAlign; }
  set textAlign(v) { this.state.textAlign = v; }
  get textBaseline() { return this.state.textBaseline; }
  set textBaseline(v) { this.state.textBaseline = v; }
  get globalAlpha() { return this.state.globalAlpha; }
  set globalAlpha(v) { this.state.globalAlpha = Number.isFinite(v) ? v : 1; }
  get direction() { return this.state.direction; }
  set direction(v) { this.state.direction = v; }
  setLineDash(d) { this.state.lineDash = Array.isArray(d) ? d.filter((x) => Number.isFinite(x) && x >= 0) : []; }
  getLineDash() { return [...this.state.lineDash]; }

  // ---- transforms ----
  setTransform(a, b, c, d, e, f) {
    this.state.transform = typeof a === 'object' && a ? [a.a, a.b, a.c, a.d, a.e, a.f] : [a, b, c, d, e, f];
  }
  resetTransform() { this.state.transform = [1, 0, 0, 1, 0, 0]; }
  transform(a, b, c, d, e, f) { this.state.transform = multiply(this.state.transform, [a, b, c, d, e, f]); }
  translate(x, y) { this.transform(1, 0, 0, 1, x, y); }
  scale(x, y) { this.transform(x, 0, 0, y, 0, 0); }
  rotate(r) { this.transform(Math.cos(r), Math.sin(r), -Math.sin(r), Math.cos(r), 0, 0); }
  getTransform() { const [a, b, c, d, e, f] = this.state.transform; return new DOMMatrix([a, b, c, d, e, f]); }

  apply(x, y) {
    const [a, b, c, d, e, f] = this.state.transform;
    return [a * x + c * y + e, b * x + d * y + f];
  }
  /// The transform's scale when it has no rotation and equal axes, else null.
  uniformScale() {
    const [a, b, c, d] = this.state.transform;
    return Math.abs(b) < 1e-12 && Math.abs(c) < 1e-12 && Math.abs(a - d) < 1e-12 && a > 0 ? a : null;
  }
  lineScale() {
    const [a, b, c, d] = this.state.transform;
    return Math.sqrt(Math.abs(a * d - b * c)) || 1;
  }

  // ---- paths (points stored in SVG user space, i.e. already transformed) ----
  beginPath() { this.path = []; this.current = null; this.start = null; }
  moveTo(x, y) {
    const p = this.apply(x, y);
    this.path.push(`M${num(p[0])} ${num(p[1])}`);
    this.current = p;
    this.start = p;
  }
  lineTo(x, y) {
    if (!this.current) return this.moveTo(x, y);
    const p = this.apply(x, y);
    this.path.push(`L${num(p[0])} ${num(p[1])}`);
    this.current = p;
  }
  closePath() {
    if (this.path.length) this.path.push('Z');
    this.current = this.start;
  }
  quadraticCurveTo(cx, cy, x, y) {
    if (!this.current) this.moveTo(cx, cy);
    const c = this.apply(cx, cy);
    const p = this.apply(x, y);
    this.path.push(`Q${num(c[0])} ${num(c[1])} ${num(p[0])} ${num(p[1])}`);
    this.current = p;
  }
  bezierCurveTo(c1x, c1y, c2x, c2y, x, y) {
    if (!this.current) this.moveTo(c1x, c1y);
    const a = this.apply(c1x, c1y);
    const b = this.apply(c2x, c2y);
    const p = this.apply(x, y);
    this.path.push(`C${num(a[0])} ${num(a[1])} ${num(b[0])} ${num(b[1])} ${num(p[0])} ${num(p[1])}`);
    this.current = p;
  }
  rect(x, y, w, h) {
    this.moveTo(x, y);
    this.lineTo(x + w, y);
    this.lineTo(x + w, y + h);
    this.lineTo(x, y + h);
    this.closePath();
  }
  roundRect(x, y, w, h) {
    this.rect(x, y, w, h); // Chart.js uses it only for rounded bars and legend boxes: square corners are fine
  }
  arc(x, y, r, a0, a1, ccw = false) {
    this.ellipse(x, y, r, r, 0, a0, a1, ccw);
  }
  ellipse(x, y, rx, ry, rotation, a0, a1, ccw = false) {
    if (!(rx >= 0 && ry >= 0)) return;
    let sweep = a1 - a0;
    if (ccw) sweep = sweep <= -2 * Math.PI ? -2 * Math.PI : sweep > 0 ? ((sweep % (2 * Math.PI)) - 2 * Math.PI) % (2 * Math.PI) : sweep;
    else sweep = sweep >= 2 * Math.PI ? 2 * Math.PI : sweep < 0 ? (sweep % (2 * Math.PI)) + 2 * Math.PI : sweep;
    const at = (t) => {
      const px = rx * Math.cos(t);
      const py = ry * Math.sin(t);
      return [x + px * Math.cos(rotation) - py * Math.sin(rotation), y + px * Math.sin(rotation) + py * Math.cos(rotation)];
    };
    const first = at(a0);
    if (this.current) this.lineTo(first[0], first[1]);
    else this.moveTo(first[0], first[1]);
    const s = this.uniformScale();
    if (s !== null && rx === ry && Math.abs(sweep) > 1e-9) {
      // Exact SVG arcs, in at most two halves (an SVG arc cannot draw a full circle at once).
      const halves = Math.abs(sweep) > Math.PI ? 2 : 1;
      for (let k = 1; k <= halves; k++) {
        const p = this.apply(...at(a0 + (sweep * k) / halves));
        const large = Math.abs(sweep / halves) > Math.PI ? 1 : 0;
        this.path.push(`A${num(rx * s)} ${num(rx * s)} 0 ${large} ${sweep > 0 ? 1 : 0} ${num(p[0])} ${num(p[1])}`);
        this.current = p;
      }
      return;
    }
    const n = Math.max(ARC_SEGMENTS_MIN, Math.ceil((Math.abs(sweep) * Math.max(rx, ry) * this.lineScale()) / 2));
    for (let k = 1; k <= n; k++) {
      const p = at(a0 + (sweep * k) / n);
      this.lineTo(p[0], p[1]);
    }
  }

  // ---- painting ----
  styleAttrs(kind) {
    const st = this.state;
    const { colour, opacity } = splitColour(kind === 'fill' ? st.fillStyle : st.strokeStyle);
    const alpha = opacity * st.globalAlpha;
    if (kind === 'fill') return `fill="${escapeXml(colour)}"${alpha < 1 ? ` fill-opacity="${num(alpha)}"` : ''} stroke="none"`;
    const scale = this.lineScale();
    const dash = st.lineDash.length ? ` stroke-dasharray="${st.lineDash.map((d) => num(d * scale)).join(' ')}"${st.lineDashOffset ? ` stroke-dashoffset="${num(st.lineDashOffset * scale)}"` : ''}` : '';
    return `fill="none" stroke="${escapeXml(colour)}"${alpha < 1 ? ` stroke-opacity="${num(alpha)}"` : ''} stroke-width="${num(st.lineWidth * scale)}" stroke-linecap="${st.lineCap}" stroke-linejoin="${st.lineJoin}"${dash}`;
  }
  visible(kind) {
    const { opacity } = splitColour(kind === 'fill' ? this.state.fillStyle : this.state.strokeStyle);
    return opacity * this.state.globalAlpha > 0 && (kind === 'fill' || this.state.lineWidth > 0);
  }
  fill() {
    if (this.path.length && this.visible('fill')) this.parts.push(`<path d="${this.path.join('')}" ${this.styleAttrs('fill')}/>`);
  }
  stroke() {
    if (this.path.length && this.visible('stroke')) this.parts.push(`<path d="${this.path.join('')}" ${this.styleAttrs('stroke')}/>`);
  }
  fillRect(x, y, w, h) {
    const saved = this.path;
    this.beginPath();
    this.rect(x, y, w, h);
    this.fill();
    this.path = saved;
  }
  strokeRect(x, y, w, h) {
    const saved = this.path;
    this.beginPath();
    this.rect(x, y, w, h);
    this.stroke();
    this.path = saved;
  }
  clearRect() {
    // The export draws on a white page: nothing to clear.
  }
  clip() {
    if (!this.path.length) return;
    const id = `clip${++this.clipCount}`;
    this.defs.push(`<clipPath id="${id}"><path d="${this.path.join('')}"/></clipPath>`);
    this.parts.push(`<g clip-path="url(#${id})">`);
    this.state.openGroups += 1;
  }
  drawImage() {
    // Chart.js draws images only for image point styles, which the dashboard does not use.
  }
  createLinearGradient() {
    return { addColorStop() {} };
  }
  createPattern() {
    return null;
  }

  // ---- text ----
  measureText(text) {
    this.measurer.font = this.state.font;
    return this.measurer.measureText(text);
  }
  text(text, x, y, kind) {
    if (!this.visible(kind)) return;
    const f = parseFont(this.state.font);
    const anchor = { left: 'start', start: 'start', center: 'middle', right: 'end', end: 'end' }[this.state.textAlign] || 'start';
    const baseline = { top: 'text-before-edge', hanging: 'hanging', middle: 'central', bottom: 'text-after-edge', ideographic: 'ideographic' }[this.state.textBaseline];
    const [a, b, c, d, e, g] = this.state.transform;
    const transform = a === 1 && b === 0 && c === 0 && d === 1 && e === 0 && g === 0 ? '' : ` transform="matrix(${[a, b, c, d, e, g].map(num).join(' ')})"`;
    this.parts.push(
      `<text x="${num(x)}" y="${num(y)}"${transform} font-family="${escapeXml(f.family)}" font-size="${num(f.size)}"` +
        `${f.weight !== 'normal' ? ` font-weight="${f.weight}"` : ''}${f.style !== 'normal' ? ` font-style="${f.style}"` : ''}` +
        ` text-anchor="${anchor}"${baseline ? ` dominant-baseline="${baseline}"` : ''} ${this.styleAttrs(kind)}>${escapeXml(text)}</text>`,
    );
  }
  fillText(text, x, y) {
    this.text(text, x, y, 'fill');
  }
  strokeText(text, x, y) {
    this.text(text, x, y, 'stroke');
  }

  /// The SVG document; `physicalWidth` like "3.5in" sets the printed size (the drawing scales).
  serialize(physicalWidth = null, physicalHeight = null) {
    while (this.stack.length) this.restore();
    this.restore(); // closes clip groups opened outside any save()
    const w = physicalWidth || `${this.width}`;
    const h = physicalHeight || `${this.height}`;
    return (
      `<?xml version="1.0" encoding="UTF-8"?>\n<svg xmlns="${XMLNS}" version="1.1" width="${w}" height="${h}" viewBox="0 0 ${this.width} ${this.height}">\n` +
      `<defs>${this.defs.join('')}</defs>\n<rect width="100%" height="100%" fill="#ffffff"/>\n${this.parts.join('\n')}\n</svg>\n`
    );
  }
}
