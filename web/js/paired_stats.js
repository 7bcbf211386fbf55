// Statistics that count failures, for two planner configurations run on the same scenes and seeds
// (the Compare page; the same definitions in C++ for `dashbench report`: server/figures/paired_stats.*,
// checked against the same hand-computed cases in tests/figures/paired_stats_cases.json):
//   - the seed-paired time ratio: the geometric mean of a/b over the pairs both solved, with a 95 %
//     Student t interval on the log ratios;
//   - a paired sign test on Gehan's pair scores: each pair says "a faster", "b faster" or nothing.
//     An unsolved run (timeout, infeasible, crash) is censored at its time limit: its time to solve
//     is known only to exceed the limit, so a solved partner at or under that limit is faster, and two
//     unsolved runs say nothing. Failures are neither dropped nor counted as taking the limit. A
//     Wilcoxon signed-rank test would need the size of every difference, unknown for censored pairs;
//     the sign test needs only their order. Two-sided exact binomial p over the decided pairs;
//   - success rates with 95 % Wilson score intervals (sound at 0 % and 100 %, unlike the Wald one).
// Pure functions, no DOM.

export const Z95 = 1.959963984540054; // the normal distribution's 97.5th percentile

/// Wilson score interval for `successes` of `n` at 95 %: {rate, low, high}; nulls when n is 0.
export function wilson(successes, n, z = Z95) {
  if (!(n > 0)) return { rate: null, low: null, high: null };
  const p = successes / n;
  const z2 = z * z;
  const denom = 1 + z2 / n;
  const centre = (p + z2 / (2 * n)) / denom;
  const half = (z / denom) * Math.sqrt((p * (1 - p)) / n + z2 / (4 * n * n));
  return { rate: p, low: Math.max(0, centre - half), high: Math.min(1, centre + half) };
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, 9 terms; relative error below 1e-13).
export function logGamma(x) {
  const c = [0.99999999999980993, 676.5203681218851, -1259.1392167224028, 771.32342877765313, -176.61502916214059, 12.507343278686905, -0.13857109526572012, 9.9843695780195716e-6, 1.5056327351493116e-7];
  if (x < 0.5) return Math.log(Math.PI / Math.abs(Math.sin(Math.PI * x))) - logGamma(1 - x);
  const y = x - 1;
  let a = c[0];
  const t = y + 7.5;
  for (let i = 1; i < 9; i++) a += c[i] / (y + i);
  return 0.5 * Math.log(2 * Math.PI) + (y + 0.5) * Math.log(t) - t + Math.log(a);
}

/// The regularized incomplete beta function I_x(a, b) (continued fraction, modified Lentz).
export function incompleteBeta(x, a, b) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  if (x > (a + 1) / (a + b + 2)) return 1 - incompleteBeta(1 - x, b, a);
  const front = Math.exp(a * Math.log(x) + b * Math.log(1 - x) - (logGamma(a) + logGamma(b) - logGamma(a + b))) / a;
  const tiny = 1e-300;
  let c = 1;
  let d = 1 - ((a + b) * x) / (a + 1);
  d = 1 / (Math.abs(d) < tiny ? tiny : d);
  let f = d;
  for (let m = 1; m <= 300; m++) {
    for (const num of [(m * (b - m) * x) / ((a + 2 * m - 1) * (a + 2 * m)), -((a + m) * (a + b + m) * x) / ((a + 2 * m) * (a + 2 * m + 1))]) {
      d = 1 + num * d;
      d = 1 / (Math.abs(d) < tiny ? tiny : d);
      c = 1 + num / c;
      if (Math.abs(c) < tiny) c = tiny;
      f *= c * d;
    }
    if (Math.abs(c * d - 1) < 1e-15) break;
  }
  return front * f;
}

/// P(T <= t) for Student's t with `df` degrees of freedom.
export function studentCdf(t, df) {
  const tail = 0.5 * incompleteBeta(df / (df + t * t), df / 2, 0.5);
  return t >= 0 ? 1 - tail : tail;
}

