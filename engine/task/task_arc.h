#pragma once
// Task hyperarcs: abstract transitions between sets of task space elements (no motion detail).
#include <cstdint>
#include <functional>

#include "engine/task/task_element.h"

namespace dash {

enum class TaskArcType : std::int8_t { kSource, kSink, kPick, kPlace, kHandover, kInspect };
const char* taskArcTypeName(TaskArcType t);

/// The property of a task hyperarc. Tail and head sets live in the hypergraph; this names the action.
struct TaskArc {
  TaskArcType type = TaskArcType::kPick;
  std::int16_t robot = -1;     ///< pick/place/inspect actor; handover giver
  std::int16_t robot2 = -1;    ///< handover receiver
  std::int16_t object = -1;
  std::int16_t location = -1;  ///< pick: from, place: to
  std::int16_t task = -1;      ///< inspect
  GraspClass grasp = GraspClass::kTop;   ///< actor's grasp (giver's for a handover)
  GraspClass grasp2 = GraspClass::kTop;  ///< receiver's grasp
  double cost = 0.0;  ///< estimated cost (distance based), used by the greedy query

  bool operator==(const TaskArc& o) const {
    return type == o.type && robot == o.robot && robot2 == o.robot2 && object == o.object &&
           location == o.location && task == o.task && grasp == o.grasp && grasp2 == o.grasp2;
  }
};

}  // namespace dash

template <>
struct std::hash<dash::TaskArc> {
  std::size_t operator()(const dash::TaskArc& a) const noexcept {
    std::uint64_t k = static_cast<std::uint8_t>(a.type);
    for (std::int16_t v : {a.robot, a.robot2, a.object, a.location, a.task}) k = k * 65599 + static_cast<std::uint16_t>(v);
    k = k * 7 + static_cast<std::uint8_t>(a.grasp);
    k = k * 7 + static_cast<std::uint8_t>(a.grasp2);
    return std::hash<std::uint64_t>{}(k);
  }
};
