#include "engine/dash/dash_planner.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <cstdlib>
#include <set>
#include <unordered_set>

#include "engine/collision/collision_queries.h"
#include "engine/core/rng.h"
#include "engine/dash/dash_task_graph.h"
#include "engine/dash/motion_hypergraph.h"
#include "engine/dash/placement_sampling.h"
#include "engine/dash/plan_extraction.h"
#include "engine/dash/resting_conflicts.h"
#include "engine/motion/lazy_roadmap.h"
#include "engine/motion/seeded_ompl.h"
#include "engine/plan/plan_validator.h"
#include "engine/task/geometric_reachability.h"

namespace dash {

namespace {

/// The robot's own vertex in the tail of hyperarc a, and the first tail vertex that is not its own
/// (the object or handover partner the transition waits for: the interval of a schedule constraint).
std::pair<VertexId, VertexId> ownAndOtherTail(const MotionGraph& g, HyperarcId a, int robot) {
  VertexId own, other;
  for (VertexId v : g.tail(a)) {
    const MotionVertex& mv = g.property(v);
    const bool robot_vertex = mv.kind == MotionVertex::Kind::kRobot || mv.kind == MotionVertex::Kind::kHolding;
    if (robot_vertex && mv.robot == robot) own = v;
    else if (!other.valid()) other = v;
  }
  return {own, other};
}

/// The conflict a failed schedule (or a contact the validator found) reports at plan step `step`:
/// for each participant, the last move into the step (its transition when it did not move), not to be
/// traversed while the object or partner of the step waits in the state the step consumes (CBS-MP:
/// one constraint per robot in the conflict). Step -1: the ways home, at any time.
MotionConflict scheduleConflict(const MotionHypergraph& graph, const ExtractedPlan& plan, int step,
                                const std::string& why) {
  MotionConflict c;
  c.kind = MotionConflict::Kind::kSchedule;
  c.step = step;
  c.what = why;
  if (step >= 0) {
    const TaskStep& s = plan.plan.steps[step];
    const int participants = s.action.type == TaskArcType::kHandover ? 2 : 1;
    for (int role = 0; role < participants; ++role) {
      const int robot = role == 0 ? s.action.robot : s.action.robot2;
      const auto& moves = plan.step_moves[step][role];
      c.robots.push_back(robot);
      const HyperarcId arc = moves.empty() ? s.arc : moves.back();
      if (std::find(c.arcs.begin(), c.arcs.end(), arc) == c.arcs.end()) c.arcs.push_back(arc);
      MotionConstraint k;
      k.robot = robot;
      k.edge = arc;
      k.during = ownAndOtherTail(graph.graph(), s.arc, robot).second;
      c.constraints.push_back(k);
    }
    return c;
  }
  for (int r = 0; r < static_cast<int>(plan.home_moves.size()); ++r)
    if (!plan.home_moves[r].empty()) {
      c.robots.push_back(r);
      c.arcs.push_back(plan.home_moves[r].back());
      c.constraints.push_back(MotionConstraint{r, {}, plan.home_moves[r].back(), {}});
    }
  return c;
}

/// A collision between robots, held objects or resting objects (what conflict resolution checks).
bool isContact(const ValidationProblem& problem) {
  return problem.kind == ProblemKind::kRobotRobotCollision || problem.kind == ProblemKind::kHeldObjectCollision ||
         problem.kind == ProblemKind::kRobotObjectCollision;
}

/// The plan step a contact the validator found belongs to: the first transition at or after it of a
/// robot involved (the move into it is where the contact was), else the last before it; -1: none.
int contactStep(const Scene& scene, const TaskPlan& plan, const std::vector<double>& step_times,
                const ValidationProblem& problem) {
  if (!isContact(problem) || step_times.size() != plan.steps.size()) return -1;
  auto involved = [&](int r) {
    return r >= 0 && (scene.robots[r].id == problem.robot || scene.robots[r].id == problem.other);
  };
  int after = -1, before = -1;
  for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k) {
    if (!involved(plan.steps[k].action.robot) && !involved(plan.steps[k].action.robot2)) continue;
    if (step_times[k] >= problem.t && (after < 0 || step_times[k] < step_times[after])) after = k;
    if (step_times[k] < problem.t && (before < 0 || step_times[k] > step_times[before])) before = k;
  }
  return after >= 0 ? after : before;
}

}  // namespace

