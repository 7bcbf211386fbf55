#include "engine/conflict/segment_boxes.h"

#include <algorithm>

#include "engine/collision/segment_queries.h"

namespace dash {

SegmentBoxes::SegmentBoxes(const CollisionWorld& world, CollisionContext& context)
    : world_(&world), context_(&context), entries_(static_cast<std::size_t>(world.robotCount())) {}

void appendHeldKey(std::vector<double>& key, const HeldObject& held) {
  key.push_back(held.object);
  key.push_back(held.in_transit ? 1.0 : 0.0);
  if (!held.holding()) return;
  const double* m = held.X_TO.matrix().data();
  key.insert(key.end(), m, m + 12);  // the rotation and translation columns
}

void SegmentBoxes::holdsKey(const RobotTimeline& timeline, double ta, double tb, std::vector<double>& key) {
  key.clear();
  for (const HoldInterval& h : timeline.holds())
    if (h.from <= tb && h.to >= ta) appendHeldKey(key, h.held);  // closed: more than heldAt gives inside
}

Aabb SegmentBoxes::segmentBox(const RobotTimeline& timeline, const JointVector& qa, const JointVector& qb, double ta,
                              double tb) {
  ++computed_;
  Aabb box;
  box.setEmpty();
  auto add = [&](const HeldObject& held) {
    parts_.clear();
    sweptPartBoxes(*world_, *context_, {timeline.robot(), qa, held}, qb, parts_);
    for (const Aabb& part : parts_) box.extend(part);
  };
  add({});  // the bodies (an empty hand at some instant, or none held at all)
  for (const HoldInterval& h : timeline.holds())
    if (h.from <= tb && h.to >= ta) add(h.held);
  box.min().array() -= kBoxSlack;
  box.max().array() += kBoxSlack;
  return box;
}

std::optional<Aabb> SegmentBoxes::pieceBox(const RobotTimeline& timeline, double u, double v) {
  const auto& pts = timeline.points();
  const double mid = 0.5 * (u + v);
  auto it = std::upper_bound(pts.begin(), pts.end(), mid, [](double t, const TimedPoint& p) { return t < p.t; });
  if (it == pts.begin()) return std::nullopt;  // before the first point
  const std::size_t i = static_cast<std::size_t>(it - pts.begin()) - 1;
  const bool last = it == pts.end();
  const double ta = pts[i].t, tb = last ? kForever : it->t;
  if (u < ta || v > tb) return std::nullopt;  // across a point (cuts merged within 1e-9 s)
  const JointVector& qa = pts[i].q;
  const JointVector& qb = last ? qa : it->q;
  std::vector<Entry>& entries = entries_.at(static_cast<std::size_t>(timeline.robot()));
  if (entries.size() <= i) entries.resize(i + 1);
  Entry& e = entries[i];
  holdsKey(timeline, ta, tb, key_);
  if (e.valid && e.ta == ta && e.tb == tb && e.qa == qa && e.qb == qb && e.holds == key_) return e.box;
  e.box = segmentBox(timeline, qa, qb, ta, tb);
  e.valid = true;
  e.ta = ta;
  e.tb = tb;
  e.qa = qa;
  e.qb = qb;
  e.holds = key_;
  return e.box;
}

}  // namespace dash
