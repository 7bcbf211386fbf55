#include "engine/dash/validated_roadmap.h"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/planners/prm/PRM.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <set>
#include <utility>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/motion/ompl_validity.h"
#include "engine/motion/seeded_ompl_planners.h"
#include "engine/motion/static_robot_validity.h"

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace dash {

namespace {
constexpr double kSameConfig = 1e-12;

std::vector<double> keyOf(const JointVector& q) { return std::vector<double>(q.data(), q.data() + q.size()); }

bool sameGrasp(const HeldObject& a, const HeldObject& b, const CollisionWorld& world) {
  if (a.holding() != b.holding()) return false;
  if (!a.holding()) return true;
  return world.scene().objects[a.object].shape.size == world.scene().objects[b.object].shape.size &&
         a.X_TO.matrix() == b.X_TO.matrix();
}

// plan()'s checks against its context (resting objects, parked robots). Roadmap paths run between
// approach lines: a held object keeps the clearance on every face.
class ContextChecks {
 public:
  ContextChecks(const CollisionWorld& world, CollisionContext& collision, int robot, const MotionContext& context)
      : world_(world), collision_(collision), robot_(robot), context_(context), held_(inTransit(context.held)) {}

  bool stateOk(const JointVector& q, CheckScope scope) {
    const RobotState self{robot_, q, held_};
    if (context_.parked.empty()) return !robotInCollision(world_, collision_, self, context_.layout, nullptr, scope);
    return !robotsAmongParked(world_, collision_, std::span<const RobotState>(&self, 1), context_.parked,
                              context_.layout, nullptr, CheckScope::kAll);
  }

  bool motionOk(const JointVector& p, const JointVector& r, CheckScope scope) {
    if (context_.parked.empty())
      return !segmentInCollision(world_, collision_, RobotState{robot_, p, held_}, r, context_.layout, nullptr,
                                 SegmentOptions{.scope = scope});
    const RobotMotion self{RobotState{robot_, p, held_}, r};
    return !motionsAmongParked(world_, collision_, std::span<const RobotMotion>(&self, 1), context_.parked,
                               context_.layout);
  }

 private:
  const CollisionWorld& world_;
  CollisionContext& collision_;
  const int robot_;
  const MotionContext& context_;
  const HeldObject held_;
};

using Adjacency = std::vector<std::vector<std::pair<int, double>>>;

// Lazy-PRM's loop (Bohlin and Kavraki 2000) over a validated roadmap: shortest paths va -> vb, A* by
// distance to b, whose vertices and edges are checked against the context only when a path uses them;
// roadmap vertices and edges are statically valid, so only the context's part is checked.
class LazySearch {
 public:
  LazySearch(const std::vector<JointVector>& q, const Adjacency& adj, ContextChecks& checks, int va, int vb,
             const JointVector& b)
      : q_(q), adj_(adj), checks_(checks), va_(va), vb_(vb), b_(b), vertex_ok_(q.size(), -1) {
    vertex_ok_[va] = vertex_ok_[vb] = 1;
  }

  /// The vertices of a valid path va -> vb, none if there is none or the deadline passed.
  std::optional<std::vector<int>> run(const Deadline& deadline) {
    while (!deadline.expired()) {
      const std::vector<int> path = shortestPath();
      if (path.empty()) return std::nullopt;
      // Lazy-PRM's order: vertices first (all invalid ones go), then the first invalid edge.
      if (dropInvalidVertices(path) || dropFirstInvalidEdge(path)) continue;
      return path;
    }
    return std::nullopt;
  }

 private:
  static std::pair<int, int> edgeKey(int x, int y) { return std::make_pair(std::min(x, y), std::max(x, y)); }

  // Over the vertices and edges not known invalid; empty when vb is unreachable.
  std::vector<int> shortestPath() const {
    using Item = std::pair<double, int>;
    std::vector<double> g(q_.size(), std::numeric_limits<double>::infinity());
    std::vector<int> pred(q_.size(), -1);
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    g[va_] = 0.0;
    open.push({(q_[va_] - b_).norm(), va_});
    while (!open.empty()) {
      const auto [f, v] = open.top();
      open.pop();
      if (v == vb_) break;
      if (f - (q_[v] - b_).norm() > g[v] + 1e-12) continue;
      for (const auto& [w, len] : adj_[v]) {
        if (vertex_ok_[w] == 0 || bad_edges_.contains(edgeKey(v, w))) continue;
        if (g[v] + len < g[w]) {
          g[w] = g[v] + len;
          pred[w] = v;
          open.push({g[w] + (q_[w] - b_).norm(), w});
        }
      }
    }
    std::vector<int> path;
    if (!std::isfinite(g[vb_])) return path;
    for (int v = vb_; v >= 0; v = pred[v]) path.push_back(v);
    std::reverse(path.begin(), path.end());
    return path;
  }

  // Checks every unchecked vertex of `path`; whether one of them is invalid.
  bool dropInvalidVertices(const std::vector<int>& path) {
    bool dropped = false;
    for (int v : path) {
      if (vertex_ok_[v] < 0) vertex_ok_[v] = checks_.stateOk(q_[v], CheckScope::kObjectsOnly) ? 1 : 0;
      dropped = dropped || vertex_ok_[v] == 0;
    }
    return dropped;
  }

  // Checks the unchecked edges of `path` in order up to the first invalid one; whether there is one.
  bool dropFirstInvalidEdge(const std::vector<int>& path) {
    for (std::size_t i = 1; i < path.size(); ++i) {
      const auto key = edgeKey(path[i - 1], path[i]);
      if (good_edges_.contains(key)) continue;
      if (!checks_.motionOk(q_[path[i - 1]], q_[path[i]], CheckScope::kObjectsOnly)) {
        bad_edges_.insert(key);
        return true;
      }
      good_edges_.insert(key);
    }
    return false;
  }

  const std::vector<JointVector>& q_;
  const Adjacency& adj_;
  ContextChecks& checks_;
  const int va_, vb_;
  const JointVector& b_;
  std::vector<signed char> vertex_ok_;
  std::set<std::pair<int, int>> bad_edges_, good_edges_;
};
}  // namespace

struct ValidatedRoadmap::Space {
  HeldObject held;  ///< the geometry every vertex and edge of this space was validated with
  std::vector<JointVector> q;
  std::vector<std::vector<std::pair<int, double>>> adj;
  std::vector<int> of_milestone;  ///< og::PRM vertex -> vertex here, -1 where invalid with `held`
  std::vector<int> anchor_list;
  std::map<std::vector<double>, int> anchors;
  std::size_t synced = 0;  ///< og::PRM vertices already brought in
  std::size_t edges = 0;

  int addVertex(const JointVector& c) {
    q.push_back(c);
    adj.emplace_back();
    return static_cast<int>(q.size()) - 1;
  }
  void addEdge(int a, int b) {
    const double d = (q[a] - q[b]).norm();
    adj[a].push_back({b, d});
    adj[b].push_back({a, d});
    ++edges;
  }
};



ValidatedRoadmap::ValidatedRoadmap(const CollisionWorld& world, CollisionContext& context, int robot,
                                   ValidatedRoadmapParams params)
    : world_(&world), context_(&context), robot_(robot), params_(params) {
  const RobotModel& model = *world.scene().robots[robot].model;
  dof_ = model.dof();
  // og::PRM builds the shared roadmap with an empty hand against what never moves.
  statically_ = std::make_shared<StaticRobotValidity>(world, context, robot);
  si_ = std::make_shared<ob::SpaceInformation>(jointSpace(model));
  const StaticRobotValidity* v = statically_.get();
  const int dof = dof_;
  installValidity(
      si_, [v, dof](const ob::State* s) { return v->stateValid(jointsOf(s, dof)); },
      [v, dof](const ob::State* a, const ob::State* b) { return v->motionValid(jointsOf(a, dof), jointsOf(b, dof)); });
  si_->setup();
  prm_ = std::make_shared<SeededPRM>(si_, false);
  prm_->setMaxNearestNeighbors(params_.neighbours);
  // og::PRM takes its edge-cost objective from the problem definition in setup(): give it an empty one.
  prm_->setProblemDefinition(std::make_shared<ob::ProblemDefinition>(si_));
  prm_->setup();
}

ValidatedRoadmap::~ValidatedRoadmap() = default;

std::size_t ValidatedRoadmap::milestoneCount() const { return prm_->milestoneCount(); }

void ValidatedRoadmap::growTo(std::size_t milestones, const Deadline& deadline) {
  if (prm_->milestoneCount() < milestones) {
    const ob::PlannerTerminationCondition ptc(
        [this, milestones, &deadline] { return prm_->milestoneCount() >= milestones || deadline.expired(); });
    prm_->growRoadmap(ptc);
  }
  for (auto& s : spaces_) sync(*s);
}

bool ValidatedRoadmap::stateFree(const Space& space, const JointVector& q) {
  return statically_->stateValid(q, space.held);
}

bool ValidatedRoadmap::segmentFree(const Space& space, const JointVector& a, const JointVector& b) {
  return statically_->motionValid(a, b, space.held);
}

// Brings the og::PRM milestones and edges added since the last call into `space`. With an empty hand
// they are valid as og::PRM checked them; with a held object each is checked again with it.
void ValidatedRoadmap::sync(Space& space) {
  const og::PRM::Graph& g = prm_->getRoadmap();
  const std::size_t n = boost::num_vertices(g);
  if (n == space.synced) return;
  const auto states = boost::get(og::PRM::vertex_state_t(), g);
  const bool holding = space.held.holding();
  const std::size_t first_new = space.synced;
  space.of_milestone.resize(n, -1);
  std::vector<int> fresh;
  for (std::size_t v = first_new; v < n; ++v) {
    const JointVector q = jointsOf(states[v], dof_);
    if (holding && !stateFree(space, q)) continue;
    space.of_milestone[v] = space.addVertex(q);
    fresh.push_back(space.of_milestone[v]);
  }
  for (const auto& e : boost::make_iterator_range(boost::edges(g))) {
    const std::size_t u = boost::source(e, g), w = boost::target(e, g);
    if (std::max(u, w) < first_new) continue;  // og::PRM only ever adds edges at a new milestone
    const int a = space.of_milestone[u], b = space.of_milestone[w];
    if (a < 0 || b < 0) continue;
    if (holding && !segmentFree(space, space.q[a], space.q[b])) continue;
    space.addEdge(a, b);
  }
  space.synced = n;
  // New milestones near existing anchors: the anchors' connections predate them.
  if (!space.anchor_list.empty())
    for (int v : fresh) connectAnchor(space, v, true);
}

int ValidatedRoadmap::space(const HeldObject& held) {
  for (std::size_t i = 0; i < spaces_.size(); ++i)
    if (sameGrasp(spaces_[i]->held, held, *world_)) return static_cast<int>(i);
  auto s = std::make_unique<Space>();
  s->held = inTransit(held);  // roadmap paths run between approach lines
  sync(*s);
  spaces_.push_back(std::move(s));
  return static_cast<int>(spaces_.size()) - 1;
}

// Connects `vertex` to its nearest vertices of the space (or nearest anchors only) by validated edges.
void ValidatedRoadmap::connectAnchor(Space& space, int vertex, bool to_anchors_only) {
  std::vector<std::pair<double, int>> near;
  const JointVector& q = space.q[vertex];
  auto consider = [&](int v) {
    if (v != vertex) near.push_back({(space.q[v] - q).norm(), v});
  };
  if (to_anchors_only) {
    for (int v : space.anchor_list) consider(v);
  } else {
    for (int v = 0; v < static_cast<int>(space.q.size()); ++v) consider(v);
  }
  const std::size_t k = std::min<std::size_t>(params_.anchor_neighbours, near.size());
  std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(k), near.end());
  for (std::size_t i = 0; i < k; ++i) {
    const int v = near[i].second;
    const bool linked = std::any_of(space.adj[vertex].begin(), space.adj[vertex].end(),
                                    [v](const auto& e) { return e.first == v; });
    if (linked || !segmentFree(space, q, space.q[v])) continue;
    space.addEdge(vertex, v);
  }
}

