#pragma once
// The axis-stop rule of a batch spec (a scenario entry's "stop_axis": "objects"): along that
// parameter, a planner configuration that fails a size on every seed is not run at the larger sizes
// of the same line (same family, same other parameters, same planner configuration). Those runs are
// recorded as skipped, with the reason, and never run, so comparison batches that go past a planner's
// failure point finish in hours. A size is judged once all of its seeds have a final result (solved or
// not); a larger size waits for that. `batch resume` rebuilds the rule from the stored results.
#include <map>
#include <string>
#include <vector>

#include "server/batch/batch_spec.h"

namespace dash::batch {

class AxisStop {
 public:
  enum class Verdict { kRun, kWait, kSkip };
  struct Decision {
    Verdict verdict = Verdict::kRun;
    std::string reason;  ///< kSkip: which size failed on every seed
  };

  /// `runs`: every run of the batch (those already finished included).
  explicit AxisStop(const std::vector<RunSpec>& runs);

  /// A run has a final result (a skipped run counts as not solved).
  void finished(const RunSpec& run, bool solved);
  /// Whether `run` may start now, must wait for smaller sizes, or is skipped.
  Decision decide(const RunSpec& run) const;

 private:
  struct Size {
    int total = 0;
    int finished = 0;
    int solved = 0;
  };
  static std::string lineOf(const RunSpec& run);
  static int axisValue(const RunSpec& run);

  std::map<std::string, std::map<int, Size>> lines_;  ///< line -> axis value -> counts
};

}  // namespace dash::batch
