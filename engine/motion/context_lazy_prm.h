#pragma once
// OMPL's Lazy-PRM (og::LazyPRM: its graph, nearest-neighbour structure, sampler and milestone
// connection) with validity split in two, for a roadmap that serves many motion contexts:
//  - static validity (the SpaceInformation's checkers: the robot against what never moves) is cached
//    in OMPL's flags, and what fails it is removed for good, as og::LazyPRM does;
//  - context validity (what the robot holds, the objects resting at that moment, robots standing
//    still) is checked only on the paths a query finds and remembered until the context changes; what
//    fails it is skipped by the searches of that context and never removed.
// og::LazyPRM removes whatever its (single) checker rejects, so a context-dependent checker made the
// roadmap decay wherever an object once rested or a robot once stood, and regrow there at the cost of
// a relabelling and a full A* per sample (stocking 3/18: 320-430 s of 600 in that bookkeeping).
// Include only from .cpp files that use OMPL.
#include <ompl/geometric/planners/prm/LazyPRM.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <vector>

namespace dash {

class ContextLazyPRM : public ompl::geometric::LazyPRM {
 public:
  using StateCheck = std::function<bool(const ompl::base::State*)>;
  using MotionCheck = std::function<bool(const ompl::base::State*, const ompl::base::State*)>;
  using StopCondition = std::function<bool()>;

  /// `static_si` checks the robot against what never moves.
  explicit ContextLazyPRM(const ompl::base::SpaceInformationPtr& static_si);

  /// The context changed: its verdicts are forgotten (static ones stay).
  void forgetContext();

  /// A path start -> goal (copies of OMPL's states, start and goal included) whose every vertex and edge
  /// is statically valid and valid in the context, or nullopt. Both ends must be valid in the context
  /// (the caller checked). Searches the roadmap, validating the path found as Lazy-PRM does (vertices
  /// first, then the first invalid edge), and when the roadmap has no path draws samples, in batches
  /// that grow with the roadmap (a search over a large roadmap costs more than a sample), at most
  /// `samples` in all. `stop` ends the query early (deadline, time ceiling).
  std::optional<std::vector<const ompl::base::State*>> solveInContext(const ompl::base::State* start,
                                                                      const ompl::base::State* goal,
                                                                      std::size_t samples, const StopCondition& stop,
                                                                      const StateCheck& context_state,
                                                                      const MotionCheck& context_motion);

  /// Samples drawn between two searches when the roadmap has `vertices` vertices.
  static std::size_t sampleBatch(std::size_t vertices);

  /// Adds `states` (copied) as milestones, each joined to its nearest neighbours as any sample and to
  /// the one before it in the list (a path found elsewhere: its states join the roadmap where uniform
  /// samples rarely land). The first and last states are query ends (deduplicated as such). Nothing is
  /// validated here: the static and context checks come when a search uses them, as for every other
  /// vertex and edge.
  void addPath(const std::vector<const ompl::base::State*>& states);

 private:
  // Context verdicts live in the high bits of OMPL's validity flags (bit 0: statically valid), tagged
  // with the context's generation, so that forgetting a context costs nothing and a search reads a
  // verdict without a lookup.
  static constexpr unsigned int kContextValid = 2u;
  static constexpr unsigned int kContextInvalid = 4u;
  static constexpr unsigned int kGenerationShift = 3u;
  static constexpr unsigned int kLastGeneration = (~0u) >> kGenerationShift;

  /// The verdict of `flags` in the current context: 1 valid, 0 invalid, -1 not checked yet.
  int contextVerdict(unsigned int flags) const;
  void setContextVerdict(unsigned int& flags, bool valid) const;

  Vertex addNumberedMilestone(ompl::base::State* state);
  /// The vertex of a query end: the one added for the same configuration before, or a new one. Ends
  /// recur (transition configurations, home); duplicates would tie in every nearest-neighbour query
  /// (kd_neighbors.h orders ties by insertion; OMPL's GNAT, used before, by address).
  Vertex endMilestone(const ompl::base::State* state);
  std::size_t id(Vertex v) const { return indexProperty_[v]; }
  /// A* over the roadmap minus what the context rejected; the vertices start .. goal, or empty.
  std::vector<Vertex> shortestPath(Vertex start, Vertex goal);
  /// Lazy-PRM's validation of a found path; false when something on it was invalid (removed or marked).
  bool validatePath(const std::vector<Vertex>& path, const StateCheck& context_state,
                    const MotionCheck& context_motion);
  void removeMilestone(Vertex v);

  std::size_t next_id_ = 0;
  std::map<std::vector<double>, Vertex> ends_;
  unsigned int generation_ = 1;
  // A* workspace, indexed by vertex id, reused by every search (a search's entries carry its stamp).
  struct SearchNode {
    double g = 0.0;
    double h = 0.0;               ///< heuristic to the current goal, valid while h_stamp == query_stamp_
    Vertex pred = nullptr;
    std::uint32_t stamp = 0;      ///< g and pred belong to the search with this stamp
    std::uint32_t h_stamp = 0;
  };
  std::vector<SearchNode> search_;
  std::uint32_t search_stamp_ = 0;
  std::uint32_t query_stamp_ = 0;
};

}  // namespace dash
