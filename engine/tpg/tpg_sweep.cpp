#include "engine/tpg/tpg_sweep.h"

#include <algorithm>
#include <array>
#include <queue>
#include <limits>

#include "engine/collision/distance_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/robots/kinematics.h"

namespace dash::tpg::detail {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

}  // namespace

Sweeps::Sweeps(const Scene& scene, const BuildOptions& options)
    : scene_(scene), options_(options), world_(scene), context_(world_) {}

void Sweeps::pose(const Piece& p, double u, std::vector<Part>& out) const {
  out.clear();
  const SceneRobot& robot = scene_.robots[at(p.robot)];
  const RobotGeometry& rg = world_.robot(p.robot);
  const JointVector q = p.q0 + u * (p.q1 - p.q0);
  std::vector<Pose> frames(rg.bodies.size());
  bodyFrames(*robot.model, robot.X_WB, q, frames);
  for (std::size_t b = 0; b < rg.bodies.size(); ++b) {
    const BodyGeometry& body = rg.bodies[b];
    out.push_back({body.shape.get(), frames[b] * body.X_FG, frames[b].translation(), body.extent, body.is_gripper,
                   false, -1});
  }
  if (p.held >= 0) {
    const Pose X_WO = forwardKinematics(*robot.model, robot.X_WB, q).X_WT * p.X_TO;
    const ObjectGeometry& og = world_.object(p.held);
    out.push_back({og.shape.get(), X_WO, X_WO.translation(), og.half_extents.norm(), false, true, p.held});
  }
}

void Sweeps::prepare(Piece& piece) {
  piece.moves = (piece.q1 - piece.q0).cwiseAbs().maxCoeff() > 0.0;
  HeldObject held;
  held.object = piece.held;
  held.X_TO = piece.X_TO;
  piece.rate = piece.moves ? segmentDisplacementBound(world_, piece.robot, piece.q0, piece.q1, held) : 0.0;
  piece.parts.clear();
  sweptPartBoxes(world_, context_, RobotState{piece.robot, piece.q0, held}, piece.q1, piece.parts);
  piece.box.setEmpty();
  for (const Aabb& part : piece.parts) piece.box.extend(part);
}

bool partsNear(const Piece& a, const Piece& b, double margin) {
  if (a.box.exteriorDistance(b.box) > margin) return false;
  for (const Aabb& x : a.parts) {
    if (x.exteriorDistance(b.box) > margin) continue;
    for (const Aabb& y : b.parts) {
      if (x.exteriorDistance(y) <= margin) return true;
    }
  }
  return false;
}

bool partsNear(const Piece& a, const Aabb& box, double margin) {
  for (const Aabb& x : a.parts) {
    if (x.exteriorDistance(box) <= margin) return true;
  }
  return false;
}

Sweeps::Distances Sweeps::distance(const Piece& a, const std::vector<Part>& pa, const Piece& b,
                                   const std::vector<Part>& pb, double enough) {
  ++evaluations_;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Distances best{kInf, kInf};
  for (const Part& x : pa) {
    for (const Part& y : pb) {
      const bool contact = (x.gripper && y.held && (y.object == a.adjacent_last || y.object == a.adjacent_next)) ||
                           (y.gripper && x.held && (x.object == b.adjacent_last || x.object == b.adjacent_next));
      double& slot = contact ? best.contact : best.normal;
      const double bound = (x.centre - y.centre).norm() - x.radius - y.radius;
      if (bound > enough || bound >= slot) {
        slot = std::min(slot, bound);
        continue;
      }
      slot = std::min(slot, signedDistance(context_, *x.shape, x.X, *y.shape, y.X));
    }
  }
  return best;
}

