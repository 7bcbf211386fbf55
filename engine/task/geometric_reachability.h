#pragma once
// H_T reachability from the real geometry: a robot can grasp an object at a pose if some grasp
// candidate of the class has an IK solution free of self and obstacle collisions (resting objects are
// ignored: that is task conflict detection's job). Handovers are assumed feasible for two arms within
// range of each other — the lazy assumption that conflict detection may refute. Results are cached,
// so rebuilding H_T after a task space expansion costs only the new locations.
#include <map>
#include <tuple>

#include "engine/task/reachability.h"
#include "engine/task/transition_sampler.h"

namespace dash {

struct ReachabilityParams {
  double max_handover_base_distance = 1.8;  ///< metres between the bases of two arms (reach ~1 m each)
};

class GeometricReachability {
 public:
  GeometricReachability(TransitionSampler& sampler, ReachabilityParams params = {});
  /// The oracle for TaskHypergraph::build; valid while this object lives.
  TaskReachability oracle();

  bool canGrasp(int robot, int object, const Pose& X_WO, GraspClass g);
  bool canHandover(int giver, int receiver, GraspClass g1, GraspClass g2) const;
  bool canInspect(int robot, int task);
  std::size_t checksDone() const { return checks_; }

 private:
  TransitionSampler* sampler_;
  ReachabilityParams params_;
  // Key: robot, object, grasp class, pose rounded to 0.1 mm.
  std::map<std::tuple<int, int, int, long, long, long, long>, bool> grasp_cache_;
  std::size_t checks_ = 0;
};

}  // namespace dash
