// Each page's state lives in the URL after its route: #/compare?family=sorting&x=objects&plot=sizes.
// Pages read it at mount and write it back with replaceState on every change (no reload, no new
// history entry), so a copied link or Back to the page reproduces the view.
const MAX_HASH_CHARS = 8000; // browsers and chat tools cut very long links; state beyond it is dropped

/// {page, args, params} of a hash like "#/run/UUID?overlay=a,b".
export function parseHash(hash = location.hash) {
  const text = hash.replace(/^#\/?/, '');
  const q = text.indexOf('?');
  const path = q < 0 ? text : text.slice(0, q);
  const [page, ...args] = path.split('/');
  let decoded = [];
  try {
    decoded = args.map(decodeURIComponent);
  } catch {
    decoded = args;
  }
  return { page, args: decoded, params: new URLSearchParams(q < 0 ? '' : text.slice(q + 1)) };
}

function asText(v) {
  return Array.isArray(v) ? v.join(',') : typeof v === 'boolean' ? (v ? '1' : '0') : String(v);
}

/// Replaces the current page's query with `state` (empty, null and default values are left out).
export function writeState(state, defaults = {}) {
  const { page, args } = parseHash();
  const q = new URLSearchParams();
  for (const [k, v] of Object.entries(state)) {
    if (v === undefined || v === null || v === '' || (Array.isArray(v) && v.length === 0)) continue;
    const text = asText(v);
    if (k in defaults && asText(defaults[k]) === text) continue;
    q.set(k, text);
  }
  const path = [page, ...args.map(encodeURIComponent)].join('/');
  const query = q.toString();
  const hash = `#/${path}${query ? `?${query}` : ''}`;
  if (hash.length > MAX_HASH_CHARS || hash === location.hash) return;
  history.replaceState(history.state, '', hash);
}

/// Typed reads of URL parameters with fallbacks.
export function readString(params, key, fallback = '') {
  const v = params.get(key);
  return v === null ? fallback : v;
}
export function readBool(params, key, fallback = false) {
  const v = params.get(key);
  return v === null ? fallback : v === '1' || v === 'true';
}
export function readNumber(params, key, fallback = 0) {
  const v = Number(params.get(key));
  return params.get(key) === null || !Number.isFinite(v) ? fallback : v;
}
export function readList(params, key) {
  const v = params.get(key);
  return v ? v.split(',').map((s) => s.trim()).filter(Boolean) : [];
}