bool Sweeps::meet(const Piece& a, const Piece& b, Thresholds th, long long budget) {
  const double reach = std::max(th.normal, th.contact);
  if (a.box.exteriorDistance(b.box) > reach) return false;
  // Best first: the cell least proved apart is split next, so a pair that meets is found early; a
  // pair proved apart costs the same in any order.
  struct Cell {
    double u0, u1, v0, v1;
    double margin;  ///< how far the cell is proved apart (< 0: not yet)
    bool operator<(const Cell& o) const { return margin > o.margin; }
  };
  std::vector<Part> pa, pb;
  enum class Verdict { kMeets, kApart, kOpen };
  auto evaluate = [&](Cell& cell) {
    const double sa = a.rate * (cell.u1 - cell.u0) / 2;
    const double sb = b.rate * (cell.v1 - cell.v0) / 2;
    pose(a, (cell.u0 + cell.u1) / 2, pa);
    pose(b, (cell.v0 + cell.v1) / 2, pb);
    const Distances d = distance(a, pa, b, pb, reach + sa + sb);
    if (--budget < 0 || d.normal <= th.normal || d.contact <= th.contact) return Verdict::kMeets;
    const double normal = d.normal - th.normal - sa - sb;
    cell.margin = std::min(normal, d.contact - th.contact - sa - sb);
    if (cell.margin > 0.0) return Verdict::kApart;
    if (normal <= 0.0) return sa + sb <= options_.resolution / 2 ? Verdict::kMeets : Verdict::kOpen;
    // Only the contact pair is open: measured down to the validator's floor, as it measures it, and at
    // the cell's corners too (a replay holds an arm at a piece's end, where the validator looks).
    if (sa + sb > options_.contact_floor / 2) return Verdict::kOpen;
    for (const double u : {cell.u0, cell.u1}) {
      for (const double v : {cell.v0, cell.v1}) {
        pose(a, u, pa);
        pose(b, v, pb);
        if (distance(a, pa, b, pb, reach).contact <= th.contact) return Verdict::kMeets;
      }
    }
    return Verdict::kApart;
  };
  std::priority_queue<Cell> open;
  Cell root{0.0, 1.0, 0.0, 1.0, 0.0};
  switch (evaluate(root)) {
    case Verdict::kMeets: return true;
    case Verdict::kApart: return false;
    case Verdict::kOpen: open.push(root);
  }
  while (!open.empty()) {
    const Cell cell = open.top();
    open.pop();
    std::array<Cell, 2> halves{cell, cell};
    if (a.rate * (cell.u1 - cell.u0) >= b.rate * (cell.v1 - cell.v0)) {
      halves[0].u1 = halves[1].u0 = (cell.u0 + cell.u1) / 2;
    } else {
      halves[0].v1 = halves[1].v0 = (cell.v0 + cell.v1) / 2;
    }
    for (Cell& half : halves) {
      const Verdict v = evaluate(half);
      if (v == Verdict::kMeets) return true;
      if (v == Verdict::kOpen) open.push(half);
    }
  }
  return false;
}

bool Sweeps::meetsObject(const Piece& a, int object, const Pose& X_WO) {
  const ObjectGeometry& og = world_.object(object);
  const Aabb box = boxAabb(X_WO, og.half_extents);
  const double c = options_.clearance;
  if (!partsNear(a, box, c)) return false;
  // The object as a piece that holds still, so distance() applies (no exemption: it rests).
  Piece still;
  const std::vector<Part> pb{{og.shape.get(), X_WO, X_WO.translation(), og.half_extents.norm(), false, false, object}};
  std::vector<std::pair<double, double>> stack{{0.0, 1.0}};
  std::vector<Part> pa;
  long long budget = options_.max_evaluations;
  while (!stack.empty()) {
    const auto [u0, u1] = stack.back();
    stack.pop_back();
    const double sa = a.rate * (u1 - u0) / 2;
    pose(a, (u0 + u1) / 2, pa);
    const double d = distance(a, pa, still, pb, c + sa).normal;
    if (--budget < 0 || d <= c) return true;
    if (d - sa > c) continue;
    if (sa <= options_.resolution) return true;
    stack.push_back({u0, (u0 + u1) / 2});
    stack.push_back({(u0 + u1) / 2, u1});
  }
  return false;
}

Piece Sweeps::stillAt(const Piece& p, double u) {
  Piece still = p;
  still.q0 = still.q1 = p.q0 + u * (p.q1 - p.q0);
  still.t0 = still.t1 = u < 0.5 ? p.t0 : p.t1;
  prepare(still);
  return still;
}

}  // namespace dash::tpg::detail
