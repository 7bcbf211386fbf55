// The graph's accessors, its structural check and its JSON codec (the "tpg" field of a plan).
#include "engine/tpg/tpg.h"

#include <cmath>
#include <deque>
#include <nlohmann/json.hpp>

#include "engine/core/check.h"

namespace dash::tpg {

namespace {

using Json = nlohmann::ordered_json;
inline std::size_t at(int i) { return static_cast<std::size_t>(i); }
constexpr double kTolerance = 1e-6;
constexpr std::size_t kMaxNodes = 1000000;
constexpr std::size_t kMaxEdges = 4000000;

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

std::string nodeProblem(const Graph& graph, const Plan& plan, std::vector<int>& seen_events) {
  int robot = -1;
  double t = 0.0;
  for (std::size_t i = 0; i < graph.nodes.size(); ++i) {
    const Node& n = graph.nodes[i];
    const std::string where = "node " + std::to_string(i) + ": ";
    if (n.robot < 0 || n.robot >= static_cast<int>(graph.robots.size())) return where + "robot out of range";
    if (n.robot < robot) return where + "nodes must be grouped by robot, in the plan's robot order";
    if (n.robot != robot) {
      if (robot >= 0 && t + kTolerance < plan.robots[at(robot)].endTime()) {
        return "robot " + graph.robots[at(robot)] + ": its nodes end at t=" + number(t) + ", before its last point";
      }
      robot = n.robot;
      t = 0.0;
    }
    if (!std::isfinite(n.t0) || !std::isfinite(n.t1) || std::abs(n.t0 - t) > kTolerance || n.t1 + kTolerance < n.t0) {
      return where + "does not start where the robot's previous node ends (t=" + number(t) + ")";
    }
    t = n.t1;
    if (n.kind == Node::Kind::kEvent) {
      if (n.event < 0 || n.event >= static_cast<int>(plan.events.size())) return where + "event out of range";
      const PlanEvent& e = plan.events[at(n.event)];
      if (e.robot != graph.robots[at(n.robot)] || std::abs(e.t - n.t0) > kTolerance || n.t1 != n.t0) {
        return where + "is not the plan's event " + std::to_string(n.event);
      }
      if (seen_events[at(n.event)]++ > 0) return where + "event " + std::to_string(n.event) + " appears twice";
    }
  }
  if (robot >= 0 && t + kTolerance < plan.robots[at(robot)].endTime()) {
    return "robot " + graph.robots[at(robot)] + ": its nodes end at t=" + number(t) + ", before its last point";
  }
  return "";
}

}  // namespace

const char* edgeWhyName(Edge::Why why) {
  switch (why) {
    case Edge::Why::kHandover: return "handover";
    case Edge::Why::kObject: return "object";
    case Edge::Why::kSwept: return "swept";
  }
  return "swept";
}

std::vector<int> Graph::armNodes(int r) const {
  std::vector<int> out;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].robot == r) out.push_back(static_cast<int>(i));
  }
  return out;
}

std::vector<std::vector<int>> Graph::predecessors() const {
  std::vector<std::vector<int>> preds(nodes.size());
  for (std::size_t i = 1; i < nodes.size(); ++i) {
    if (nodes[i].robot == nodes[i - 1].robot) preds[i].push_back(static_cast<int>(i) - 1);
  }
  for (const Edge& e : edges) preds[at(e.to)].push_back(e.from);
  return preds;
}

std::string graphProblem(const Graph& graph, const Plan& plan) {
  if (graph.robots.size() != plan.robots.size()) return "the graph's robots are not the plan's";
  for (std::size_t r = 0; r < plan.robots.size(); ++r) {
    if (graph.robots[r] != plan.robots[r].robot) return "the graph's robots are not the plan's, in its order";
  }
  std::vector<int> seen(plan.events.size(), 0);
  if (std::string p = nodeProblem(graph, plan, seen); !p.empty()) return p;
  for (std::size_t e = 0; e < seen.size(); ++e) {
    if (seen[e] == 0) return "event " + std::to_string(e) + " of the plan has no node";
  }
  for (std::size_t r = 0; r < plan.robots.size(); ++r) {
    if (graph.armNodes(static_cast<int>(r)).empty()) return "robot " + plan.robots[r].robot + " has no node";
  }
  const int n = static_cast<int>(graph.nodes.size());
  for (const Edge& e : graph.edges) {
    if (e.from < 0 || e.from >= n || e.to < 0 || e.to >= n) return "an edge names a node out of range";
    if (graph.nodes[at(e.from)].robot == graph.nodes[at(e.to)].robot) return "an edge joins two nodes of one robot";
  }
  // No cycle (Kahn).
  const auto preds = graph.predecessors();
  std::vector<std::vector<int>> succs(at(n));
  std::vector<int> pending(at(n), 0);
  for (int i = 0; i < n; ++i) {
    pending[at(i)] = static_cast<int>(preds[at(i)].size());
    for (int p : preds[at(i)]) succs[at(p)].push_back(i);
  }
  std::deque<int> ready;
  for (int i = 0; i < n; ++i) {
    if (pending[at(i)] == 0) ready.push_back(i);
  }
  int done = 0;
  while (!ready.empty()) {
    const int i = ready.front();
    ready.pop_front();
    ++done;
    for (int s : succs[at(i)]) {
      if (--pending[at(s)] == 0) ready.push_back(s);
    }
  }
  if (done != n) return "the edges form a cycle: no execution can respect them";
  return "";
}

