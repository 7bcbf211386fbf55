#pragma once
// Task space elements of the multi-manipulator rearrangement problem (paper, "Task Space"):
//   robot alone          R_i          hand-free constraint h_c(r_i)
//   robot holding object R_i+O_j(g)   formation constraint f_c(r_i, o_j, t), grasp class g
//   object at a location O_j@l        stability constraint s_c(o_j, q) at an explicit location
//   task pending / done  T_k, T_k*    an extra goal such as a lab inspection
#include <cstdint>
#include <functional>
#include <string>

namespace dash {

/// Grasp classes of the paper ("sides, top, bottom"). The concrete grasp (which face, which finger
/// axis) is chosen when transition configurations are sampled in task conflict detection.
enum class GraspClass : std::int8_t { kTop = 0, kSide = 1, kBottom = 2 };
inline constexpr int kGraspClassCount = 3;
const char* graspClassName(GraspClass g);

enum class ElementKind : std::int8_t { kRobot, kHolding, kObjectAt, kTaskPending, kTaskDone, kSource, kSink };

struct TaskElement {
  ElementKind kind = ElementKind::kRobot;
  std::int16_t robot = -1;
  std::int16_t object = -1;
  std::int16_t location = -1;  ///< index into the object's locations (kObjectAt)
  std::int16_t task = -1;      ///< index into scene.tasks (kTaskPending / kTaskDone)
  GraspClass grasp = GraspClass::kTop;  ///< kHolding only

  static TaskElement robotAlone(int r) { return {ElementKind::kRobot, static_cast<std::int16_t>(r)}; }
  static TaskElement holding(int r, int o, GraspClass g) {
    return {ElementKind::kHolding, static_cast<std::int16_t>(r), static_cast<std::int16_t>(o), -1, -1, g};
  }
  static TaskElement objectAt(int o, int l) {
    return {ElementKind::kObjectAt, -1, static_cast<std::int16_t>(o), static_cast<std::int16_t>(l)};
  }
  static TaskElement taskState(int t, bool done) {
    return {done ? ElementKind::kTaskDone : ElementKind::kTaskPending, -1, -1, -1, static_cast<std::int16_t>(t)};
  }

  static TaskElement source() { return {ElementKind::kSource}; }
  static TaskElement sink() { return {ElementKind::kSink}; }

  bool operator==(const TaskElement&) const = default;
};

}  // namespace dash

template <>
struct std::hash<dash::TaskElement> {
  std::size_t operator()(const dash::TaskElement& e) const noexcept {
    std::uint64_t k = static_cast<std::uint64_t>(static_cast<std::uint8_t>(e.kind));
    k = k * 1031 + static_cast<std::uint16_t>(e.robot);
    k = k * 65599 + static_cast<std::uint16_t>(e.object);
    k = k * 65599 + static_cast<std::uint16_t>(e.location);
    k = k * 65599 + static_cast<std::uint16_t>(e.task);
    k = k * 7 + static_cast<std::uint8_t>(e.grasp);
    return std::hash<std::uint64_t>{}(k);
  }
};
