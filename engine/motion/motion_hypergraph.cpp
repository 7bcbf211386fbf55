#include "engine/motion/motion_hypergraph.h"

#include <bit>
#include <utility>

#include "engine/core/check.h"

std::size_t std::hash<dash::lazy::MotionVertex>::operator()(const dash::lazy::MotionVertex& v) const noexcept {
  std::size_t h = std::hash<dash::TaskElement>{}(v.element) * 131 + static_cast<std::uint16_t>(v.robot);
  for (double x : v.values) {
    // + 0.0 makes -0.0 hash as 0.0 (they compare equal).
    h ^= std::bit_cast<std::uint64_t>(x + 0.0) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
  }
  return h;
}

namespace dash::lazy {

namespace {

const char* arcTypeName(const MotionArc& a) {
  switch (a.type) {
    case MotionArcType::kSource:
      return "source";
    case MotionArcType::kSink:
      return "sink";
    case MotionArcType::kMove:
      return "move";
    case MotionArcType::kTransition:
      return taskArcTypeName(a.action.type);
  }
  return "?";
}

}  // namespace

MotionHypergraph::MotionHypergraph(log::EventEmitter& emitter, std::function<std::string(const MotionVertex&)> labels)
    : emitter_(&emitter), labels_(std::move(labels)) {}

VertexId MotionHypergraph::addVertex(MotionVertex v) {
  const AddResult<VertexId> added = graph_.addVertex(std::move(v));
  if (added.inserted && emitter_->enabled())
    emitter_->vertex(log::Layer::Motion, added.id.value(), labels_ ? labels_(graph_.property(added.id)) : std::string());
  return added.id;
}

HyperarcId MotionHypergraph::addArc(std::vector<VertexId> tail, std::vector<VertexId> head, MotionArc property,
                                    const char* type) {
  const AddResult<HyperarcId> added = graph_.addHyperarc(std::move(tail), std::move(head), std::move(property));
  if (added.inserted) {
    paths_.emplace_back();
    emitter_->hyperarcOf(log::Layer::Motion, type, added.id.value(), graph_.head(added.id), graph_.tail(added.id));
  }
  return added.id;
}

VertexId MotionHypergraph::robotVertex(int robot, const TaskElement& element, const JointVector& q) {
  return addVertex({static_cast<std::int16_t>(robot), element, std::vector<double>(q.data(), q.data() + q.size())});
}

VertexId MotionHypergraph::objectVertex(int object, int location, const Pose& X_WO) {
  MotionVertex v{-1, TaskElement::objectAt(object, location), {}};
  for (int i = 0; i < 3; ++i) v.values.push_back(X_WO.translation()[i]);
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) v.values.push_back(X_WO.linear()(r, c));
  return addVertex(std::move(v));
}

VertexId MotionHypergraph::taskVertex(int task, bool done) {
  return addVertex(MotionVertex{-1, TaskElement::taskState(task, done), {}});
}

std::optional<HyperarcId> MotionHypergraph::move(VertexId from, VertexId to, const std::vector<JointVector>& path,
                                                  bool validated) {
  if (from == to) return std::nullopt;
  const std::size_t before = paths_.size();
  const HyperarcId id = addArc({from}, {to}, MotionArc{MotionArcType::kMove, {}}, "move");
  if (validated || paths_.size() > before) paths_[id.value()] = path;
  return id;
}

HyperarcId MotionHypergraph::transition(const TaskArc& action, std::vector<VertexId> tail, std::vector<VertexId> head) {
  MotionArc a{MotionArcType::kTransition, action};
  a.action.cost = 0.0;  // not part of equality; keep the stored property canonical
  const char* type = arcTypeName(a);
  return addArc(std::move(tail), std::move(head), std::move(a), type);
}

HyperarcId MotionHypergraph::source(std::vector<VertexId> head) {
  return addArc({}, std::move(head), MotionArc{MotionArcType::kSource, {}}, "source");
}

HyperarcId MotionHypergraph::sink(std::vector<VertexId> tail) {
  return addArc(std::move(tail), {}, MotionArc{MotionArcType::kSink, {}}, "sink");
}

std::size_t MotionHypergraph::coupledHyperarcCount() const {
  std::size_t n = 0;
  for (HyperarcId a : graph_.hyperarcs()) {
    if (graph_.property(a).type != MotionArcType::kTransition) continue;
    int first = -2;
    bool coupled = false;
    for (VertexId v : graph_.tail(a)) {
      const int r = graph_.property(v).robot;
      if (r < 0) continue;
      if (first >= 0 && r != first) coupled = true;
      if (first < 0) first = r;
    }
    n += coupled ? 1 : 0;
  }
  return n;
}

void MotionHypergraph::beginQuery() {
  query_ = {};
  instance_.clear();
}

ExtendedMotionVertex MotionHypergraph::newInstance(VertexId v) {
  const auto id = static_cast<ExtendedMotionVertex>(extended_vertices_++);
  ++query_.extended_vertices;
  instance_[v.value()] = id;
  emitter_->vertex(log::Layer::MotionExtended, id, std::to_string(v.value()));
  return id;
}

ExtendedMotionVertex MotionHypergraph::instanceOf(VertexId v) {
  const auto it = instance_.find(v.value());
  return it != instance_.end() ? it->second : newInstance(v);
}

std::uint32_t MotionHypergraph::take(HyperarcId arc) {
  std::vector<std::uint32_t> tail, head;
  for (VertexId v : graph_.tail(arc)) tail.push_back(instanceOf(v));
  for (VertexId v : graph_.head(arc)) head.push_back(newInstance(v));
  const auto id = static_cast<std::uint32_t>(extended_hyperarcs_++);
  ++query_.extended_hyperarcs;
  if (graph_.property(arc).type == MotionArcType::kSink) query_.reached_sink = true;
  if (emitter_->enabled())
    emitter_->hyperarc(log::Layer::MotionExtended, arcTypeName(graph_.property(arc)), id, std::move(head), std::move(tail));
  return id;
}

}  // namespace dash::lazy
