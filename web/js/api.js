// The JSON API: fetch wrappers that turn {"error": "..."} answers into ApiError, and the token.
const TOKEN_KEY = 'dashbench.token';

export class ApiError extends Error {
  constructor(status, message, body) {
    super(message);
    this.status = status;
    this.body = body;
  }
}

export function getToken() {
  return localStorage.getItem(TOKEN_KEY) || '';
}

/// Whether the server takes the saved token: true, false (refused), or null (no token, or no answer).
export async function checkToken() {
  if (!getToken()) return null;
  try {
    await request('GET', '/api/token', { quiet: true });
    return true;
  } catch (e) {
    return e.status === 401 ? false : null;
  }
}

export function setToken(token) {
  if (token) localStorage.setItem(TOKEN_KEY, token);
  else localStorage.removeItem(TOKEN_KEY);
  window.dispatchEvent(new CustomEvent('dashbench-token'));
}

async function request(method, path, { body, auth = true, text = false, quiet = false } = {}) {
  const headers = {};
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  if (auth && getToken()) headers.Authorization = `Bearer ${getToken()}`;
  let res;
  try {
    res = await fetch(path, {
      method,
      headers,
      body: body === undefined ? undefined : typeof body === 'string' ? body : JSON.stringify(body),
    });
  } catch (e) {
    // fetch's own words ("Failed to fetch") say nothing to people: the server is gone or unreachable.
    throw new ApiError(0, `the dashboard's server does not answer (${path}): is \`dashbench serve\` still running?`, null);
  }
  const raw = await res.text();
  let data = null;
  if (!text || !res.ok) {
    try {
      data = raw ? JSON.parse(raw) : null;
    } catch {
      data = null;
    }
  }
  if (!res.ok) {
    const message = (data && data.error) || `${res.status} ${res.statusText}`;
    const err = new ApiError(res.status, message, data);
    if (res.status === 401 && !quiet) window.dispatchEvent(new CustomEvent('dashbench-unauthorized', { detail: message }));
    throw err;
  }
  return text ? raw : data;
}

export const api = {
  get: (path) => request('GET', path),
  text: (path) => request('GET', path, { text: true }),
  post: (path, body, { auth = true } = {}) => request('POST', path, { body, auth }),
  put: (path, body) => request('PUT', path, { body, auth: true }),
  del: (path) => request('DELETE', path, { auth: true }),
};

/// "a=1&b=x" from an object, leaving out empty values.
export function query(params) {
  const q = new URLSearchParams();
  for (const [k, v] of Object.entries(params)) {
    if (v !== undefined && v !== null && v !== '') q.set(k, String(v));
  }
  const s = q.toString();
  return s ? `?${s}` : '';
}
