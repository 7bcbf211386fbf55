#include "engine/core/planner_params.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "engine/core/check.h"

namespace dash {

namespace {

/// More validator threads than this is a typing error, not a machine.
constexpr int kMaxValidationThreads = 1024;

constexpr const char* kBeyond = "beyond the paper";

/// A switch: default `value`, paper value `paper`.
ParamInfo flag(std::string name, bool value, bool paper, std::string source, std::string description) {
  return {std::move(name), ParamType::kBool, value ? "true" : "false", paper ? "true" : "false", 0, 0,
          std::move(description), std::move(source)};
}
/// A budget the paper has too (its value is not given): --profile paper leaves it alone.
ParamInfo budget(std::string name, int value, int min, int max, std::string source, std::string description) {
  return {std::move(name), ParamType::kInt, std::to_string(value), "", static_cast<double>(min),
          static_cast<double>(max), std::move(description), std::move(source)};
}
/// A count with a paper value of its own.
ParamInfo count(std::string name, int value, int paper, int max, std::string source, std::string description) {
  return {std::move(name), ParamType::kInt, std::to_string(value), std::to_string(paper), 0, static_cast<double>(max),
          std::move(description), std::move(source)};
}

// What both planners share: the clearance of every check (engine/collision/collision_world.h, whose
// kDefaultPlanningClearance is this default; a test checks they agree), the threads of the validator
// they run on each schedule, and conflict resolution (engine/conflict/scheduler.h).
std::vector<ParamInfo> schedulerParameters() {
  const std::string arc = "Motion Conflict Resolution and Constraint Feedback (ARC)";
  return {
      {"clearance", ParamType::kReal, "0.002", "", 0.0, 0.05,
       "metres every check of the planner keeps between parts not in contact by design (0: touching allowed)",
       "beyond the paper (no value given; the validator checks at 0)"},
      {"validation_threads", ParamType::kInt, "0", "", 0, kMaxValidationThreads,
       "threads of the plan validator run on each schedule (0: the hardware's) and of conflict resolution's checks "
       "(0: the hardware's, up to 2; 8 at most); the plan is the same for any number",
       "beyond the paper (changes no result)"},
      flag("conflict_replanning", true, true, arc,
           "conflict resolution replans motions (around robots in the way, ARC's composite subproblem); false: it "
           "only retimes (an ablation)"),
      flag("staggered_arrivals", true, false, kBeyond,
           "a handover whose two robots collide on the way also tries one robot in place first, then the other"),
      flag("idle_arms_home", true, false, kBeyond, "a robot standing idle in the way is sent home before a step is given up"),
      flag("parking", true, false, kBeyond,
           "robots that step aside in a composite replan go to a parking configuration when home is in the way"),
      flag("schedule_memo", true, false, kBeyond,
           "a task plan that starts like the last one keeps those steps as they were scheduled"),
  };
}

std::vector<ParamInfo> lazyDashParameters() {
  const std::string motion_query = "Query (Motion-extended Hypergraph)";
  const std::string motion_hg = "Representation Construction (Motion Hypergraph)";
  const std::string theory = "Theoretical Properties";
  std::vector<ParamInfo> p = {
      // Motion layer.
      flag("straight_first", true, false, kBeyond, "try the straight joint-space segment before a roadmap query"),
      flag("deep_backoffs", true, false, kBeyond,
           "back off 0.15-0.35 m along the approach axis when a transit fails (shelf cubbies)"),
      flag("global_sampling", true, true, motion_query + ": \"additional vertices are sampled globally\"",
           "RRT-Connect from both ends when the roadmap finds no way between valid ends (global sampling in tree "
           "form; off: none)"),
      flag("path_simplification", true, false, kBeyond, "shortcut roadmap paths (OMPL PathSimplifier)"),
      flag("keep_tree_paths", true, true, motion_query + ": globally sampled vertices join the roadmap",
           "a path global sampling finds joins the roadmap (its states as milestones)"),
      flag("budget_growth", true, true, theory + ": \"with increasing budgets\"",
           "raise the roadmap budgets 4x (at most 3 times) when a failure has no alternative"),
      // Task layer.
      flag("round_trip_removal", true, false, kBeyond,
           "drop task plan round trips (an object taken out and put back for nothing)"),
      flag("approach_line_preference", true, false, kBeyond, "side grasps prefer the IK branch whose approach line is free"),
      flag("handover_class_bans", true, false, kBeyond,
           "a motion failure at a handover bans its class (robots, grasps) instead of the one hyperarc"),
      budget("move_outs_per_object", 3, 0, 100, "Task Planning Layer: task space expansion",
             "extra stable poses (move-out states) task space expansion may add per object"),
      flag("move_out_one_grasp", false, false, kBeyond,
           "task space expansion first samples move-out poses that trap no robot: each robot that takes the object "
           "at its start and can grasp it there carries it there, and on to its goal, with one grasp (on: solves "
           "stocking 3/18 seed 2 but loses 2/28 seed 4, and the task query of 3/18 seed 1 grows 10x, "
           "experiments/RESULTS.md)"),
      budget("ban_queries", 8, 1, 1000, motion_query + ": \"the invalid motion hyperarc is not permanently excluded\"",
             "a hyperarc the motion layer failed on is banned for as many task queries as it failed, at most this many"),
      budget("ban_lifts", 20, 0, 100000, motion_query,
             "times the temporary bans may all be lifted when no task plan avoids them"),
      {"handover_base_distance", ParamType::kReal, "1.8", "", 0.1, 100.0,
       "metres between two arms' bases above which H_T has no handover between them",
       "Representation Construction (Task Space Hypergraph): reachability by range"},
      // The loop.
      budget("transition_resamples", 2, 0, 100, motion_hg + ": \"resampling is performed to search for valid alternatives\"",
             "transition configurations of one task hyperarc turned down before the hyperarc is banned"),
      count("move_out_resamples", 0, 0, 100, kBeyond,
            "times a move-out pose is resampled when its object's chain has no collision-free transition "
            "configuration there or at a later step (a place at the goal), before the step is banned for some task "
            "queries; with move_out_one_grasp the new pose traps no robot (off: 3 solves stocking 2/28 seed 4 but "
            "loses stocking 3/18 seeds 4 and 5, experiments/RESULTS.md)"),
      count("validator_rechecks", 3, 0, 100, kBeyond,
            "schedule again, checking the instant the validator found a contact at (per round)"),
      flag("restart_when_exhausted", true, true, theory + ": constraints \"can be lifted when new task or motion samples "
           "are introduced\"",
           "when nothing is left to try (task query, feedback loop, task rounds), lift every task constraint, "
           "resample and grow the roadmaps, until the deadline (off: the run ends \"infeasible\")"),
      count("validation_feedbacks", 100, 0, 10000, kBeyond,
            "contacts the validator finds after the rechecks fed back as task constraints (per attempt; one "
            "more ends the attempt: a restart, or with restarts off the run)"),
      budget("motion_budget", 3, 1, 1000, "Algorithm 1, lines 8-15",
             "motion rounds on one task plan (motion constraints, resampling) before its failure becomes a task "
             "constraint"),
      budget("max_task_plans", 200, 1, 1000000, "Algorithm 1, line 3 (a budget of one attempt)",
             "task plans one attempt tries before it counts as exhausted (then restart_when_exhausted)"),
      budget("roadmap_query_samples", 5000, 10, 10000000, motion_query + " (Lazy-PRM)",
             "Lazy-PRM samples one roadmap query may add (at most 1000 once a roadmap has 10000 vertices)"),
      budget("roadmap_max_vertices", 30000, 1000, 100000000, motion_query + " (Lazy-PRM)",
             "a Lazy-PRM roadmap this large stops growing: queries answer from what it has"),
  };
  for (ParamInfo& s : schedulerParameters()) p.push_back(std::move(s));
  return p;
}

// DaSH (engine/dash/dash_planner.h): every addition beyond the DaSH paper (Motes et al., T-RO 2023) is
// a switch off in `--profile paper`; the budgets below them are the representation's own sizes.
std::vector<ParamInfo> dashParameters() {
  const std::string prm = "DaSH (Motes et al., T-RO 2023): validated PRM roadmaps";
  std::vector<ParamInfo> p = {
      // Combined query (engine/dash/combined_query.h).
      flag("greedy_move_pruning", true, false, kBeyond,
           "the greedy pass skips moves to where nothing can happen now and moves back from a handover (off: it "
           "expands every move and is complete by itself over H_M)"),
      flag("one_object_pass", true, false, kBeyond, "after a failed greedy pass, a pass that moves one object at a time"),
      flag("complete_pass", true, false, kBeyond, "after the failed passes, a depth-first search that expands every move"),
      flag("stranding_prune", true, false, kBeyond, "never take a step that leaves a robot with no way home in H_M"),
      // Transition sampling (engine/dash/transition_catalog.h).
      flag("targeted_handovers", true, false, kBeyond,
           "a handover chained onto a grasp the receiver already has tries the first 16 of the 1040 handover "
           "poses (off: the whole grid for every grasp chain)"),
      flag("approach_line_preference", true, false, kBeyond, "side grasps prefer the IK branch whose approach line is free"),
      flag("deep_backoffs", true, false, kBeyond, "side grasps back off by the farthest free of 0.15-0.35 m (off: 6 cm only)"),
      // Conflict resolution and validation.
      flag("shortcutting", true, false, kBeyond,
           "roadmap paths of the hyperpath are shortened (straight segments) before scheduling"),
      count("validator_rechecks", 3, 0, 100, kBeyond,
            "schedule the same hyperpath again, checking the instant the validator found a contact at (per node)"),
      // Budgets: --profile paper leaves them alone.
      budget("empty_roadmap_samples", 100, 1, 1000000, prm, "og::PRM milestones per robot with an empty hand before the first query"),
      budget("holding_roadmap_samples", 60, 1, 1000000, prm, "og::PRM milestones per robot holding an object before the first query"),
      budget("growth_samples", 50, 1, 1000000, prm + ", grown by CBS-MP's break rule", "milestones one roadmap growth adds"),
      {"grow_roadmap_probability", ParamType::kReal, "0.3", "", 0.0, 1.0,
       "CBS-MP's break rule: chance that an unresolved conflict grows the roadmaps rather than the constraint tree",
       "CBS-MP's probabilistic break rule (Solis et al.)"},
  };
  for (ParamInfo& s : schedulerParameters()) p.push_back(std::move(s));
  return p;
}

const ParamInfo& findParam(const std::vector<ParamInfo>& params, const std::string& planner, const std::string& name) {
  for (const ParamInfo& p : params)
    if (p.name == name) return p;
  std::string known;
  for (const ParamInfo& p : params) known += (known.empty() ? "" : ", ") + p.name;
  throw InputError("unknown parameter '" + name + "' for planner " + planner + " (it has: " + known + ")");
}

/// The canonical text of `value` for `p`, or InputError naming the parameter.
std::string checked(const ParamInfo& p, const std::string& value) {
  auto bad = [&](const std::string& why) {
    return InputError("parameter " + p.name + ": '" + value + "' " + why);
  };
  if (p.type == ParamType::kBool) {
    if (value == "true" || value == "1" || value == "on") return "true";
    if (value == "false" || value == "0" || value == "off") return "false";
    throw bad("is not true or false");
  }
  if (value.size() > 32) throw bad("is too long");
  double x = 0.0;
  if (p.type == ParamType::kInt) {
    long long n = 0;
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
    if (ec != std::errc() || end != value.data() + value.size()) throw bad("is not an integer");
    x = static_cast<double>(n);
  } else {
    const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), x);
    if (ec != std::errc() || end != value.data() + value.size() || !std::isfinite(x)) throw bad("is not a number");
  }
  if (x < p.min || x > p.max) {
    std::ostringstream range;
    range << "is out of range [" << p.min << ", " << p.max << "]";
    throw bad(range.str());
  }
  if (p.type == ParamType::kInt) return std::to_string(static_cast<long long>(x));
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

}  // namespace