int ValidatedRoadmap::anchor(int s, const JointVector& q) {
  Space& space = *spaces_[s];
  auto key = keyOf(q);
  if (auto it = space.anchors.find(key); it != space.anchors.end()) return it->second;
  const int v = space.addVertex(q);
  space.anchors.emplace(std::move(key), v);
  space.anchor_list.push_back(v);
  connectAnchor(space, v, false);
  return v;
}

const JointVector& ValidatedRoadmap::config(int s, int vertex) const { return spaces_[s]->q[vertex]; }

ValidatedRoadmap::Tree ValidatedRoadmap::shortestPaths(int s, int from) const {
  const Space& space = *spaces_[s];
  Tree tree;
  tree.dist.assign(space.q.size(), std::numeric_limits<double>::infinity());
  tree.pred.assign(space.q.size(), -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  tree.dist[from] = 0.0;
  open.push({0.0, from});
  while (!open.empty()) {
    const auto [d, v] = open.top();
    open.pop();
    if (d > tree.dist[v]) continue;
    for (const auto& [w, len] : space.adj[v]) {
      if (d + len < tree.dist[w]) {
        tree.dist[w] = d + len;
        tree.pred[w] = v;
        open.push({tree.dist[w], w});
      }
    }
  }
  return tree;
}

std::vector<JointVector> ValidatedRoadmap::pathTo(int s, const Tree& tree, int to) const {
  std::vector<JointVector> path;
  if (!std::isfinite(tree.dist[to])) return path;
  for (int v = to; v >= 0; v = tree.pred[v]) path.push_back(spaces_[s]->q[v]);
  std::reverse(path.begin(), path.end());
  return path;
}

std::optional<std::vector<JointVector>> ValidatedRoadmap::plan(const JointVector& a, const JointVector& b,
                                                               const MotionContext& context,
                                                               const Deadline& deadline) {
  if ((a - b).cwiseAbs().maxCoeff() < kSameConfig) return std::vector<JointVector>{a};
  ContextChecks checks(*world_, *context_, robot_, context);
  // Cheapest first: the straight segment, checked against everything.
  if (checks.motionOk(a, b, CheckScope::kAll)) return std::vector<JointVector>{a, b};
  if (!checks.stateOk(a, CheckScope::kAll) || !checks.stateOk(b, CheckScope::kAll)) return std::nullopt;

  const int s = space(context.held);
  const int va = anchor(s, a);
  const int vb = anchor(s, b);
  const Space& sp = *spaces_[s];
  const std::optional<std::vector<int>> path = LazySearch(sp.q, sp.adj, checks, va, vb, b).run(deadline);
  if (!path) return std::nullopt;
  std::vector<JointVector> out;
  for (int v : *path) out.push_back(sp.q[v]);
  out.front() = a;
  out.back() = b;
  return out;
}

std::size_t ValidatedRoadmap::vertexCount() const {
  std::size_t n = 0;
  for (const auto& s : spaces_) n += s->q.size();
  return n;
}

std::size_t ValidatedRoadmap::edgeCount() const {
  std::size_t n = 0;
  for (const auto& s : spaces_) n += s->edges;
  return n;
}

}  // namespace dash
