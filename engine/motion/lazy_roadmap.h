#pragma once
// An edge-unvalidated roadmap for one robot (OMPL's Lazy-PRM, Bohlin & Kavraki 2000), reused across
// the queries of a run. Lazy-PRM checks vertices and edges only on the paths it returns and caches the
// result. Validity here depends on the motion context (held object, resting objects), so when the
// context changes the cached flags are cleared (clearValidity) while the roadmap itself is kept.
// Departure from a context-free Lazy-PRM: vertices or edges found invalid in one context are removed by
// OMPL for good; the roadmap keeps sampling, so it regrows where they were.
#include <memory>
#include <optional>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/core/deadline.h"
#include "engine/events/event_emitter.h"
#include "engine/motion/motion_context.h"

namespace ompl::geometric {
class LazyPRM;
}
namespace ompl::base {
class Planner;
class SpaceInformation;
}

namespace dash {

struct RoadmapParams {
  double max_edge_length = 1.5;         ///< radians (joint space) or metres (gantry), OMPL setRange
  unsigned int neighbours = 10;         ///< k nearest neighbours
  /// Work budget of one query: samples (Lazy-PRM adds one milestone per iteration). Work, not time,
  /// so that a run does the same on a loaded machine as on an idle one (same seed, same plan).
  std::size_t query_samples = 5000;
  double query_seconds = 10.0;          ///< a ceiling per query on top of the work budget
  /// A roadmap this dense answers from what it has, growing by at most `dense_query_samples` per
  /// query: queries that still fail there ask for a narrow passage that more samples rarely find, and
  /// every sample makes the next query slower (thousands of replans in conflict resolution).
  std::size_t dense_vertices = 50000;
  std::size_t dense_query_samples = 1000;
  /// A roadmap this large stops growing: a query draws the one sample OMPL's Lazy-PRM needs before it
  /// searches, and answers from the roadmap. Past the dense size every sample of a failing query costs
  /// a search of the whole roadmap, so growth without a bound makes each failure slower than the last
  /// (stocking 3/18: 486k vertices after ~440 failing queries of one conflict-resolution round).
  std::size_t max_vertices = 100000;
  bool simplify = true;                 ///< shortcut the found path
  /// Work budget of one global-sampling query (queryTrees): RRT-Connect iterations.
  std::size_t tree_iterations = 20000;

  /// Multiplies the per-query work budgets and the time ceiling.
  void scale(double factor) {
    query_samples = static_cast<std::size_t>(static_cast<double>(query_samples) * factor);
    tree_iterations = static_cast<std::size_t>(static_cast<double>(tree_iterations) * factor);
    query_seconds *= factor;
  }
};

/// Samples one roadmap query may add to a roadmap of `vertices` vertices (its work budget).
std::size_t querySampleBudget(const RoadmapParams& params, std::size_t vertices);

class LazyRoadmap {
 public:
  LazyRoadmap(const CollisionWorld& world, CollisionContext& context, int robot, RoadmapParams params = {});
  ~LazyRoadmap();

  /// A collision-free path q_start -> q_goal in `motion` (straight segments, checked at the segment
  /// resolution), or nullopt. Grows the roadmap as needed.
  std::optional<std::vector<JointVector>> query(const JointVector& q_start, const JointVector& q_goal,
                                                const MotionContext& motion, const Deadline& deadline);
  /// Global sampling, for when query() found no path between valid ends: OMPL's RRT-Connect grows a
  /// tree from each end, and so gets out of narrow places next to them (deep in a shelf cubby) that the
  /// roadmap's uniform samples rarely reach. The roadmap itself is not changed.
  std::optional<std::vector<JointVector>> queryTrees(const JointVector& q_start, const JointVector& q_goal,
                                                     const MotionContext& motion, const Deadline& deadline);
  /// Multiplies the per-query budgets (after a motion failure was found to have no alternative).
  void scaleBudget(double factor);
  /// Where the roadmap books its construction time (see solve()); nullptr: nowhere.
  void setEmitter(log::EventEmitter* emitter) { emitter_ = emitter; }
  std::size_t vertexCount() const;
  std::size_t edgeCount() const;
  int robot() const { return robot_; }

  struct Checker;  ///< validity in the current context (defined in the .cpp)

 private:
  /// Sets the validity context; false if an end is invalid (answered at once, see query()).
  bool prepare(const JointVector& q_start, const JointVector& q_goal, const MotionContext& motion);
  /// Runs `planner` from q_start to q_goal for at most `work` condition evaluations (and the time
  /// ceiling), then simplifies the path.
  std::optional<std::vector<JointVector>> solve(ompl::base::Planner& planner, const JointVector& q_start,
                                                const JointVector& q_goal, std::size_t work, const Deadline& deadline);

  const CollisionWorld* world_;
  CollisionContext* context_;
  int robot_;
  RoadmapParams params_;
  std::shared_ptr<Checker> checker_;
  std::shared_ptr<ompl::base::SpaceInformation> si_;
  std::shared_ptr<ompl::geometric::LazyPRM> planner_;
  std::optional<MotionContext> last_context_;
  log::EventEmitter* emitter_ = nullptr;
};


}  // namespace dash