const std::vector<ParamInfo>& plannerParameters(const std::string& planner) {
  static const std::vector<ParamInfo> kLazyDash = lazyDashParameters();
  static const std::vector<ParamInfo> kDash = dashParameters();
  if (planner == "lazy-dash") return kLazyDash;
  if (planner == "dash") return kDash;
  throw InputError("unknown planner '" + planner + "'");
}

ParamValues resolveParameters(const std::string& planner, const ParamValues& overrides) {
  const std::vector<ParamInfo>& params = plannerParameters(planner);
  ParamValues out;
  for (const ParamInfo& p : params) out[p.name] = p.default_value;
  for (const auto& [name, value] : overrides) out[name] = checked(findParam(params, planner, name), value);
  return out;
}

ParamValues profileOverrides(const std::string& planner, const std::string& profile) {
  if (profile == "default") return {};
  DASH_THROW_UNLESS(profile == "paper", "unknown profile '" + profile + "' (expected paper or default)");
  ParamValues out;
  for (const ParamInfo& p : plannerParameters(planner))
    if (p.extension()) out[p.name] = p.paper_value;
  return out;
}

std::pair<std::string, std::string> parseAssignment(const std::string& text) {
  const auto eq = text.find('=');
  DASH_THROW_UNLESS(eq != std::string::npos && eq > 0, "--set expects NAME=VALUE, got '" + text + "'");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

std::string describeParameters(const std::string& planner) {
  std::string out = planner + " parameters (default; the paper's value for extensions):\n";
  for (const ParamInfo& p : plannerParameters(planner)) {
    char line[512];
    std::snprintf(line, sizeof line, "  %-26s %-6s paper %-6s %s\n", p.name.c_str(), p.default_value.c_str(),
                  p.extension() ? p.paper_value.c_str() : "same", p.description.c_str());
    out += line;
  }
  return out;
}

std::string parametersMarkdown(const std::string& planner) {
  std::string out = "| parameter | default | paper | source | what it does |\n|---|---|---|---|---|\n";
  for (const ParamInfo& p : plannerParameters(planner))
    out += "| `" + p.name + "` | " + p.default_value + " | " + (p.extension() ? p.paper_value : "same (a budget)") +
           " | " + p.source + " | " + p.description + " |\n";
  return out;
}

std::string parametersJson(const ParamValues& values) {
  std::string out = "{";
  for (const auto& [name, value] : values) {
    if (out.size() > 1) out += ",";
    // Names are ours (letters and underscores); values are canonical booleans or numbers.
    out += "\"" + name + "\":" + value;
  }
  return out + "}";
}

bool paramBool(const ParamValues& values, const std::string& name) {
  const auto it = values.find(name);
  DASH_DEMAND_MSG(it != values.end(), name);
  return it->second == "true";
}

int paramInt(const ParamValues& values, const std::string& name) {
  const auto it = values.find(name);
  DASH_DEMAND_MSG(it != values.end(), name);
  return std::stoi(it->second);
}

double paramReal(const ParamValues& values, const std::string& name) {
  const auto it = values.find(name);
  DASH_DEMAND_MSG(it != values.end(), name);
  return std::stod(it->second);
}

}  // namespace dash
