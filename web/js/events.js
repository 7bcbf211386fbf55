// One EventSource for the whole page (the server's /api/events stream), shared by every view.
const handlers = new Map(); // event name -> Set of functions
const KNOWN = ['hello', 'batch', 'batches', 'run', 'sizes', 'resync'];
let source = null;
let statusListener = () => {};

function dispatch(name, data) {
  for (const fn of handlers.get(name) || []) {
    try {
      fn(data);
    } catch (e) {
      console.warn(`handler of ${name} failed`, e);
    }
  }
}

export function connectEvents(onStatus) {
  statusListener = onStatus || statusListener;
  if (source) return;
  source = new EventSource('/api/events');
  source.onopen = () => statusListener(true);
  source.onerror = () => statusListener(false); // EventSource reconnects by itself
  for (const name of KNOWN) {
    source.addEventListener(name, (e) => {
      let data = {};
      try {
        data = JSON.parse(e.data);
      } catch {
        data = {};
      }
      dispatch(name, data);
    });
  }
}

/// Subscribes `fn` to an event; returns the function that unsubscribes.
export function on(name, fn) {
  if (!handlers.has(name)) handlers.set(name, new Set());
  handlers.get(name).add(fn);
  return () => handlers.get(name).delete(fn);
}

/// Calls fn at most once per `ms`, trailing (for "refetch on change" handlers).
export function debounce(fn, ms) {
  let timer = null;
  return (...args) => {
    clearTimeout(timer);
    timer = setTimeout(() => fn(...args), ms);
  };
}
