// A batch's time left as the Launch page shows it: the runner's estimate (time per finished run
// times the runs left) taken when a run ends, then counted down by the batch's clock until the next
// one ends, so that it never counts up while a long run works (the runner's own estimate grows with
// every second nothing ends). Null (unknown) once the countdown ran out with runs still to finish.
// The terminal's bar does the same (server/batch/progress_printer.h, SteadyEta).
const anchors = new Map(); // batch id -> {done, eta, at}
const MAX_BATCHES = 200;

/// Seconds left for batch `id` at progress `p` ({done, remaining, elapsed, eta}), or null.
export function steadyEta(id, p) {
  if (!p) return null;
  let a = anchors.get(id);
  const eta = typeof p.eta === 'number' && p.eta >= 0 ? p.eta : null;
  if (!a || a.done !== p.done || (a.eta === null && eta !== null)) {
    a = { done: p.done, eta, at: p.elapsed || 0 };
    anchors.delete(id);
    anchors.set(id, a);
    if (anchors.size > MAX_BATCHES) anchors.delete(anchors.keys().next().value);
  }
  if (a.eta === null) return null;
  if (!(p.remaining > 0)) return 0;
  const left = a.eta - ((p.elapsed || 0) - a.at);
  return left > 0 ? left : null;
}
