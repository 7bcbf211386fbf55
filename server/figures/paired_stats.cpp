#include "server/figures/paired_stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace dash::figures {
namespace {

constexpr double kZ95 = 1.959963984540054;  // the normal distribution's 97.5th percentile

/// The regularized incomplete beta function I_x(a, b) (continued fraction, modified Lentz).
double incompleteBeta(double x, double a, double b) {
  if (x <= 0) return 0;
  if (x >= 1) return 1;
  if (x > (a + 1) / (a + b + 2)) return 1 - incompleteBeta(1 - x, b, a);
  const double front =
      std::exp(a * std::log(x) + b * std::log1p(-x) - (std::lgamma(a) + std::lgamma(b) - std::lgamma(a + b))) / a;
  constexpr double kTiny = 1e-300;
  auto guard = [](double v) { return std::fabs(v) < kTiny ? kTiny : v; };
  double c = 1, d = 1 / guard(1 - (a + b) * x / (a + 1)), f = d;
  for (int m = 1; m <= 300; ++m) {
    const double even = m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m));
    const double odd = -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
    double step = 1;
    for (double num : {even, odd}) {
      d = 1 / guard(1 + num * d);
      c = guard(1 + num / c);
      step = c * d;
      f *= step;
    }
    if (std::fabs(step - 1) < 1e-15) break;
  }
  return front * f;
}

double studentCdf(double t, double df) {
  const double tail = 0.5 * incompleteBeta(df / (df + t * t), df / 2, 0.5);
  return t >= 0 ? 1 - tail : tail;
}

}  // namespace

Observation observe(const log::RunRecord& run) {
  Observation o;
  const std::optional<double>& total = run.summary.total_time;
  o.solved = run.status == log::RunStatus::Solved && total && *total > 0;
  if (o.solved) o.time = *total;
  if (run.meta.time_limit && *run.meta.time_limit > 0) o.limit = run.meta.time_limit;
  else if (total) o.limit = total;
  return o;
}

RateInterval wilson(int successes, int n) {
  if (n <= 0) return {};
  const double p = static_cast<double>(successes) / n, z2 = kZ95 * kZ95;
  const double denom = 1 + z2 / n;
  const double centre = (p + z2 / (2.0 * n)) / denom;
  const double half = kZ95 / denom * std::sqrt(p * (1 - p) / n + z2 / (4.0 * n * n));
  return {p, std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

double studentQuantile(double p, double df) {
  double lo = 0, hi = 1;
  while (studentCdf(hi, df) < p && hi < 1e12) hi *= 2;
  for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (studentCdf(mid, df) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

std::optional<double> signTestP(int k, int n) {
  if (n <= 0) return std::nullopt;
  const int m = std::min(k, n - k);
  // log C(n, i) - n ln 2, summed for i = 0..m in log space (no underflow for large n).
  double log_term = -n * std::log(2.0), log_sum = log_term;
  for (int i = 1; i <= m; ++i) {
    log_term += std::log(static_cast<double>(n - i + 1) / i);
    log_sum += std::log1p(std::exp(log_term - log_sum));
  }
  return std::min(1.0, 2 * std::exp(log_sum));
}

int gehanScore(const Observation& a, const Observation& b) {
  if (a.solved && b.solved) return a.time < b.time ? 1 : a.time > b.time ? -1 : 0;
  if (a.solved && b.limit && a.time <= *b.limit) return 1;
  if (b.solved && a.limit && b.time <= *a.limit) return -1;
  return 0;
}

PairedStats pairedStats(const std::vector<std::pair<Observation, Observation>>& pairs) {
  PairedStats s;
  s.pairs = static_cast<int>(pairs.size());
  std::vector<double> logs;
  for (const auto& [a, b] : pairs) {
    if (a.solved && b.solved) logs.push_back(std::log(a.time / b.time));
    const int score = gehanScore(a, b);
    s.a_faster += score > 0;
    s.b_faster += score < 0;
    s.a_solved += a.solved;
    s.b_solved += b.solved;
  }
  s.undecided = s.pairs - s.a_faster - s.b_faster;
  s.both_solved = static_cast<int>(logs.size());
  if (!logs.empty()) {
    const double m = static_cast<double>(logs.size());
    const double mean = std::accumulate(logs.begin(), logs.end(), 0.0) / m;
    s.ratio = std::exp(mean);
    if (logs.size() >= 2) {
      double ss = 0;
      for (double v : logs) ss += (v - mean) * (v - mean);
      const double half = studentQuantile(0.975, m - 1) * std::sqrt(ss / (m - 1)) / std::sqrt(m);
      s.ratio_low = std::exp(mean - half);
      s.ratio_high = std::exp(mean + half);
    }
  }
  s.p_value = signTestP(s.a_faster, s.a_faster + s.b_faster);
  s.a_success = wilson(s.a_solved, s.pairs);
  s.b_success = wilson(s.b_solved, s.pairs);
  return s;
}

}  // namespace dash::figures