std::string tpgToJson(const Graph& graph, const Plan& plan) {
  Json nodes = Json::array();
  for (const Node& n : graph.nodes) {
    Json j{{"robot", plan.robots[at(n.robot)].robot}, {"kind", n.kind == Node::Kind::kEvent ? "event" : "motion"},
           {"t0", n.t0}, {"t1", n.t1}};
    if (n.kind == Node::Kind::kEvent) j["event"] = n.event;
    else j["moves"] = n.moves;
    nodes.push_back(std::move(j));
  }
  Json edges = Json::array();
  for (const Edge& e : graph.edges) edges.push_back(Json{{"from", e.from}, {"to", e.to}, {"why", edgeWhyName(e.why)}});
  Json root{{"format", kTpgFormat}, {"clearance", graph.clearance}, {"forced", graph.forced},
            {"nodes", std::move(nodes)}, {"edges", std::move(edges)}};
  return root.dump();
}

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputError("tpg." + path + ": " + what);
}

const Json& field(const Json& j, const std::string& path, const char* name) {
  const auto it = j.find(name);
  if (it == j.end()) fail(path.empty() ? name : path + "." + name, "missing");
  return *it;
}

double finiteNumber(const Json& j, const std::string& path) {
  if (!j.is_number()) fail(path, "expected a number");
  const double x = j.get<double>();
  if (!std::isfinite(x)) fail(path, "expected a finite number");
  return x;
}

int index(const Json& j, const std::string& path, std::size_t size) {
  if (!j.is_number_unsigned() || j.get<std::uint64_t>() >= size) fail(path, "expected an index below " + std::to_string(size));
  return static_cast<int>(j.get<std::uint64_t>());
}

Node parseNode(const Json& j, const std::string& path, const Plan& plan) {
  if (!j.is_object()) fail(path, "expected an object");
  Node n;
  const Json& robot = field(j, path, "robot");
  if (!robot.is_string()) fail(path + ".robot", "expected a robot id");
  for (std::size_t r = 0; r < plan.robots.size(); ++r) {
    if (plan.robots[r].robot == robot.get<std::string>()) n.robot = static_cast<int>(r);
  }
  if (n.robot < 0) fail(path + ".robot", "\"" + robot.get<std::string>() + "\" is not a robot of the plan");
  const Json& kind = field(j, path, "kind");
  if (kind == "event") n.kind = Node::Kind::kEvent;
  else if (kind != "motion") fail(path + ".kind", "expected \"motion\" or \"event\"");
  n.t0 = finiteNumber(field(j, path, "t0"), path + ".t0");
  n.t1 = finiteNumber(field(j, path, "t1"), path + ".t1");
  if (n.kind == Node::Kind::kEvent) {
    n.event = index(field(j, path, "event"), path + ".event", plan.events.size());
  } else if (const auto it = j.find("moves"); it != j.end()) {
    if (!it->is_boolean()) fail(path + ".moves", "expected true or false");
    n.moves = it->get<bool>();
  }
  return n;
}

}  // namespace

Graph parseTpg(const std::string& json_text, const Plan& plan) {
  Json root = Json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded() || !root.is_object()) throw InputError("tpg: expected a JSON object");
  if (field(root, "", "format") != kTpgFormat) fail("format", std::string("expected \"") + kTpgFormat + "\"");
  Graph g;
  for (const RobotTrajectory& r : plan.robots) g.robots.push_back(r.robot);
  g.clearance = finiteNumber(field(root, "", "clearance"), "clearance");
  if (g.clearance < 0.0) fail("clearance", "must not be negative");
  if (const auto it = root.find("forced"); it != root.end()) g.forced = index(*it, "forced", kMaxEdges);
  const Json& nodes = field(root, "", "nodes");
  if (!nodes.is_array() || nodes.size() > kMaxNodes) fail("nodes", "expected an array of at most 1000000 nodes");
  for (std::size_t i = 0; i < nodes.size(); ++i) g.nodes.push_back(parseNode(nodes[i], "nodes[" + std::to_string(i) + "]", plan));
  const Json& edges = field(root, "", "edges");
  if (!edges.is_array() || edges.size() > kMaxEdges) fail("edges", "expected an array of at most 4000000 edges");
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const std::string path = "edges[" + std::to_string(i) + "]";
    if (!edges[i].is_object()) fail(path, "expected an object");
    Edge e;
    e.from = index(field(edges[i], path, "from"), path + ".from", g.nodes.size());
    e.to = index(field(edges[i], path, "to"), path + ".to", g.nodes.size());
    const Json& why = field(edges[i], path, "why");
    if (why == "handover") e.why = Edge::Why::kHandover;
    else if (why == "object") e.why = Edge::Why::kObject;
    else if (why != "swept") fail(path + ".why", "expected \"handover\", \"object\" or \"swept\"");
    g.edges.push_back(e);
  }
  if (const std::string problem = graphProblem(g, plan); !problem.empty()) throw InputError("tpg: " + problem);
  return g;
}

}  // namespace dash::tpg
