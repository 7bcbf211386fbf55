#pragma once
// A plan in the dashbench.plan/1 format (docs/formats.md): one joint-space trajectory
// per robot (points joined by straight lines, held still after the last point) and the timed grasp,
// release and inspect events. Plain value type; the JSON codec is plan_json.h and the contract check
// is plan_validator.h.
#include <string>
#include <vector>

#include "engine/geometry/pose.h"
#include "engine/robots/joint_vector.h"

namespace dash {

struct Scene;

inline constexpr const char* kPlanFormat = "dashbench.plan/1";
/// The only status a plan file may carry (a failed run writes no plan file).
inline constexpr const char* kPlanStatusSolved = "solved";

struct TrajectoryPoint {
  double t = 0.0;  ///< seconds from the start of the plan
  JointVector q;   ///< in the order of the robot's joint_names
};

/// One robot's trajectory ("robots": {"<id>": {...}} in the file).
struct RobotTrajectory {
  std::string robot;                     ///< the scene robot's id
  std::vector<std::string> joint_names;  ///< must equal the model's, in order
  std::vector<TrajectoryPoint> points;   ///< strictly increasing t, first at t = 0

  /// Joint positions at time `t`: linear interpolation between the points around t, the last point
  /// from then on, the first point before it (a plan whose first point is not at t = 0 is invalid, but
  /// the validator still needs a position). Throws InputError if t < 0 or there are no points.
  JointVector positionAt(double t) const;
  /// Time of the last point (0 if there are none).
  double endTime() const;
};

struct PlanEvent {
  enum class Type { kGrasp, kRelease, kInspect };
  Type type = Type::kGrasp;
  double t = 0.0;
  std::string robot;
  std::string object;           ///< grasp, release; optional for inspect (written only if set)
  Pose X_TO = Pose::Identity();  ///< grasp only: the object in the TCP frame
  int task = -1;                ///< inspect only: index into Scene::tasks
};

/// "grasp", "release", "inspect".
const char* eventTypeName(PlanEvent::Type type);

struct Plan {
  std::string format = kPlanFormat;
  std::string scene;    ///< the scene's name
  std::string planner;  ///< "lazy-dash", "dash", "hand-made", ...
  std::string status = kPlanStatusSolved;
  double makespan = 0.0;
  /// Robot trajectories in a fixed order: file order when parsed, scene order when a planner builds
  /// the plan (sortRobots puts them in scene order). Output follows this order, so it is deterministic.
  std::vector<RobotTrajectory> robots;
  std::vector<PlanEvent> events;  ///< file order; need not be sorted by time
  /// The optional "tpg" field (the temporal plan graph, engine/tpg/tpg.h, docs/formats.md) as compact
  /// JSON text of an object; empty when the plan has none. engine/tpg parses and checks its content.
  std::string tpg;

  const RobotTrajectory* findRobot(const std::string& id) const;  ///< nullptr if absent
  RobotTrajectory* findRobot(const std::string& id);
  /// Orders `robots` by the scene's robot order; robots the scene lacks go last, by id.
  void sortRobots(const Scene& scene);
  /// The latest point or event time (what makespan should be).
  double lastTime() const;
  /// The joint-space length of every robot's trajectory, summed (radians and metres alike).
  double jointPathLength() const;
};

}  // namespace dash
