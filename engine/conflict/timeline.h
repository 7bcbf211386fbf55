#pragma once
// Timed trajectories of the schedule being built: each robot's points (joined linearly, held still
// after the last one) and what it holds when; each object's resting poses over time.
#include <limits>
#include <vector>

#include "engine/collision/collision_state.h"
#include "engine/scene/object_layout.h"

namespace dash {

inline constexpr double kForever = std::numeric_limits<double>::infinity();

struct TimedPoint {
  double t = 0.0;
  JointVector q;
};

struct HoldInterval {
  double from = 0.0;       ///< grasp time
  double to = kForever;    ///< release time
  HeldObject held;
};

class RobotTimeline {
 public:
  RobotTimeline(int robot, const JointVector& home);

  int robot() const { return robot_; }
  const std::vector<TimedPoint>& points() const { return points_; }
  double end() const { return points_.back().t; }
  const JointVector& last() const { return points_.back().q; }
  JointVector at(double t) const;
  /// What the robot holds over [t, t'): the interval containing t (empty hand if none).
  HeldObject heldAt(double t) const;
  /// What the robot holds from its last point on (a grasp with no release yet).
  HeldObject heldAtEnd() const;
  /// Point times strictly inside (a, b).
  void breakpoints(double a, double b, std::vector<double>& out) const;

  /// Appends a point; t must be after end() (equal times merge if q is equal).
  void append(double t, const JointVector& q);
  void grasp(double t, const HeldObject& held);
  void release(double t);
  const std::vector<HoldInterval>& holds() const { return holds_; }

  /// Where the timeline stands now, to come back to after later appends, grasps and releases.
  struct Mark {
    std::size_t points = 0;
    std::vector<HoldInterval> holds;
  };
  Mark mark() const { return {points_.size(), holds_}; }
  /// Back to a mark taken on this timeline (everything appended since is dropped).
  void rewind(const Mark& mark);

 private:
  int robot_;
  std::vector<TimedPoint> points_;
  std::vector<HoldInterval> holds_;
};

/// Where each object rests over time (absent while held).
class ObjectTimeline {
 public:
  explicit ObjectTimeline(const ObjectLayout& start);

  void pick(int object, double t);                 ///< leaves its resting pose at t
  void place(int object, double t, const Pose& X_WO);  ///< rests at X_WO from t
  /// The objects resting throughout [a, b) and where (call with no event strictly inside).
  ObjectLayout layoutAt(double t) const;
  /// Event times strictly inside (a, b).
  void breakpoints(double a, double b, std::vector<double>& out) const;

  /// Changes recorded so far; rewind(n) drops those recorded after the first n.
  std::size_t mark() const { return changes_.size(); }
  void rewind(std::size_t mark);

 private:
  struct Change {
    double t;
    int object;
    bool present;
    Pose X_WO;
  };
  ObjectLayout start_;
  std::vector<Change> changes_;
};

}  // namespace dash
