#include "engine/task/task_plan.h"

#include <nlohmann/json.hpp>
#include <sstream>

namespace dash {

std::string describeStep(const TaskStep& step, const TaskSpace& space) {
  const Scene& scene = space.scene();
  const TaskArc& a = step.action;
  std::string s = taskArcTypeName(a.type);
  if (a.type == TaskArcType::kHandover) {
    s += " " + scene.robots[a.robot].id + " -> " + scene.robots[a.robot2].id + " " + scene.objects[a.object].id +
         " (" + graspClassName(a.grasp) + " -> " + graspClassName(a.grasp2) + ")";
  } else if (a.type == TaskArcType::kInspect) {
    s += " " + scene.robots[a.robot].id + " task#" + std::to_string(a.task);
  } else {
    s += " " + scene.robots[a.robot].id + " " + space.locationLabel(a.object, a.location) + " (" +
         graspClassName(a.grasp) + ")";
  }
  return s;
}

std::string TaskPlan::describe(const TaskSpace& space) const {
  std::ostringstream out;
  for (std::size_t i = 0; i < steps.size(); ++i) {
    out << "  " << i << ". " << describeStep(steps[i], space);
    if (!steps[i].after.empty()) {
      out << "   after";
      for (std::size_t k = 0; k < steps[i].after.size(); ++k) out << (k ? ", " : " ") << steps[i].after[k];
    }
    out << "\n";
  }
  return out.str();
}

std::string TaskPlan::toJson(const TaskSpace& space) const {
  const Scene& scene = space.scene();
  nlohmann::json j;
  j["steps"] = nlohmann::json::array();
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const TaskArc& a = steps[i].action;
    nlohmann::json s;
    s["index"] = i;
    s["type"] = taskArcTypeName(a.type);
    s["robot"] = scene.robots[a.robot].id;
    if (a.robot2 >= 0) s["robot2"] = scene.robots[a.robot2].id;
    if (a.object >= 0) s["object"] = scene.objects[a.object].id;
    if (a.location >= 0 && a.object >= 0) s["location"] = space.locationLabel(a.object, a.location);
    if (a.type != TaskArcType::kInspect) s["grasp"] = graspClassName(a.grasp);
    if (a.type == TaskArcType::kHandover) s["grasp2"] = graspClassName(a.grasp2);
    if (a.task >= 0) s["task"] = a.task;
    s["after"] = steps[i].after;
    j["steps"].push_back(std::move(s));
  }
  return j.dump(1);
}

RestingAlongPlan restingAlong(const TaskPlan& plan, const TaskSpace& space) {
  ObjectLayout layout = ObjectLayout::atStart(space.scene());
  std::vector<int> at(static_cast<std::size_t>(space.objectCount()));
  for (int o = 0; o < space.objectCount(); ++o) {
    layout.place(o, space.location(o, space.startLocation(o)).X_WO);
    at[o] = space.startLocation(o);
  }
  RestingAlongPlan out;
  for (const TaskStep& step : plan.steps) {
    out.layouts.push_back(layout);
    out.locations.push_back(at);
    if (step.action.type == TaskArcType::kPick) {
      layout.remove(step.action.object);
      at[step.action.object] = -1;
    }
    if (step.action.type == TaskArcType::kPlace) {
      layout.place(step.action.object, space.location(step.action.object, step.action.location).X_WO);
      at[step.action.object] = step.action.location;
    }
  }
  out.layouts.push_back(layout);
  out.locations.push_back(at);
  return out;
}

}  // namespace dash
