#include "engine/dash/dash_run.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/dash/placement_sampling.h"
#include "engine/dash/schedule_conflicts.h"
#include "engine/plan/plan_validator.h"

namespace dash {

DashRun::DashRun(const DashParams& params, std::string planner_name, const Scene& scene,
                 const PlannerSettings& settings, const Deadline& deadline, log::EventSink* sink)
    : params_(params),
      name_(std::move(planner_name)),
      scene_(scene),
      settings_(settings),
      deadline_(deadline),
      ompl_seeds_(settings.seed),
      emitter_(sink),
      other_(emitter_, log::Phase::Other),
      world_(scene, {.clearance = params.clearance}),
      context_(world_),
      rng_(Rng::derive(settings.seed, 23)),
      space_(scene),
      sampler_(world_, context_),
      reach_(sampler_),
      last_failure_("no hyperpath from the start to the goal in the motion hypergraph") {
  for (int r = 0; r < world_.robotCount(); ++r) all_robots_.push_back(r);
  on_vertex_ = [this](const ExtendedVertex& v) {
    emitter_.vertex(log::Layer::MotionExtended, static_cast<std::uint32_t>(extended_vertices_++),
                    emitter_.enabled() ? motion_->label(v.vertex) : std::string());
  };
  on_hyperarc_ = [this](const ExtendedHyperarc& a) {
    const auto id = static_cast<std::uint32_t>(extended_hyperarcs_++);
    if (!emitter_.enabled()) return;
    emitter_.hyperarcOf(log::Layer::MotionExtended, motionArcTypeName(motion_->graph().property(a.hyperarc).type), id,
                        a.produced, a.consumed);
  };
}

DashRun::~DashRun() = default;

PlanResult DashRun::solve() {
  buildTaskSpace();
  if (deadline_.expired()) return timeout("task space construction");
  buildMotionHypergraph();
  emitCounters();
  if (deadline_.expired()) return timeout("motion hypergraph construction");
  return searchConstraintTree();
}

// 1. Task space hypergraph (location-free object elements), placements pre-sampled.
void DashRun::buildTaskSpace() {
  log::PhaseTimer timer(emitter_, log::Phase::TaskConstruction);
  const std::int64_t before = checks();
  presamplePlacements(space_, reach_, sampler_, rng_, params_.placements);
  DashTaskGraphObserver observer;
  if (emitter_.enabled()) {
    observer.onVertex = [&](VertexId v, const TaskElement& e) {
      emitter_.vertex(log::Layer::Task, v.value(), dashElementLabel(e, scene_));
    };
    observer.onHyperarc = [&](HyperarcId a, const TaskArc& arc, std::span<const VertexId> tail,
                              std::span<const VertexId> head) {
      emitter_.hyperarcOf(log::Layer::Task, taskArcTypeName(arc.type), a.value(), head, tail);
    };
  }
  task_graph_ = buildDashTaskGraph(space_, reach_.oracle(), observer);
  eager_ += checks() - before;
}

// 2. Motion hypergraph, exhaustively: every transition, validated roadmaps, every move.
void DashRun::buildMotionHypergraph() {
  log::PhaseTimer timer(emitter_, log::Phase::MotionConstruction);
  const std::int64_t before = checks();
  catalog_ = sampleTransitions(sampler_, space_, task_graph_, params_.transitions, deadline_);
  motion_ = std::make_unique<MotionHypergraph>(space_, catalog_, emitter_);
  roadmaps_ = RoadmapSet(world_.robotCount());
  for (int r = 0; r < world_.robotCount(); ++r) {
    for (const bool holding : {false, true}) {
      roadmaps_.slot(r, holding) = std::make_unique<ValidatedRoadmap>(world_, context_, r, params_.roadmap);
      roadmaps_.at(r, holding).growTo(holding ? params_.holding_roadmap_samples : params_.empty_roadmap_samples,
                                      deadline_);
    }
  }
  motion_->connectMoves(roadmaps_, {}, deadline_);
  eager_ += checks() - before;
}

// 3-4. Query, conflict resolution, constraint tree (depth first), until solved or the deadline: a
// PRM-based planner never proves a problem infeasible, so an exhausted tree (or a root without a
// hyperpath) grows every roadmap and starts the tree again.
PlanResult DashRun::searchConstraintTree() {
  query_ = std::make_unique<CombinedQuery>(*motion_);
  // One scheduler for the whole run, as Lazy-DaSH's: its memo carries the steps a new hyperpath
  // shares with the last one scheduled, and the instants the validator found contacts at.
  scheduler_ = std::make_unique<Scheduler>(world_, context_, params_.scheduler);
  scheduler_->reportProgress(&emitter_);  // steps scheduled, for people watching (reporting only)
  break_rule_ = std::make_unique<BreakRule>(world_.robotCount(), params_.break_rule, Rng::derive(settings_.seed, 29));
  open_ = {{}};
  seen_ = {{}};
  emitter_.counter("roadmap_growths", 0);
  emitter_.counter("constraint_tree_branchings", 0);
  for (;;) {
    if (deadline_.expired()) return timeout("constraint tree (last: " + last_failure_ + ")");
    if (open_.empty()) {
      // Every node is dead or exhausted under the current roadmaps: denser ones may add hyperpaths
      // or ways round; grow them all and start from the root again.
      growRoadmaps(all_robots_);
      emitter_.counter("constraint_tree_restarts", ++restarts_);
      open_ = {{}};
      seen_ = {{}};
    }
    const Node node = std::move(open_.back());
    open_.pop_back();
    const HyperpathResult path = queryNode(node);
    if (!path.found()) {
      if (path.status == HyperpathStatus::kDeadline) return timeout("combined query (last: " + last_failure_ + ")");
      // Under constraints: back up the tree. Without any, the representation itself has no
      // hyperpath (a move a sparse roadmap misses, e.g. into a narrow cubby): only denser roadmaps
      // can add one, so roadmaps grow and the root is queried again.
      if (!node.empty()) continue;
      growAfterNoHyperpath();
      open_.push_back(node);
      continue;
    }
    ExtractedPlan extracted = extractPlan(*motion_, path);
    if (settings_.task_only) {
      // DaSH has no task layer of its own: its transitions, as queried, before conflict resolution.
      result_.task_plan_json = extracted.plan.toJson(space_);
      return finish(PlanOutcome::kSolved, extracted.plan.describe(space_));
    }
    NodeOutcome outcome = resolveConflicts(extracted, node);
    if (!outcome.internal_error.empty()) return finish(PlanOutcome::kInfeasible, outcome.internal_error);
    if (outcome.plan) {
      result_.stats.makespan = outcome.plan->makespan;
      result_.stats.path_length = outcome.plan->jointPathLength();
      result_.plan = std::move(outcome.plan);
      return finish(PlanOutcome::kSolved, "solved");
    }
    if (deadline_.expired()) return timeout("conflict resolution");
    last_failure_ = outcome.conflict->what;
    breakRule(node, *outcome.conflict);
  }
}

HyperpathResult DashRun::queryNode(const Node& node) {
  emitter_.setIteration(queries_++);
  emitter_.counter("constraint_tree_nodes", queries_);
  HyperpathResult path;
  {
    log::PhaseTimer timer(emitter_, log::Phase::MotionQuery);
    path = query_->run(node, params_.query, deadline_, on_vertex_, on_hyperarc_);
  }
  if (query_->lastPass() == CombinedQuery::Pass::kComplete && params_.query.prune_moves)
    emitter_.counter("complete_query_passes", ++complete_passes_);
  if (query_->lastPass() == CombinedQuery::Pass::kOneObjectAtATime)
    emitter_.counter("one_object_query_passes", ++one_object_passes_);
  return path;
}

// The root has no hyperpath: say why (the objects H_M has no route for, if any), and let the break
// rule pick the robots whose roadmaps grow (all of them when it picks the tree: there is none).
void DashRun::growAfterNoHyperpath() {
  const std::string unrouted = unroutedObjects();
  last_failure_ = "no hyperpath from the start to the goal in the motion hypergraph" +
                  (unrouted.empty() ? std::string(" (every object has a route of its own: the objects block each other)")
                                    : "; no route to the goal for " + unrouted);
  MotionConflict none;
  none.what = last_failure_;
  none.robots = all_robots_;
  const BreakRule::Choice choice = break_rule_->decide(none);
  emitter_.counter("roadmap_growths", break_rule_->roadmapDecisions());
  growRoadmaps(choice.decision == BreakRule::Decision::kGrowRoadmaps ? choice.robots : all_robots_);
}

std::string DashRun::unroutedObjects() const {
  std::string unrouted;
  for (int o = 0; o < space_.objectCount(); ++o) {
    const VertexId start = motion_->objectVertex(o, space_.startLocation(o));
    if (start.valid() && !std::isfinite(query_->costToGo(start)))
      unrouted += (unrouted.empty() ? "" : ", ") + scene_.objects[o].id;
  }
  return unrouted;
}

// Resting-object conflicts by CBS-MP's low-level search, then the scheduler and the validator.
DashRun::NodeOutcome DashRun::resolveConflicts(ExtractedPlan& extracted, const Node& node) {
  log::PhaseTimer timer(emitter_, log::Phase::ConflictResolution);
  const std::int64_t before = checks();
  RestingConflictStats resting;
  if (params_.shortcutting) shortcutPaths(extracted, world_, context_);
  NodeOutcome outcome;
  outcome.conflict =
      resolveRestingConflicts(extracted, *motion_, world_, context_, roadmaps_, deadline_, resting);
  if (!outcome.conflict) {
    respectWindows(extracted, node);
    outcome = scheduleAndValidate(extracted);
  }
  emitter_.counter("scheduled_steps_reused", reused_steps_);
  lazy_ += checks() - before;
  return outcome;
}

// A contact the validator finds between the scheduler's check instants: that instant is checked from
// then on and the same hyperpath scheduled again (validator_rechecks times, as Lazy-DaSH does); a
// contact that stays is a conflict like any other, never an error.
DashRun::NodeOutcome DashRun::scheduleAndValidate(ExtractedPlan& extracted) {
  const MoveReplanner replan = [&](int r, const JointVector& from, const JointVector& to, const MotionContext& ctx) {
    return roadmaps_.at(r, ctx.held.holding()).plan(from, to, ctx, deadline_);
  };
  NodeOutcome outcome;
  for (int recheck = 0;; ++recheck) {
    ScheduleResult schedule =
        scheduler_->build(extracted.plan, extracted.transitions, extracted.motion, space_, replan, deadline_);
    reused_steps_ += schedule.stats.reused_steps;
    if (!schedule.ok) {
      outcome.conflict = scheduleConflict(*motion_, extracted, schedule.failed_step, schedule.reason, schedule.region);
      return outcome;
    }
    Plan plan = std::move(schedule.plan);
    plan.planner = name_;
    ValidationReport report;
    {
      log::PhaseTimer validation(emitter_, log::Phase::Validation);  // booked as Lazy-DaSH books it
      report = validatePlan(scene_, plan,
                            {.threads = params_.validation_threads, .stop = [this] { return deadline_.expired(); }});
    }
    if (report.stopped) return outcome;  // the deadline passed: neither a plan nor a conflict
    if (report.valid()) {
      outcome.plan = std::move(plan);
      return outcome;
    }
    const ValidationProblem& problem = report.problems.front();
    // Only a contact can be a missed conflict; anything else the validator finds is a bug.
    if (!isContact(problem)) {
      outcome.internal_error = "internal error: the planned schedule failed validation: " + problem.message;
      return outcome;
    }
    if (recheck < params_.validator_rechecks) {
      scheduler_->alsoCheckAt(problem.t);
      if (problem.t_end > problem.t) scheduler_->alsoCheckAt(problem.t_end);
      scheduler_->forgetFrom(problem.t);
      emitter_.counter("validation_rechecks", ++rechecks_);
      continue;
    }
    scheduler_->forgetFrom(problem.t);
    const int step = contactStep(scene_, extracted.plan, schedule.step_times, problem);
    emitter_.counter("validation_feedbacks", ++validation_feedbacks_);
    const SchedulerParams& sp = params_.scheduler;
    outcome.conflict =
        scheduleConflict(*motion_, extracted, step, "validation: " + problem.message,
                         contactTiming(scene_, extracted.plan, schedule.step_times, problem, sp.dwell, sp.delay_step));
    return outcome;
  }
}

// The node's timed constraints as windows on this plan's steps (motion_constraint.h): the Scheduler
// keeps each robot's step out of its windows. The steps a changed window can reach are scheduled again
// (the memo would otherwise hand back steps placed under the old windows).
void DashRun::respectWindows(const ExtractedPlan& extracted, const Node& node) {
  std::vector<StepWindow> windows = stepWindows(motion_->graph(), extracted, node);
  double from = std::numeric_limits<double>::infinity();
  auto forgetChanged = [&from](const std::vector<StepWindow>& a, const std::vector<StepWindow>& b) {
    for (const StepWindow& w : a)
      if (std::find(b.begin(), b.end(), w) == b.end()) from = std::min(from, w.t0);
  };
  forgetChanged(windows, windows_);
  forgetChanged(windows_, windows);
  if (std::isfinite(from)) scheduler_->forgetFrom(std::max(0.0, from));
  windows_ = std::move(windows);
  scheduler_->respect(nullptr, &windows_);
}

// CBS-MP's probabilistic break rule: grow the roadmaps, or grow the constraint tree by one child per
// constraint of the conflict (depth first: the children go on top of the open stack).
void DashRun::breakRule(const Node& node, const MotionConflict& conflict) {
  const BreakRule::Choice choice = break_rule_->decide(conflict);
  emitter_.counter("roadmap_growths", break_rule_->roadmapDecisions());
  emitter_.counter("constraint_tree_branchings", break_rule_->treeDecisions());
  if (choice.decision == BreakRule::Decision::kDeadNode) return;
  if (choice.decision == BreakRule::Decision::kGrowRoadmaps) {
    growRoadmaps(choice.robots);
    open_.push_back(node);
    return;
  }
  for (auto it = conflict.constraints.rbegin(); it != conflict.constraints.rend(); ++it) {
    Node child = node;
    if (std::find(child.begin(), child.end(), *it) != child.end()) continue;  // already there: no change
    child.push_back(*it);
    std::sort(child.begin(), child.end());
    if (!seen_.insert(child).second) continue;
    emitter_.constraint(log::ConstraintKind::Motion, log::ConstraintAction::Created,
                        static_cast<std::uint32_t>(motion_constraints_++), describe(*motion_, *it), {}, conflict.what);
    open_.push_back(std::move(child));
  }
}

// A roadmap growth: more milestones in both hand states of each robot, then their moves again.
void DashRun::growRoadmaps(const std::vector<int>& robots) {
  log::PhaseTimer timer(emitter_, log::Phase::MotionConstruction);
  const std::int64_t before = checks();
  for (int r : robots) {
    for (const bool holding : {false, true}) {
      ValidatedRoadmap& rm = roadmaps_.at(r, holding);
      rm.growTo(rm.milestoneCount() + params_.growth_samples, deadline_);
    }
  }
  motion_->connectMoves(roadmaps_, robots, deadline_);
  eager_ += checks() - before;
  emitCounters();
}

std::int64_t DashRun::checks() const { return static_cast<std::int64_t>(context_.counters().configuration_checks); }

void DashRun::roadmapTotals(std::int64_t& vertices, std::int64_t& edges) const {
  vertices = edges = 0;
  for (const auto& r : roadmaps_) {
    vertices += static_cast<std::int64_t>(r->vertexCount());
    edges += static_cast<std::int64_t>(r->edgeCount());
  }
}

void DashRun::emitCounters() {
  std::int64_t v = 0, e = 0;
  roadmapTotals(v, e);
  emitter_.counter("roadmap_vertices", v);
  emitter_.counter("roadmap_edges", e);
  emitter_.counter("collision_checks_eager", eager_);
  emitter_.counter("collision_checks_lazy", lazy_);
}

PlanResult DashRun::finish(PlanOutcome outcome, std::string message) {
  PlanStats& st = result_.stats;
  other_.stop();
  st.phase_seconds = emitter_.phaseTotals();
  st.wall_seconds = emitter_.now();
  st.sizes.task_vertices = task_graph_.vertexCount();
  st.sizes.task_hyperarcs = task_graph_.hyperarcCount();
  if (motion_) {
    st.sizes.motion_vertices = motion_->graph().vertexCount();
    st.sizes.motion_hyperarcs = motion_->graph().hyperarcCount();
  }
  st.sizes.motion_extended_vertices = extended_vertices_;
  st.sizes.motion_extended_hyperarcs = extended_hyperarcs_;
  st.iterations = queries_;
  st.collision_checks_eager = eager_;
  st.collision_checks_lazy = lazy_;
  roadmapTotals(st.roadmap_vertices, st.roadmap_edges);
  st.motion_constraints = motion_constraints_;
  emitCounters();
  result_.outcome = outcome;
  result_.message = std::move(message);
  return std::move(result_);
}

PlanResult DashRun::timeout(const std::string& where) {
  return finish(deadline_.stopRequested() ? PlanOutcome::kCancelled : PlanOutcome::kTimeout, where + ": timeout");
}

}  // namespace dash