/// The p quantile (0.5 < p < 1) of Student's t with `df` degrees of freedom, by bisection.
export function studentQuantile(p, df) {
  let lo = 0;
  let hi = 1;
  while (studentCdf(hi, df) < p && hi < 1e12) hi *= 2;
  for (let i = 0; i < 200 && hi - lo > 1e-13 * hi; i++) {
    const mid = 0.5 * (lo + hi);
    if (studentCdf(mid, df) < p) lo = mid;
    else hi = mid;
  }
  return 0.5 * (lo + hi);
}

/// Two-sided exact sign test: P of a split at least as uneven as k of n under Binomial(n, 1/2).
export function signTestP(k, n) {
  if (!(n > 0)) return null;
  const m = Math.min(k, n - k);
  // log C(n, i) - n ln 2, summed for i = 0..m in log space (no underflow for large n).
  let logTerm = -n * Math.LN2;
  let logSum = logTerm;
  for (let i = 1; i <= m; i++) {
    logTerm += Math.log((n - i + 1) / i);
    logSum = logSum + Math.log1p(Math.exp(logTerm - logSum));
  }
  return Math.min(1, 2 * Math.exp(logSum));
}

/// One run as the statistics see it: {solved, time, limit}. `time`: its total time (s); `limit`: its
/// time limit (s), where an unsolved run is censored (its own time when it has no limit).
export function observation(run) {
  if (!run) return null;
  const solved = run.status === 'solved' && typeof run.total_time === 'number' && run.total_time > 0;
  const limit = typeof run.time_limit === 'number' && run.time_limit > 0 ? run.time_limit : typeof run.total_time === 'number' ? run.total_time : null;
  return { solved, time: solved ? run.total_time : null, limit };
}

/// Gehan's score of a pair: 1 when a is known to solve faster, -1 when b is, 0 when the order is
/// unknown (both unsolved, a tie, or a solve after the partner's limit).
export function gehanScore(a, b) {
  if (a.solved && b.solved) return a.time < b.time ? 1 : a.time > b.time ? -1 : 0;
  if (a.solved && b.limit !== null && a.time <= b.limit) return 1;
  if (b.solved && a.limit !== null && b.time <= a.limit) return -1;
  return 0;
}

/// The statistics of pairs [{a, b}] of observations (see observation()): {pairs, both_solved,
/// ratio, ratio_low, ratio_high, a_faster, b_faster, undecided, p_value, a_solved, b_solved,
/// a_success: wilson(), b_success: wilson()}. Ratios: a/b of total time; the interval needs 2 pairs.
export function pairedStats(pairs) {
  const logs = pairs.filter((p) => p.a.solved && p.b.solved).map((p) => Math.log(p.a.time / p.b.time));
  const m = logs.length;
  const mean = m ? logs.reduce((s, v) => s + v, 0) / m : null;
  let low = null;
  let high = null;
  if (m >= 2) {
    const sd = Math.sqrt(logs.reduce((s, v) => s + (v - mean) ** 2, 0) / (m - 1));
    const half = (studentQuantile(0.975, m - 1) * sd) / Math.sqrt(m);
    low = Math.exp(mean - half);
    high = Math.exp(mean + half);
  }
  const scores = pairs.map((p) => gehanScore(p.a, p.b));
  const aFaster = scores.filter((s) => s > 0).length;
  const bFaster = scores.filter((s) => s < 0).length;
  const aSolved = pairs.filter((p) => p.a.solved).length;
  const bSolved = pairs.filter((p) => p.b.solved).length;
  return {
    pairs: pairs.length,
    both_solved: m,
    ratio: m ? Math.exp(mean) : null,
    ratio_low: low,
    ratio_high: high,
    a_faster: aFaster,
    b_faster: bFaster,
    undecided: pairs.length - aFaster - bFaster,
    p_value: signTestP(aFaster, aFaster + bFaster),
    a_solved: aSolved,
    b_solved: bSolved,
    a_success: wilson(aSolved, pairs.length),
    b_success: wilson(bSolved, pairs.length),
  };
}
