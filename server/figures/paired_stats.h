#pragma once
// Statistics that count failures, for two planner configurations run on the same scenes and seeds
// (`dashbench report`; the Compare page computes the same in web/js/paired_stats.js, and both are
// checked against the hand-worked cases in tests/figures/paired_stats_cases.json):
//   - the seed-paired time ratio: the geometric mean of a/b over the pairs both solved, with a 95 %
//     Student t interval on the log ratios;
//   - a paired sign test on Gehan's pair scores. An unsolved run (timeout, infeasible, crash) is
//     censored at its time limit: its time to solve is only known to exceed the limit, so a solved
//     partner at or under that limit is faster and two unsolved runs say nothing. Failures are neither
//     dropped nor counted as taking the limit. (A Wilcoxon signed-rank test would need the size of
//     every difference, unknown for censored pairs; the sign test needs only their order.) Two-sided
//     exact binomial p over the decided pairs;
//   - success rates with 95 % Wilson score intervals (sound at 0 % and 100 %, unlike the Wald one).
#include <optional>
#include <utility>
#include <vector>

#include "engine/log/results_db.h"

namespace dash::figures {

/// One run as the statistics see it: solved at `time` (s), or censored at `limit` (s: its time
/// limit, its own total time when it has none; unset when neither is known).
struct Observation {
  bool solved = false;
  double time = 0;
  std::optional<double> limit;
};

Observation observe(const log::RunRecord& run);

/// A rate with its 95 % Wilson score interval; all unset when n is 0.
struct RateInterval {
  std::optional<double> rate, low, high;
};
RateInterval wilson(int successes, int n);

/// The p quantile (0.5 < p < 1) of Student's t with `df` degrees of freedom.
double studentQuantile(double p, double df);

/// Two-sided exact sign test: P of a split at least as uneven as k of n under Binomial(n, 1/2);
/// unset when n is 0.
std::optional<double> signTestP(int k, int n);

/// Gehan's score of a pair: 1 when a is known to solve faster, -1 when b is, 0 when the order is
/// unknown (both unsolved, a tie, or a solve after the partner's limit).
int gehanScore(const Observation& a, const Observation& b);

struct PairedStats {
  int pairs = 0;
  int both_solved = 0;
  std::optional<double> ratio, ratio_low, ratio_high;  ///< a/b of total time; the interval needs 2 pairs
  int a_faster = 0, b_faster = 0, undecided = 0;
  std::optional<double> p_value;
  int a_solved = 0, b_solved = 0;
  RateInterval a_success, b_success;
};

PairedStats pairedStats(const std::vector<std::pair<Observation, Observation>>& pairs);

}  // namespace dash::figures
