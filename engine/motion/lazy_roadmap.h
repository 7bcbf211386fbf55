#pragma once
// An edge-unvalidated roadmap for one robot (OMPL's Lazy-PRM, Bohlin & Kavraki 2000), reused across
// the queries of a run. Lazy-PRM checks vertices and edges only on the paths it returns and caches the
// result. Validity here has two parts (context_lazy_prm.h): static (the robot with an empty hand against
// what never moves), cached for good, what fails it removed as Lazy-PRM does; and the motion context
// (held object, resting objects, robots standing still), cached until the context changes, what fails
// it only skipped: the roadmap keeps every vertex and edge a later context may use.
#include <memory>
#include <optional>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/core/deadline.h"
#include "engine/events/event_emitter.h"
#include "engine/motion/motion_context.h"

namespace ompl::geometric {
class PathGeometric;
}
namespace ompl::base {
class SpaceInformation;
}

namespace dash {

class ContextLazyPRM;

struct RoadmapParams {
  double max_edge_length = 1.5;         ///< radians (joint space) or metres (gantry), OMPL setRange
  unsigned int neighbours = 10;         ///< k nearest neighbours
  /// Work budget of one query: samples (milestones added to the roadmap). Work, not time,
  /// so that a run does the same on a loaded machine as on an idle one (same seed, same plan).
  std::size_t query_samples = 5000;
  double query_seconds = 10.0;          ///< a ceiling per query on top of the work budget
  /// A roadmap this dense grows by at most `dense_query_samples` per query. A joint-space roadmap
  /// needs some thousands of samples to connect at all, but most queries that fail on a dense one
  /// (conflict resolution asks around robots standing in the way) fail whatever the budget, and every
  /// sample they add makes each later search slower: shelf-wall 4/32 seed 1 spent 194 of 213 s of
  /// roadmap queries in 156 failing ones (5000 samples up to 50k vertices, 600k vertices in all), and
  /// solved in 165 s instead of 477 s with 1000 samples and a 30k cap (51 s with these defaults).
  std::size_t dense_vertices = 10000;
  std::size_t dense_query_samples = 1000;
  /// A roadmap this large stops growing: a query answers from what the roadmap has. Every search of a
  /// failing query covers what it reaches of the roadmap, so growth without a bound makes each
  /// failure slower than the last (stocking 3/18: 486k vertices after ~440 failing queries of one
  /// conflict-resolution round).
  std::size_t max_vertices = 30000;
  bool simplify = true;                 ///< shortcut the found path
  /// Work budget of the simplification: vertex-removal attempts, and attempts in a row that remove
  /// nothing (OMPL's defaults are the path's state count for both). Each attempt checks a motion in
  /// the query's context; around robots standing in the way (conflict resolution) that is most of a
  /// query's cost: 27 % of sorting 16/64 seed 1 went to reduceVertices.
  unsigned int simplify_steps = 16;
  unsigned int simplify_empty_steps = 4;
  /// Work budget of one global-sampling query (queryTrees): RRT-Connect iterations.
  std::size_t tree_iterations = 20000;
  /// A path global sampling finds joins the roadmap (its states as milestones, consecutive ones joined):
  /// the long moves the roadmap misses recur (sorting 16/64 seed 1: a giver carrying its object half a
  /// turn round, 12.7 rad of joint travel, the same move for several robots and twice for some; the
  /// roadmap failed 64 times in the motion layer, each after its whole sample budget, and RRT-Connect
  /// found a path every time). The path's states join even a roadmap at max_vertices (a few per
  /// global-sampling query, which has its own work budget).
  bool keep_tree_paths = true;

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
  /// roadmap's uniform samples rarely reach. With keep_tree_paths the path found (before
  /// simplification) joins the roadmap.
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
  /// A found path, simplified (in the context) and with exactly the requested ends.
  std::vector<JointVector> finish(ompl::geometric::PathGeometric& path, const JointVector& q_start,
                                  const JointVector& q_goal) const;
  void bookConstruction(double seconds, double check_seconds_before);

  const CollisionWorld* world_;
  CollisionContext* context_;
  int robot_;
  RoadmapParams params_;
  std::shared_ptr<Checker> checker_;
  std::shared_ptr<ompl::base::SpaceInformation> static_si_;  ///< the roadmap's own (static) validity
  std::shared_ptr<ompl::base::SpaceInformation> si_;         ///< validity in the context: trees, simplifier
  std::shared_ptr<ContextLazyPRM> planner_;
  std::optional<MotionContext> last_context_;
  log::EventEmitter* emitter_ = nullptr;
};


}  // namespace dash
