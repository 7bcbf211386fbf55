// buildGraph (tpg.h): events in the validator's order, each arm's timeline cut into pieces, the
// pairs of pieces that meet, cuts made finer where two pieces overlap in time, then the pieces merged
// into segments between the cuts that edges need.
#include <algorithm>
#include <limits>
#include <set>
#include <tuple>

#include "engine/core/check.h"
#include "engine/robots/kinematics.h"
#include "engine/tpg/tpg_builder.h"

namespace dash::tpg {

namespace detail {

Pose Builder::tcp(int arm, double t) const {
  const SceneRobot& robot = scene_.robots[at(scene_robot_[at(arm)])];
  return forwardKinematics(*robot.model, robot.X_WB, plan_.robots[at(arm)].positionAt(t)).X_WT;
}

void Builder::sortEvents() {
  // The validator's order at one instant: grasps of an object another robot holds, releases, other
  // grasps, inspects. Which grasps take over a held object follows from replaying in time order.
  std::vector<int> by_time(plan_.events.size());
  for (std::size_t i = 0; i < by_time.size(); ++i) by_time[i] = static_cast<int>(i);
  std::stable_sort(by_time.begin(), by_time.end(),
                   [&](int a, int b) { return plan_.events[at(a)].t < plan_.events[at(b)].t; });
  std::map<std::string, int> holders;
  std::size_t i = 0;
  while (i < by_time.size()) {
    std::size_t j = i;
    const double t = plan_.events[at(by_time[i])].t;
    while (j < by_time.size() && plan_.events[at(by_time[j])].t - t <= kTimeTolerance) ++j;
    std::vector<std::pair<int, int>> ranked;  // (rank, event)
    for (std::size_t k = i; k < j; ++k) {
      const PlanEvent& e = plan_.events[at(by_time[k])];
      int rank = 3;
      if (e.type == PlanEvent::Type::kGrasp) rank = holders[e.object] > 0 ? 0 : 2;
      if (e.type == PlanEvent::Type::kRelease) rank = 1;
      ranked.emplace_back(rank, by_time[k]);
    }
    std::stable_sort(ranked.begin(), ranked.end(), [](auto& a, auto& b) { return a.first < b.first; });
    for (const auto& [rank, e] : ranked) {
      order_.push_back(e);
      const PlanEvent& ev = plan_.events[at(e)];
      if (ev.type == PlanEvent::Type::kGrasp) ++holders[ev.object];
      if (ev.type == PlanEvent::Type::kRelease) --holders[ev.object];
    }
    i = j;
  }
  position_of_event_.assign(order_.size(), -1);
  for (std::size_t p = 0; p < order_.size(); ++p) position_of_event_[at(order_[p])] = static_cast<int>(p);
}

void Builder::replayHolders() {
  const int objects = static_cast<int>(scene_.objects.size());
  std::vector<std::vector<std::pair<int, Pose>>> holders(at(objects));  // (arm, X_TO)
  std::vector<int> open(at(objects), -1);                                // rest in rests_
  for (int o = 0; o < objects; ++o) {
    open[at(o)] = static_cast<int>(rests_.size());
    rests_.push_back({o, scene_.objects[at(o)].X_WO_start, -1, -1});
  }
  for (int p = 0; p < static_cast<int>(order_.size()); ++p) {
    const PlanEvent& e = plan_.events[at(order_[at(p)])];
    if (e.type == PlanEvent::Type::kInspect) continue;
    const int o = scene_.objectIndex(e.object);
    DASH_THROW_UNLESS(o >= 0, "event of unknown object \"" + e.object + "\": validate the plan first");
    const int arm = eventArm(p);
    auto& hs = holders[at(o)];
    if (e.type == PlanEvent::Type::kGrasp) {
      if (!hs.empty()) handovers_.emplace_back(p, hs.front().first);
      if (open[at(o)] >= 0) rests_[at(open[at(o)])].to = p;
      open[at(o)] = -1;
      hs.emplace_back(arm, e.X_TO);
    } else {
      auto it = std::find_if(hs.begin(), hs.end(), [&](const auto& h) { return h.first == arm; });
      DASH_THROW_UNLESS(it != hs.end(), e.robot + " releases " + e.object + " it does not hold: validate the plan first");
      const Pose X_WO = tcp(arm, e.t) * it->second;
      hs.erase(it);
      if (!hs.empty()) {
        handovers_.emplace_back(p, hs.front().first);
      } else {
        open[at(o)] = static_cast<int>(rests_.size());
        rests_.push_back({o, X_WO, p, -1});
      }
    }
  }
}


/// Handovers order both arms' pasts before both arms' futures (addHandoverEdges), and chains of them
/// order more: a vector clock per arm, advanced at each handover instant from the clocks as they
/// were before it (handovers at one instant are not chained: their order there is the event order).
void Builder::syncHandovers() {
  const int arms = static_cast<int>(plan_.robots.size());
  constexpr double kNever = -std::numeric_limits<double>::infinity();
  std::vector<std::vector<double>> clock(at(arms), std::vector<double>(at(arms), kNever));
  sync_.assign(at(arms), {});
  std::vector<std::tuple<double, int, int>> meets;  // (t, arm, other)
  for (const auto& [position, other] : handovers_) meets.emplace_back(eventTime(position), eventArm(position), other);
  std::sort(meets.begin(), meets.end());
  for (std::size_t i = 0; i < meets.size();) {
    std::size_t j = i;
    const double t = std::get<0>(meets[i]);
    std::vector<std::vector<double>> next = clock;
    std::set<int> involved;
    for (; j < meets.size() && std::get<0>(meets[j]) - t <= kTimeTolerance; ++j) {
      const auto [tj, arm, other] = meets[j];
      for (const auto& [x, y] : {std::make_pair(arm, other), std::make_pair(other, arm)}) {
        for (int c = 0; c < arms; ++c) next[at(y)][at(c)] = std::max(next[at(y)][at(c)], clock[at(x)][at(c)]);
        next[at(y)][at(x)] = std::max(next[at(y)][at(x)], tj);
        involved.insert(y);
      }
    }
    clock = std::move(next);
    for (int y : involved) sync_[at(y)].push_back({t, clock[at(y)]});
    i = j;
  }
}

void Builder::makePieces() {
  pieces_.clear();
  slots_.assign(plan_.robots.size(), {});
  slot_of_piece_.clear();
  slot_of_event_.assign(order_.size(), -1);
  for (int arm = 0; arm < static_cast<int>(plan_.robots.size()); ++arm) {
    const RobotTrajectory& traj = plan_.robots[at(arm)];
    std::vector<int> own;  // event positions of this arm, in order
    for (int p = 0; p < static_cast<int>(order_.size()); ++p) {
      if (eventArm(p) == arm) own.push_back(p);
    }
    std::vector<double> cuts;
    for (double t : cuts_[at(arm)]) {
      if (cuts.empty() || t - cuts.back() > kTimeTolerance) cuts.push_back(t);
      else if (t == *cuts_[at(arm)].rbegin()) cuts.back() = t;  // keep the end exactly
    }
    std::size_t next_event = 0;
    int held = -1;
    Pose X_TO = Pose::Identity();
    int last = -1;
    auto addEvents = [&](double until) {
      while (next_event < own.size() && eventTime(own[next_event]) <= until + kTimeTolerance) {
        const int p = own[next_event++];
        const PlanEvent& e = plan_.events[at(order_[at(p)])];
        if (e.type == PlanEvent::Type::kGrasp) {
          held = scene_.objectIndex(e.object);
          X_TO = e.X_TO;
          last = held;
        } else if (e.type == PlanEvent::Type::kRelease) {
          held = -1;
        }
        slot_of_event_[at(p)] = static_cast<int>(slots_[at(arm)].size());
        slots_[at(arm)].push_back({-1, p});
      }
    };
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      addEvents(cuts[k]);
      Piece piece;
      piece.robot = scene_robot_[at(arm)];
      piece.arm = arm;
      piece.t0 = cuts[k];
      piece.t1 = cuts[k + 1];
      piece.q0 = traj.positionAt(piece.t0);
      piece.q1 = traj.positionAt(piece.t1);
      piece.held = held;
      piece.X_TO = X_TO;
      piece.adjacent_last = last;
      for (std::size_t n = next_event; n < own.size(); ++n) {
        const PlanEvent& e = plan_.events[at(order_[at(own[n])])];
        if (e.type != PlanEvent::Type::kGrasp) continue;
        piece.adjacent_next = scene_.objectIndex(e.object);
        break;
      }
      prepareCached(piece);
      slot_of_piece_.emplace_back(arm, static_cast<int>(slots_[at(arm)].size()));
      slots_[at(arm)].push_back({static_cast<int>(pieces_.size()), -1});
      pieces_.push_back(std::move(piece));
    }
    addEvents(std::numeric_limits<double>::infinity());
  }
  max_pieces_ = std::max(max_pieces_, static_cast<int>(pieces_.size()));
}

void Builder::prepareCached(Piece& piece) {
  const auto key = std::make_tuple(piece.arm, piece.t0, piece.t1);
  if (auto it = prepared_.find(key); it != prepared_.end()) {
    piece.moves = it->second.moves;
    piece.rate = it->second.rate;
    piece.box = it->second.box;
    piece.parts = it->second.parts;
    return;
  }
  sweeps_.prepare(piece);
  prepared_.emplace(key, piece);
}

void Builder::addEdge(int from_arm, int from_slot, int to_arm, int to_slot, Edge::Why why) {
  if (from_arm == to_arm || from_slot < 0 || to_slot < 0) return;
  if (from_slot >= static_cast<int>(slots_[at(from_arm)].size()) || to_slot >= static_cast<int>(slots_[at(to_arm)].size())) return;
  edges_.insert({from_arm, from_slot, to_arm, to_slot, static_cast<int>(why)});
}










Graph Builder::mergeAndReduce() const {
  Graph g;
  g.clearance = options_.clearance;
  g.forced = forced_;
  const int arms = static_cast<int>(plan_.robots.size());
  std::set<std::pair<int, int>> outgoing, incoming;
  for (const auto& [fa, fs, ta, ts, why] : edges_) {
    outgoing.emplace(fa, fs);
    incoming.emplace(ta, ts);
  }
  std::vector<std::vector<int>> node_of_slot(at(arms));
  for (int arm = 0; arm < arms; ++arm) {
    g.robots.push_back(plan_.robots[at(arm)].robot);
    const auto& slots = slots_[at(arm)];
    for (int s = 0; s < static_cast<int>(slots.size()); ++s) {
      const Slot& slot = slots[at(s)];
      const bool joins = s > 0 && slot.piece >= 0 && slots[at(s - 1)].piece >= 0 && !outgoing.count({arm, s - 1}) &&
                         !incoming.count({arm, s});
      if (slot.event >= 0) {
        const double t = eventTime(slot.event);
        g.nodes.push_back({Node::Kind::kEvent, arm, t, t, order_[at(slot.event)], false});
      } else if (joins) {
        Node& last = g.nodes.back();
        last.t1 = pieces_[at(slot.piece)].t1;
        last.moves = last.moves || pieces_[at(slot.piece)].moves;
      } else {
        const Piece& p = pieces_[at(slot.piece)];
        g.nodes.push_back({Node::Kind::kMotion, arm, p.t0, p.t1, -1, p.moves});
      }
      node_of_slot[at(arm)].push_back(static_cast<int>(g.nodes.size()) - 1);
    }
  }
  // Lifted, then only the latest source per (target, source arm) and the earliest target per
  // (source, target arm): an arm runs its nodes in order, so the others are implied.
  std::map<std::pair<int, int>, std::pair<int, int>> latest;  // (to, from arm) -> (from, why)
  for (const auto& [fa, fs, ta, ts, why] : edges_) {
    const int from = node_of_slot[at(fa)][at(fs)];
    const int to = node_of_slot[at(ta)][at(ts)];
    auto [it, fresh] = latest.try_emplace({to, fa}, from, why);
    if (!fresh && (from > it->second.first || (from == it->second.first && why < it->second.second))) it->second = {from, why};
  }
  std::map<std::pair<int, int>, std::pair<int, int>> earliest;  // (from, to arm) -> (to, why)
  for (const auto& [key, value] : latest) {
    const int to = key.first;
    const int ta = g.nodes[at(to)].robot;
    auto [it, fresh] = earliest.try_emplace({value.first, ta}, to, value.second);
    if (!fresh && (to < it->second.first || (to == it->second.first && value.second < it->second.second))) {
      it->second = {to, value.second};
    }
  }
  for (const auto& [key, value] : earliest) g.edges.push_back({key.first, value.first, static_cast<Edge::Why>(value.second)});
  std::sort(g.edges.begin(), g.edges.end(), [](const Edge& a, const Edge& b) {
    return std::tie(a.to, a.from) < std::tie(b.to, b.from);
  });
  return g;
}

/// Each arm is cut at its points, at its events and at the events of the arms that can come near it
/// (their reach, the boxes of all their pieces, within the clearance): only those can bound an edge.
void Builder::initialCuts() {
  const double end = std::max(plan_.lastTime(), plan_.makespan);
  const int arms = static_cast<int>(plan_.robots.size());
  cuts_.assign(at(arms), {});
  for (int arm = 0; arm < arms; ++arm) {
    auto& cuts = cuts_[at(arm)];
    cuts.insert(0.0);
    cuts.insert(end);
    for (const TrajectoryPoint& p : plan_.robots[at(arm)].points) cuts.insert(std::min(p.t, end));
  }
  for (const PlanEvent& e : plan_.events) cuts_[at(arm_of_robot_.at(e.robot))].insert(std::min(e.t, end));
  makePieces();
  std::vector<Aabb> reach(at(arms));
  for (const Piece& p : pieces_) reach[at(p.arm)].extend(p.box);
  for (int arm = 0; arm < arms; ++arm) {
    for (const PlanEvent& e : plan_.events) {
      const int other = arm_of_robot_.at(e.robot);
      if (other != arm && reach[at(arm)].exteriorDistance(reach[at(other)]) <= options_.clearance) {
        cuts_[at(arm)].insert(std::min(e.t, end));
      }
    }
  }
}

Graph Builder::build(BuildStats* stats) {
  for (int arm = 0; arm < static_cast<int>(plan_.robots.size()); ++arm) {
    const std::string& id = plan_.robots[at(arm)].robot;
    const int r = scene_.robotIndex(id);
    DASH_THROW_UNLESS(r >= 0, "the plan's robot \"" + id + "\" is not in the scene");
    DASH_THROW_UNLESS(!plan_.robots[at(arm)].points.empty(), "robot \"" + id + "\" has no points");
    arm_of_robot_[id] = arm;
    scene_robot_.push_back(r);
  }
  for (const PlanEvent& e : plan_.events) {
    DASH_THROW_UNLESS(arm_of_robot_.count(e.robot), "an event names robot \"" + e.robot + "\", which the plan lacks");
  }
  sortEvents();
  replayHolders();
  syncHandovers();
  initialCuts();
  for (;;) {
    makePieces();
    ++rounds_;
    last_round_ = rounds_ >= kMaxRounds;
    const bool again = findConflicts();
    if (options_.progress) {
      options_.progress("round " + std::to_string(rounds_) + ": " + std::to_string(pieces_.size()) + " pieces, " +
                        std::to_string(meet_cache_.size()) + " pairs tested (" + std::to_string(ordered_tests_) +
                        " run one after the other, " + std::to_string(ordered_meet_) + " of them meet), " +
                        std::to_string(sweeps_.evaluations()) +
                        " distance evaluations, " + std::to_string(pending_.size()) + " cuts asked");
    }
    if (!again) break;
  }
  addObjectEdges();
  addHandoverEdges();
  Graph g = mergeAndReduce();
  if (stats != nullptr) {
    stats->pieces = max_pieces_;
    stats->evaluations = static_cast<int>(sweeps_.evaluations());
    stats->rounds = rounds_;
  }
  return g;
}

}  // namespace detail

Graph buildGraph(const Scene& scene, const Plan& plan, const BuildOptions& options, BuildStats* stats) {
  DASH_THROW_UNLESS(options.clearance >= 0.0 && options.clearance <= 0.1, "clearance must be within 0 .. 0.1 m");
  DASH_THROW_UNLESS(options.resolution > 0.0 && options.resolution <= 0.01, "resolution must be within 0 .. 0.01 m");
  DASH_THROW_UNLESS(options.contact_floor > 0.0 && options.contact_floor <= options.resolution,
                    "contact_floor must be within 0 .. resolution");
  DASH_THROW_UNLESS(options.contact_tolerance >= 0.0 && options.contact_tolerance <= 1e-4,
                    "contact_tolerance must be within 0 .. 1e-4 m");
  DASH_THROW_UNLESS(options.min_cut > 0.0 && options.max_evaluations > 0 && options.max_ordered_evaluations > 0,
                    "min_cut, max_evaluations and max_ordered_evaluations must be positive");
  detail::Builder builder(scene, plan, options);
  return builder.build(stats);
}

}  // namespace dash::tpg
