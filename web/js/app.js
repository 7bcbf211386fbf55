// The dashboard's shell: hash routes (#/launch, #/runs, #/compare, #/run/UUID, #/query, #/dispatch;
// each page's settings follow a '?', see url_state.js),
// the token box, the live-updates indicator, and error banners.
import { checkToken, getToken, setToken } from './api.js';
import { connectEvents } from './events.js';
import { clear, errorBox } from './dom.js';
import * as launch from './pages/launch.js';
import * as runs from './pages/runs.js';
import * as compare from './pages/compare.js';
import * as run from './pages/run.js';
import * as queryPage from './pages/query.js';
import * as dispatch from './pages/dispatch.js';
import { parseHash } from './url_state.js';

const PAGES = { launch, runs, compare, run, query: queryPage, dispatch };
let unmount = null;

function banner(message) {
  const b = document.getElementById('banner');
  b.textContent = message || '';
  b.hidden = !message;
}

function route() {
  const { page: name, args, params } = parseHash();
  const page = PAGES[name] ? name : 'runs';
  for (const a of document.querySelectorAll('#nav a')) a.classList.toggle('active', a.dataset.page === page);
  if (unmount) {
    try {
      unmount();
    } catch (e) {
      console.warn('unmount failed', e);
    }
  }
  unmount = null;
  banner('');
  const root = clear(document.getElementById('page'));
  root.dataset.page = page;
  try {
    unmount = PAGES[page].mount(root, args, params) || null;
  } catch (e) {
    root.append(errorBox(String(e)));
  }
}

function setupToken() {
  // `dashbench serve` prints a link with #token=... at the first start: take it, then drop it from the URL.
  const m = location.hash.match(/^#token=([0-9A-Za-z]+)$/);
  if (m) {
    setToken(m[1]);
    history.replaceState(null, '', `${location.pathname}#/runs`);
  }
  const panel = document.getElementById('token-panel');
  const input = document.getElementById('token-input');
  const button = document.getElementById('token-button');
  // ✓ only for a token the server took (GET /api/token), ✗ for one it refused.
  let checking = 0;
  const show = (text, title, state) => {
    button.textContent = text;
    button.title = title;
    button.dataset.token = state;
  };
  const refresh = async () => {
    if (!getToken()) return show('Token', 'no token: changes will be refused', 'none');
    const mine = ++checking;
    show('Token …', 'checking the token with the server', 'checking');
    const ok = await checkToken();
    if (mine !== checking) return;
    if (ok === true) show('Token ✓', 'the server takes this token', 'valid');
    else if (ok === false) show('Token ✗', 'the server refuses this token: paste the one in its token file (data/token)', 'refused');
    else show('Token ?', 'token saved; the server did not answer, so it is not checked', 'unchecked');
  };
  button.addEventListener('click', () => {
    panel.hidden = !panel.hidden;
    input.value = getToken();
  });
  document.getElementById('token-save').addEventListener('click', () => {
    setToken(input.value.trim());
    panel.hidden = true;
    banner('');
  });
  document.getElementById('token-clear').addEventListener('click', () => {
    setToken('');
    input.value = '';
  });
  window.addEventListener('dashbench-token', refresh);
  window.addEventListener('dashbench-unauthorized', (e) => {
    banner(`${e.detail} — enter the token (Token button, top right).`);
    panel.hidden = false;
    refresh();
  });
  refresh();
}

setupToken();
connectEvents((on) => {
  const live = document.getElementById('live');
  live.textContent = on ? 'live' : 'offline';
  live.classList.toggle('on', on);
});
window.addEventListener('hashchange', route);
route();
