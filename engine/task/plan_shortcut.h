#pragma once
// Round trips removed from a task plan. The greedy task query is depth first: under frontier
// constraints it may take an object out of its place and put it back many times (stocking, three
// layers: thousands of steps), each trip letting something else move one step. A trip (an object
// picked from location L, passed between hands, maybe set down and picked up elsewhere, and placed
// back at L) is removed when nothing that happens meanwhile needs L free: no step in between produces
// the v_post of a frontier constraint whose v_pre is "object at L". The robots involved held nothing
// else meanwhile, so every robot's sequence stays consistent; dependencies are rebuilt from who
// touched what last. Task conflict detection then checks the shorter plan as usual (a blockage it
// finds there becomes a constraint, and the next query keeps that trip).
#include "engine/task/task_constraints.h"
#include "engine/task/task_plan.h"

namespace dash {

/// The plan without removable round trips (unchanged if it has inspect steps); `removed` counts steps.
TaskPlan removeRoundTrips(const TaskPlan& plan, const TaskHypergraph& graph, const TaskConstraintSet& constraints,
                          int* removed = nullptr);

/// Each step's `after`: the last earlier steps that touched its robots or its object.
void rebuildDependencies(TaskPlan& plan);

}  // namespace dash
