#pragma once
// One interface for every planner of the workbench (Lazy-DaSH, DaSH): the same scene in, the same
// plan format, validator and event stream out. Planning outcomes are a status value, never an
// exception; bad input throws InputError.
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/deadline.h"
#include "engine/core/planner_params.h"
#include "engine/events/event_emitter.h"
#include "engine/events/events.h"
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
  /// Named planner parameters set for this run (engine/core/planner_params.h); the rest keep their
  /// defaults. The planner checks them (InputError naming a bad one).
  ParamValues params;
};

/// The batch runner's test faults (PlannerSettings::test_fault), at the start of a planner's solve().
inline void applyTestFault(const PlannerSettings& settings) {
  if (settings.test_fault == "abort") std::abort();
  if (settings.test_fault == "ignore-deadline") {
    volatile std::uint64_t spin = 0;
    for (;;) spin = spin + 1;  // never returns: the batch runner must kill it from outside
  }
}

/// Sizes of the four representations of the paper, at the end of the run. Extended hypergraphs are
/// counted over every query of the run (what was built), as the event stream records them.
struct RepresentationCounts {
  std::size_t task_vertices = 0, task_hyperarcs = 0;
  std::size_t task_extended_vertices = 0, task_extended_hyperarcs = 0;
  std::size_t motion_vertices = 0, motion_hyperarcs = 0;
  std::size_t motion_extended_vertices = 0, motion_extended_hyperarcs = 0;
};

/// One planning space's roadmap (a robot with an empty hand, or holding), at the end of the run.
struct RoadmapSize {
  std::string space;  ///< "ur5e_0/empty", "ur5e_0/holding"
  std::int64_t vertices = 0;
  std::int64_t edges = 0;
};

struct PlanStats {
  /// Seconds per phase; phases are exclusive (a nested one pauses the enclosing one), so their sum is
  /// the planner's accounted time, at most wall_seconds.
  log::PhaseTotals phase_seconds{};
  double wall_seconds = 0.0;
  RepresentationCounts sizes;
  int iterations = 0;
  std::int64_t collision_checks_eager = 0;  ///< checks done before they were needed (validated roadmaps, IK filters)
  std::int64_t collision_checks_lazy = 0;   ///< checks done on demand (lazy edges, transitions, schedules)
  std::int64_t roadmap_vertices = 0;  ///< over every planning space
  std::int64_t roadmap_edges = 0;
  std::vector<RoadmapSize> roadmaps;  ///< per planning space that has a roadmap
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
