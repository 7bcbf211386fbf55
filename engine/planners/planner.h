#pragma once
// One interface for every planner of the workbench (Lazy-DaSH, DaSH): the same scene in, the same
// plan format, validator and event stream out. Planning outcomes are a status value, never an
// exception; bad input throws InputError.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/deadline.h"
#include "engine/log/event_emitter.h"
#include "engine/log/events.h"
#include "engine/plan/plan.h"
#include "engine/scene/scene.h"

namespace dash {

enum class PlanOutcome { kSolved, kTimeout, kInfeasible, kCancelled };
const char* toString(PlanOutcome outcome);

struct PlannerSettings {
  std::uint64_t seed = 1;
  double time_limit = 600.0;  ///< seconds; the deadline passed to solve() is what is enforced
  bool task_only = false;     ///< stop after the task layer (Lazy-DaSH: an unvalidated schedule)
  /// Faults for the batch runner's own tests (never used by a real run):
  /// "abort" calls std::abort() at the start; "ignore-deadline" plans past its deadline by spinning.
  std::string test_fault;
};

/// Sizes of the four representations of the paper, at the end of the run. Extended hypergraphs are
/// counted over every query of the run (what was built), as the event stream records them.
struct RepresentationCounts {
  std::size_t task_vertices = 0, task_hyperarcs = 0;
  std::size_t task_extended_vertices = 0, task_extended_hyperarcs = 0;
  std::size_t motion_vertices = 0, motion_hyperarcs = 0;
  std::size_t motion_extended_vertices = 0, motion_extended_hyperarcs = 0;
};

struct PlanStats {
  log::PhaseTotals phase_seconds{};
  RepresentationCounts sizes;
  int iterations = 0;
  std::int64_t collision_checks_eager = 0;  ///< checks done before they were needed (validated roadmaps, IK filters)
  std::int64_t collision_checks_lazy = 0;   ///< checks done on demand (lazy edges, transitions, schedules)
  std::int64_t roadmap_vertices = 0;
  std::int64_t roadmap_edges = 0;
  std::int64_t task_constraints = 0;
  std::int64_t motion_constraints = 0;
  std::int64_t task_space_expansions = 0;
  double makespan = 0.0;
  double path_length = 0.0;  ///< joint-space length summed over robots (radians / metres)
};

struct PlanResult {
  PlanOutcome outcome = PlanOutcome::kInfeasible;
  std::optional<Plan> plan;  ///< when solved: a plan the validator passed
  std::string message;       ///< why not solved; or the task-only schedule in readable form
  std::string task_plan_json;  ///< task-only runs: the unvalidated schedule as JSON
  PlanStats stats;
};

class Planner {
 public:
  virtual ~Planner() = default;
  virtual std::string name() const = 0;
  /// Plans for `scene` until solved, proven infeasible, or `deadline` expires (which also carries
  /// the stop flag for Ctrl-C and cancelled batches). Events go to `sink` (may be nullptr).
  virtual PlanResult solve(const Scene& scene, const PlannerSettings& settings, const Deadline& deadline,
                           log::EventSink* sink) = 0;
};

/// "lazy-dash" or "dash"; throws InputError for any other name.
std::unique_ptr<Planner> makePlanner(const std::string& name);
/// The same with the planner's collision clearance (m) set (LazyDashParams / DashParams::clearance).
std::unique_ptr<Planner> makePlanner(const std::string& name, double clearance);
/// The names makePlanner accepts.
std::vector<std::string> plannerNames();

}  // namespace dash