PlanResult DashPlanner::solve(const Scene& scene, const PlannerSettings& settings, const Deadline& deadline,
                              log::EventSink* sink) {
  applyTestFault(settings);
  // The named parameters given (engine/core/planner_params.h), checked and applied over params_.
  DashParams params = params_;
  {
    const ParamValues effective = resolveParameters(name(), settings.params);
    ParamValues overrides;
    for (const auto& entry : settings.params) overrides[entry.first] = effective.at(entry.first);
    applyDashParameters(params, overrides);
  }
  const SchedulerParams& scheduler_params = params.scheduler;
  const double clearance = params.clearance;
  const int validation_threads = params.validation_threads;
  const OmplSeedScope ompl_seeds(settings.seed);
  log::EventEmitter emitter(sink);
  const CollisionWorld world(scene, {.clearance = clearance});
  CollisionContext context(world);
  Rng rng(Rng::derive(settings.seed, 23));
  TaskSpace space(scene);
  TransitionSampler sampler(world, context);
  GeometricReachability reach(sampler);
  PlanResult result;
  std::int64_t eager = 0, lazy = 0;
  std::size_t extended_vertices = 0, extended_hyperarcs = 0;
  auto checks = [&] { return static_cast<std::int64_t>(context.counters().configuration_checks); };

  DashTaskGraph task_graph;
  TransitionCatalog catalog;
  std::unique_ptr<MotionHypergraph> motion;
  RoadmapSet roadmaps;
  auto roadmapTotals = [&](std::int64_t& vertices, std::int64_t& edges) {
    vertices = edges = 0;
    for (const auto& r : roadmaps) {
      vertices += static_cast<std::int64_t>(r->vertexCount());
      edges += static_cast<std::int64_t>(r->edgeCount());
    }
  };
  auto emitCounters = [&] {
    std::int64_t v = 0, e = 0;
    roadmapTotals(v, e);
    emitter.counter("roadmap_vertices", v);
    emitter.counter("roadmap_edges", e);
    emitter.counter("collision_checks_eager", eager);
    emitter.counter("collision_checks_lazy", lazy);
  };
  int motion_constraints = 0;
  int queries = 0;
  auto finish = [&](PlanOutcome outcome, std::string message) {
    PlanStats& st = result.stats;
    st.phase_seconds = emitter.phaseTotals();
    st.wall_seconds = emitter.now();
    st.sizes.task_vertices = task_graph.vertexCount();
    st.sizes.task_hyperarcs = task_graph.hyperarcCount();
    if (motion) {
      st.sizes.motion_vertices = motion->graph().vertexCount();
      st.sizes.motion_hyperarcs = motion->graph().hyperarcCount();
    }
    st.sizes.motion_extended_vertices = extended_vertices;
    st.sizes.motion_extended_hyperarcs = extended_hyperarcs;
    st.iterations = queries;
    st.collision_checks_eager = eager;
    st.collision_checks_lazy = lazy;
    roadmapTotals(st.roadmap_vertices, st.roadmap_edges);
    st.motion_constraints = motion_constraints;
    emitCounters();
    result.outcome = outcome;
    result.message = std::move(message);
    return result;
  };
  auto timeout = [&](const std::string& where) {
    return finish(deadline.stopRequested() ? PlanOutcome::kCancelled : PlanOutcome::kTimeout, where + ": timeout");
  };

  // 1. Task space hypergraph (location-free object elements), placements pre-sampled.
  {
    log::PhaseTimer timer(emitter, log::Phase::TaskConstruction);
    const std::int64_t before = checks();
    presamplePlacements(space, reach, sampler, rng, params.placements);
    DashTaskGraphObserver observer;
    if (emitter.enabled()) {
      observer.onVertex = [&](VertexId v, const TaskElement& e) {
        emitter.vertex(log::Layer::Task, v.value(), dashElementLabel(e, scene));
      };
      observer.onHyperarc = [&](HyperarcId a, const TaskArc& arc, std::span<const VertexId> tail,
                                std::span<const VertexId> head) {
        emitter.hyperarcOf(log::Layer::Task, taskArcTypeName(arc.type), a.value(), head, tail);
      };
    }
    task_graph = buildDashTaskGraph(space, reach.oracle(), observer);
    eager += checks() - before;
  }
  if (deadline.expired()) return timeout("task space construction");

  // 2. Motion hypergraph, exhaustively: every transition, validated roadmaps, every move.
  {
    log::PhaseTimer timer(emitter, log::Phase::MotionConstruction);
    const std::int64_t before = checks();
    catalog = sampleTransitions(sampler, space, task_graph, params.transitions, deadline);
    motion = std::make_unique<MotionHypergraph>(space, catalog, emitter);
    roadmaps = RoadmapSet(world.robotCount());
    for (int r = 0; r < world.robotCount(); ++r) {
      for (const bool holding : {false, true}) {
        roadmaps.slot(r, holding) = std::make_unique<ValidatedRoadmap>(world, context, r, params.roadmap);
        roadmaps.at(r, holding).growTo(holding ? params.holding_roadmap_samples : params.empty_roadmap_samples, deadline);
      }
    }
    motion->connectMoves(roadmaps, {}, deadline);
    eager += checks() - before;
  }
  emitCounters();
  if (deadline.expired()) return timeout("motion hypergraph construction");

  // 3-4. Query, conflict resolution, constraint tree (depth first), until solved or the deadline: a
  // PRM-based planner never proves a problem infeasible, so an exhausted tree (or a root without a
  // hyperpath) grows every roadmap and starts the tree again.
  CombinedQuery query(*motion);
  using Node = std::vector<MotionConstraint>;
  std::vector<Node> open{{}};
  std::set<Node> seen{{}};
  BreakRule break_rule(world.robotCount(), params.break_rule, Rng::derive(settings.seed, 29));
  // One scheduler for the whole run, as Lazy-DaSH's: its memo carries the steps a new hyperpath
  // shares with the last one scheduled, and the instants the validator found contacts at.
  Scheduler scheduler(world, context, scheduler_params);
  scheduler.reportProgress(&emitter);  // steps scheduled, for people watching (reporting only)
  std::int64_t rechecks = 0, validation_feedbacks = 0, reused_steps = 0, restarts = 0;
  std::int64_t complete_passes = 0, one_object_passes = 0;  // queries that got past the greedy pass
  std::function<void(const ExtendedVertex&)> on_vertex = [&](const ExtendedVertex& v) {
    emitter.vertex(log::Layer::MotionExtended, static_cast<std::uint32_t>(extended_vertices++),
                   emitter.enabled() ? motion->label(v.vertex) : std::string());
  };
  std::function<void(const ExtendedHyperarc&)> on_hyperarc = [&](const ExtendedHyperarc& a) {
    const auto id = static_cast<std::uint32_t>(extended_hyperarcs++);
    if (!emitter.enabled()) return;
    emitter.hyperarcOf(log::Layer::MotionExtended, motionArcTypeName(motion->graph().property(a.hyperarc).type), id,
                       a.produced, a.consumed);
  };
  // A roadmap growth: more milestones in both hand states of each robot, then their moves again.
  auto growRoadmaps = [&](const std::vector<int>& robots) {
    log::PhaseTimer timer(emitter, log::Phase::MotionConstruction);
    const std::int64_t before = checks();
    for (int r : robots) {
      for (const bool holding : {false, true}) {
        ValidatedRoadmap& rm = roadmaps.at(r, holding);
        rm.growTo(rm.milestoneCount() + params.growth_samples, deadline);
      }
    }
    motion->connectMoves(roadmaps, robots, deadline);
    eager += checks() - before;
    emitCounters();
  };
  std::vector<int> all_robots;
  for (int r = 0; r < world.robotCount(); ++r) all_robots.push_back(r);
  std::string last_failure = "no hyperpath from the start to the goal in the motion hypergraph";
  emitter.counter("roadmap_growths", 0);
  emitter.counter("constraint_tree_branchings", 0);
  for (;;) {
    if (deadline.expired()) return timeout("constraint tree (last: " + last_failure + ")");
    if (open.empty()) {
      // Every node is dead or exhausted under the current roadmaps: denser ones may add hyperpaths
      // or ways round; grow them all and start from the root again.
      growRoadmaps(all_robots);
      emitter.counter("constraint_tree_restarts", ++restarts);
      open = {{}};
      seen = {{}};
    }
    const Node node = std::move(open.back());
    open.pop_back();
    emitter.setIteration(queries++);
    emitter.counter("constraint_tree_nodes", queries);
    HyperpathResult path;
    {
      log::PhaseTimer timer(emitter, log::Phase::MotionQuery);
      path = query.run(node, params.query, deadline, on_vertex, on_hyperarc);
    }
    if (query.lastPass() == CombinedQuery::Pass::kComplete && params.query.prune_moves) emitter.counter("complete_query_passes", ++complete_passes);
    if (query.lastPass() == CombinedQuery::Pass::kOneObjectAtATime)
      emitter.counter("one_object_query_passes", ++one_object_passes);
    if (!path.found()) {
      if (path.status == HyperpathStatus::kDeadline) return timeout("combined query (last: " + last_failure + ")");
      // Under constraints: back up the tree. Without any, the representation itself has no
      // hyperpath (a move a sparse roadmap misses, e.g. into a narrow cubby): only denser roadmaps
      // can add one, so every robot's roadmaps grow and the root is queried again.
      if (!node.empty()) continue;
      // Say why: the objects H_M has no route for from their start to their goal (a missing
      // transition or an unconnected move), if any.
      std::string unrouted;
      for (int o = 0; o < space.objectCount(); ++o) {
        const VertexId start = motion->objectVertex(o, space.startLocation(o));
        if (start.valid() && !std::isfinite(query.costToGo(start)))
          unrouted += (unrouted.empty() ? "" : ", ") + scene.objects[o].id;
      }
      last_failure = "no hyperpath from the start to the goal in the motion hypergraph" +
                     (unrouted.empty() ? std::string(" (every object has a route of its own: the objects block each other)")
                                       : "; no route to the goal for " + unrouted);
      MotionConflict none;
      none.what = last_failure;
      none.robots = all_robots;
      const BreakRule::Choice choice = break_rule.decide(none);
      emitter.counter("roadmap_growths", break_rule.roadmapDecisions());
      growRoadmaps(choice.decision == BreakRule::Decision::kGrowRoadmaps ? choice.robots : all_robots);
      open.push_back(node);
      continue;
    }
    ExtractedPlan extracted = extractPlan(*motion, path);
    if (settings.task_only) {
      // DaSH has no task layer of its own: its transitions, as queried, before conflict resolution.
      result.task_plan_json = extracted.plan.toJson(space);
      return finish(PlanOutcome::kSolved, extracted.plan.describe(space));
    }
    std::optional<MotionConflict> conflict;
    ScheduleResult schedule;
    Plan plan;
    {
      log::PhaseTimer timer(emitter, log::Phase::ConflictResolution);
      const std::int64_t before = checks();
      RestingConflictStats resting;
      if (params.shortcutting) shortcutPaths(extracted, world, context);
      conflict = resolveRestingConflicts(extracted, *motion, world, context, roadmaps, deadline, resting);
      const MoveReplanner replan = [&](int r, const JointVector& from, const JointVector& to, const MotionContext& ctx) {
        return roadmaps.at(r, ctx.held.holding()).plan(from, to, ctx, deadline);
      };
      // A contact the validator finds between the scheduler's check instants: that instant is checked
      // from then on and the same hyperpath scheduled again (as Lazy-DaSH does); a contact that stays
      // is a conflict like any other, never an error.
      for (int recheck = 0; !conflict; ++recheck) {
        schedule = scheduler.build(extracted.plan, extracted.transitions, extracted.motion, space, replan, deadline);
        reused_steps += schedule.stats.reused_steps;
        if (!schedule.ok) {
          conflict = scheduleConflict(*motion, extracted, schedule.failed_step, schedule.reason);
          break;
        }
        plan = std::move(schedule.plan);
        plan.planner = name();
        const ValidationReport report = validatePlan(scene, plan, {.threads = validation_threads});
        if (report.valid()) break;
        const ValidationProblem& problem = report.problems.front();
        if (recheck < params.validator_rechecks && isContact(problem)) {
          scheduler.alsoCheckAt(problem.t);
          if (problem.t_end > problem.t) scheduler.alsoCheckAt(problem.t_end);
          scheduler.forgetFrom(problem.t);
          emitter.counter("validation_rechecks", ++rechecks);
          continue;
        }
        // Only a contact can be a missed conflict; anything else the validator finds is a bug.
        if (!isContact(problem))
          return finish(PlanOutcome::kInfeasible, "internal error: the planned schedule failed validation: " +
                                                      problem.message);
        const int step = contactStep(scene, extracted.plan, schedule.step_times, problem);
        scheduler.forgetFrom(problem.t);
        emitter.counter("validation_feedbacks", ++validation_feedbacks);
        conflict = scheduleConflict(*motion, extracted, step, "validation: " + problem.message);
      }
      emitter.counter("scheduled_steps_reused", reused_steps);
      lazy += checks() - before;
    }
    if (!conflict) {
      result.stats.makespan = plan.makespan;
      result.stats.path_length = plan.jointPathLength();
      result.plan = std::move(plan);
      return finish(PlanOutcome::kSolved, "solved");
    }
    if (deadline.expired()) return timeout("conflict resolution");
    last_failure = conflict->what;

    // CBS-MP's probabilistic break rule: grow the roadmaps, or grow the constraint tree.
    const BreakRule::Choice choice = break_rule.decide(*conflict);
    emitter.counter("roadmap_growths", break_rule.roadmapDecisions());
    emitter.counter("constraint_tree_branchings", break_rule.treeDecisions());
    if (choice.decision == BreakRule::Decision::kDeadNode) continue;
    if (choice.decision == BreakRule::Decision::kGrowRoadmaps) {
      growRoadmaps(choice.robots);
      open.push_back(node);
      continue;
    }
    for (auto it = conflict->constraints.rbegin(); it != conflict->constraints.rend(); ++it) {
      Node child = node;
      if (std::find(child.begin(), child.end(), *it) != child.end()) continue;  // already there: no change
      child.push_back(*it);
      std::sort(child.begin(), child.end());
      if (!seen.insert(child).second) continue;
      emitter.constraint(log::ConstraintKind::Motion, log::ConstraintAction::Created,
                         static_cast<std::uint32_t>(motion_constraints++), describe(*motion, *it), {}, conflict->what);
      open.push_back(std::move(child));
    }
  }
}

}  // namespace dash
