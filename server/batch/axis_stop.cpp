#include "server/batch/axis_stop.h"

namespace dash::batch {

AxisStop::AxisStop(const std::vector<RunSpec>& runs) {
  for (const RunSpec& r : runs)
    if (!r.stop_axis.empty()) ++lines_[lineOf(r)][axisValue(r)].total;
}

std::string AxisStop::lineOf(const RunSpec& run) {
  std::string line = run.family + "/";
  for (const auto& [name, value] : run.params)
    if (name != run.stop_axis) line += name + "=" + std::to_string(value) + ",";
  return line + "/" + run.label;
}

int AxisStop::axisValue(const RunSpec& run) {
  for (const auto& [name, value] : run.params)
    if (name == run.stop_axis) return value;
  return 0;
}

void AxisStop::finished(const RunSpec& run, bool solved) {
  if (run.stop_axis.empty()) return;
  const auto line = lines_.find(lineOf(run));
  if (line == lines_.end()) return;
  const auto size = line->second.find(axisValue(run));
  if (size == line->second.end()) return;
  ++size->second.finished;
  if (solved) ++size->second.solved;
}

AxisStop::Decision AxisStop::decide(const RunSpec& run) const {
  if (run.stop_axis.empty()) return {};
  const auto line = lines_.find(lineOf(run));
  if (line == lines_.end()) return {};
  const int value = axisValue(run);
  bool wait = false;
  for (const auto& [smaller, size] : line->second) {
    if (smaller >= value) break;
    if (size.finished < size.total) {
      wait = true;
      continue;
    }
    if (size.solved == 0)
      return {Verdict::kSkip, run.label + " solved none of the " + std::to_string(size.total) + " runs at " +
                                  run.stop_axis + "=" + std::to_string(smaller)};
  }
  return {wait ? Verdict::kWait : Verdict::kRun, ""};
}

}  // namespace dash::batch
