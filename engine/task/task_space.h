#pragma once
// The task space of one planning run: the scene plus the explicit object locations that object-only
// task space elements O_j@l refer to. Lazy-DaSH starts minimal (each object's start and goal only) and
// adds extra stable poses ("move-out" states, lab sanitisation spots) when task conflict detection
// asks for a task space expansion.
#include <optional>
#include <string>
#include <vector>

#include "engine/geometry/pose.h"
#include "engine/scene/scene.h"

namespace dash {

struct ObjectLocation {
  enum class Kind { kStart, kGoal, kStartAndGoal, kExtra };
  Kind kind = Kind::kStart;
  Pose X_WO = Pose::Identity();
  /// Not anchored at the start or goal: task conflict detection may move it (paper: resample).
  bool resampleable = false;
  int surface = -1;  ///< the scene surface it rests on, for resampling (-1: unknown)

  bool isStart() const { return kind == Kind::kStart || kind == Kind::kStartAndGoal; }
  bool isGoal() const { return kind == Kind::kGoal || kind == Kind::kStartAndGoal; }
};

class TaskSpace {
 public:
  /// Start and goal locations only; a goal within 1 mm and 0.01 rad of the start is the same location.
  explicit TaskSpace(const Scene& scene);

  const Scene& scene() const { return *scene_; }
  int objectCount() const { return static_cast<int>(locations_.size()); }
  const std::vector<ObjectLocation>& locations(int object) const { return locations_[object]; }
  const ObjectLocation& location(int object, int index) const { return locations_[object][index]; }
  int startLocation(int object) const;  ///< always valid
  int goalLocation(int object) const;   ///< -1 if the object has no goal
  /// The object must not move (scene `fixed`).
  bool isFixed(int object) const { return scene_->objects[object].fixed; }

  /// Adds an extra stable pose; returns its index.
  int addExtraLocation(int object, const Pose& X_WO, int surface);
  /// Moves a resampleable location (task conflict detection resolving a pose conflict).
  /// A new pose for a resampleable location (and its support surface, unless -1).
  void resample(int object, int index, const Pose& X_WO, int surface = -1);
  int extraLocationCount(int object) const;
  /// "O3@goal", "O1@extra2" for people and logs.
  std::string locationLabel(int object, int index) const;

 private:
  const Scene* scene_;
  std::vector<std::vector<ObjectLocation>> locations_;
};

}  // namespace dash
