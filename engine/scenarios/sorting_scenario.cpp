// Sorting and Wall (Lazy-DaSH, Sec. "Sorting" and "Wall"): UR5e arms on a ring around a workstation
// table, each with a start cluster and a goal box behind it, out of every other arm's reach. Objects
// go from robot s's cluster to the box of the robot across the ring ("cross sorting"), so they travel
// round the ring through mid-air handovers between neighbours. Wall adds thin tall radial panels that
// cut the handover between some neighbours; objects then go the long way round within their arc.
// Layout and rules: engine/scenarios/README.md.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/scenarios/layout_tools.h"
#include "engine/scenarios/portable_random.h"
#include "engine/scenarios/scenario_families.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/scenarios/scene_builder.h"

namespace dash {

namespace {

using layout::Vec2;

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

// Ring geometry. A UR5e holding a cube with a side grasp reaches about 1.07 m from its base axis, so
// two arms can meet mid-air up to about 2.1 m apart. Neighbours stand kNeighbourDistance apart
// (a comfortable handover: each arm reaches 0.6 m) and the ring is widened until robots two apart are
// kSecondNeighbourDistance apart, beyond any handover: objects must pass every robot in between.
constexpr double kNeighbourDistance = 1.2;
constexpr double kSmallRingNeighbourDistance = 1.0;  ///< 2 or 3 robots: everyone is a neighbour
constexpr double kSecondNeighbourDistance = 2.25;
// Slots: at least this far from every other robot's base (a top grasp on the table reaches 0.91 m).
constexpr double kOtherRobotClearance = 1.0;
constexpr double kSlotPitches[] = {0.08, 0.07, 0.065};  ///< tried in order; >= 0.065 keeps aligned top grasps free
constexpr double kBoxMargin = 0.035;                    ///< box polygon around its slots
constexpr int kMinBoxSlots = 4;                         ///< a box has room for at least this many
constexpr double kTableMargin = 0.3;                    ///< table edge beyond the farthest slot
constexpr double kTableThickness = 0.05;
// Walls: thin, taller than any arm can reach over, and long enough radially that no arm reaches
// round their ends.
constexpr double kWallThickness = 0.01;
constexpr double kWallHeight = 1.5;
constexpr double kWallHalfLength = 1.35;
constexpr double kWallClearance = 0.12;  ///< slots keep this far from walls

struct Ring {
  int robots = 0;
  double radius = 0.0;
  std::vector<layout::WorkFrame> frames;  ///< per robot, x pointing away from the centre
};

Ring makeRing(int robots) {
  Ring ring;
  ring.robots = robots;
  const double pi = std::numbers::pi;
  double neighbour = robots <= 3 ? kSmallRingNeighbourDistance : kNeighbourDistance;
  if (robots >= 4) neighbour = std::max(neighbour, kSecondNeighbourDistance / (2.0 * std::cos(pi / robots)));
  ring.radius = neighbour / (2.0 * std::sin(pi / robots));
  for (int i = 0; i < robots; ++i) {
    const double angle = 2.0 * pi * i / robots;
    ring.frames.push_back({.origin = ring.radius * Vec2(std::cos(angle), std::sin(angle)), .yaw = angle});
  }
  return ring;
}

struct Wall {
  int gap = -1;  ///< between robot gap and gap + 1
  Vec2 a, b;     ///< inner and outer end of its middle line
};

Wall makeWall(const Ring& ring, int gap) {
  const double angle = 2.0 * std::numbers::pi * (gap + 0.5) / ring.robots;
  const Vec2 dir(std::cos(angle), std::sin(angle));
  const double inner = std::max(0.0, ring.radius - kWallHalfLength);
  return {.gap = gap, .a = inner * dir, .b = (ring.radius + kWallHalfLength) * dir};
}

/// Goal robot of objects starting at robot s. Without walls: the robot across the ring (cross
/// sorting). With walls the ring falls into arcs (the robots between two walls, counter-clockwise);
/// an arc is mirrored end to end: the robot at position p of an arc of m robots sends to position
/// m - 1 - p, so the two robots beside a wall send to each other the long way round. The middle robot
/// of an odd arc sends to its counter-clockwise neighbour. (The farthest robot of the arc would pile
/// every object of an arc onto the two boxes at its ends.) A robot walled in on both sides is an arc
/// of one: it sorts its objects into its own box.
int goalRobot(int s, int robots, const std::vector<int>& wall_gaps) {
  if (wall_gaps.empty()) return (s + robots / 2) % robots;
  auto blocked = [&](int gap) { return std::find(wall_gaps.begin(), wall_gaps.end(), gap) != wall_gaps.end(); };
  int ccw = 0;  // steps counter-clockwise before a wall
  while (ccw < robots - 1 && !blocked((s + ccw) % robots)) ++ccw;
  int cw = 0;  // steps clockwise before a wall
  while (cw < robots - 1 && !blocked(((s - cw - 1) % robots + robots) % robots)) ++cw;
  if (ccw == 0 && cw == 0) return s;
  // s sits at position cw of an arc of cw + ccw + 1 robots; its mirror is ccw - cw steps away.
  int steps = ccw - cw;
  if (steps == 0) steps = 1;
  return ((s + steps) % robots + robots) % robots;
}

struct RobotArea {
  std::vector<Vec2> cluster;  ///< start slots of the objects starting here, in object order
  std::vector<Vec2> box;      ///< the box's slots; the first ones hold goals
};

/// Which objects start and end where: object k starts at robot k mod robots and goes to its goalRobot.
struct Assignment {
  std::vector<int> start_robot, goal_robot;  ///< per object
  std::vector<int> starting, arriving;       ///< per robot: objects starting, arriving there
};

Assignment assignObjects(int robots, int objects, const std::vector<int>& wall_gaps) {
  Assignment as{.start_robot = std::vector<int>(at(objects)),
                .goal_robot = std::vector<int>(at(objects)),
                .starting = std::vector<int>(at(robots), 0),
                .arriving = std::vector<int>(at(robots), 0)};
  for (int k = 0; k < objects; ++k) {
    as.start_robot[at(k)] = k % robots;
    as.goal_robot[at(k)] = goalRobot(k % robots, robots, wall_gaps);
    ++as.starting[at(as.start_robot[at(k)])];
    ++as.arriving[at(as.goal_robot[at(k)])];
  }
  return as;
}

/// Slots: the largest pitch at which every robot's cluster and box fit, each in a random order.
std::vector<RobotArea> robotAreas(const FamilyInput& in, const Ring& ring, const std::vector<Wall>& walls,
                                  double table_half, const Assignment& as) {
  const int robots = ring.robots;
  auto keep = [&](int self) {
    return [&, self](const Vec2& p) {
      for (int r = 0; r < robots; ++r) {
        if (r != self && (p - ring.frames[at(r)].origin).norm() < kOtherRobotClearance) return false;
      }
      for (const Wall& w : walls) {
        if (layout::segmentDistance(p, w.a, w.b) < kWallClearance) return false;
      }
      return std::abs(p.x()) < table_half - 0.1 && std::abs(p.y()) < table_half - 0.1;
    };
  };
  std::vector<RobotArea> areas;
  for (const double pitch : kSlotPitches) {
    areas.clear();
    bool fits = true;
    for (int r = 0; r < robots && fits; ++r) {
      const auto left = layout::gridSlots(ring.frames[at(r)], {}, layout::Side::kLeft, pitch, keep(r));
      const auto right = layout::gridSlots(ring.frames[at(r)], {}, layout::Side::kRight, pitch, keep(r));
      const int box_slots = std::max(as.arriving[at(r)], kMinBoxSlots);
      fits = static_cast<int>(left.size()) >= as.starting[at(r)] && static_cast<int>(right.size()) >= box_slots;
      if (fits)
        areas.push_back({.cluster = layout::compactCluster(left, as.starting[at(r)], in.rng),
                         .box = layout::compactCluster(right, box_slots, in.rng)});
    }
    if (fits) break;
    areas.clear();
  }
  if (areas.empty()) {
    throw ScenarioError(in.family + ": " + std::to_string(static_cast<int>(as.start_robot.size())) +
                        " objects do not fit with " + std::to_string(robots) +
                        " robots (a robot's cluster or box has no room for its " +
                        "share; use fewer objects or more robots)");
  }
  // Cubes take the slots of their cluster and box in a random order.
  for (RobotArea& a : areas) {
    portable::shuffle(a.cluster, in.rng);
    std::vector<Vec2> goals(a.box.begin(), a.box.end());
    portable::shuffle(goals, in.rng);
    a.box = goals;
  }
  return areas;
}

GeneratedLayout generateRing(const FamilyInput& in, int robots, int objects, const std::vector<int>& wall_gaps,
                             const std::string& short_params) {
  const Ring ring = makeRing(robots);
  std::vector<Wall> walls;
  for (const int g : wall_gaps) walls.push_back(makeWall(ring, g));
  const Assignment as = assignObjects(robots, objects, wall_gaps);
  const double table_half =
      ring.radius + std::max(layout::AreaSpec{}.max_reach + kTableMargin, walls.empty() ? 0.0 : kWallHalfLength + 0.05);
  const std::vector<RobotArea> areas = robotAreas(in, ring, walls, table_half, as);

  SceneBuilder b(in.library, sceneName(in, short_params), generatorRecord(in));
  for (int r = 0; r < robots; ++r) {
    const layout::WorkFrame& f = ring.frames[at(r)];
    b.addRobot("ur5e_" + std::to_string(r), layout::kUr5eModel, Vec3(f.origin.x(), f.origin.y(), 0.0), f.ur5eBaseYaw(),
               layout::kUr5eHome, {"grasp"});
  }
  b.addBox("table", Vec3(2.0 * table_half, 2.0 * table_half, kTableThickness), Vec3(0.0, 0.0, -0.5 * kTableThickness));
  for (const Wall& w : walls) {
    const Vec2 c = 0.5 * (w.a + w.b);
    const Vec2 d = w.b - w.a;
    b.addBox("wall_" + std::to_string(w.gap), Vec3(d.norm(), kWallThickness, kWallHeight),
             Vec3(c.x(), c.y(), 0.5 * kWallHeight), std::atan2(d.y(), d.x()));
  }
  b.addRectSurface("table_top", 0.0, Vec2::Zero(), Vec2(2.0 * table_half, 2.0 * table_half));
  for (int r = 0; r < robots; ++r) {
    b.addSurface("box_" + std::to_string(r), 0.0,
                 layout::boundingRectangle(ring.frames[at(r)], areas[at(r)].box, kBoxMargin));
  }
  std::vector<int> next_start(at(robots), 0), next_goal(at(robots), 0);
  const Vec3 cube(layout::kCube, layout::kCube, layout::kCube);
  for (int k = 0; k < objects; ++k) {
    const int s = as.start_robot[at(k)];
    const int g = as.goal_robot[at(k)];
    const Vec2 p = areas[at(s)].cluster[at(next_start[at(s)]++)];
    const Vec2 q = areas[at(g)].box[at(next_goal[at(g)]++)];
    b.addObject("obj_" + std::to_string(k), cube,
                yawPose(Vec3(p.x(), p.y(), 0.5 * layout::kCube), ring.frames[at(s)].yaw),
                yawPose(Vec3(q.x(), q.y(), 0.5 * layout::kCube), ring.frames[at(g)].yaw));
  }
  return {.scene = b.build(), .validation = {}};
}

}  // namespace

GeneratedLayout generateSorting(const FamilyInput& in) {
  const int robots = in.params.get("robots");
  const int objects = in.params.get("objects");
  return generateRing(in, robots, objects, {}, "r" + std::to_string(robots) + "-o" + std::to_string(objects));
}

GeneratedLayout generateWall(const FamilyInput& in) {
  const int robots = in.params.get("robots");
  const int objects = in.params.get("objects");
  const int walls = in.params.get("walls");
  DASH_THROW_UNLESS(walls < robots, "scenario wall: walls=" + std::to_string(walls) + " needs robots >= " +
                                        std::to_string(walls + 1) +
                                        " (at least one pair of neighbours keeps its handover), got robots=" +
                                        std::to_string(robots));
  // Up to robots/2 walls: they fence off W - 1 pairs of neighbours side by side and leave the rest
  // of the ring as one long arc, starting at a random place. The long arc is what makes the lazy
  // assumption fail: once it holds more than robots/2 + 1 robots (robots >= 4 walls - 1), the robots
  // at its ends are closer through the wall than along the arc, yet must send to each other along it.
  // More walls go into the remaining gaps in ring order from the same place, splitting pairs into
  // single robots that sort their own objects (scenes with walls <= robots/2 are unchanged).
  const int offset = static_cast<int>(portable::integer(in.rng, 0, robots - 1));
  std::vector<int> gaps;
  for (int k = 0; k < std::min(walls, robots / 2); ++k) gaps.push_back((offset + 2 * k) % robots);
  for (int j = 0; j < robots && static_cast<int>(gaps.size()) < walls; ++j) {
    const int gap = (offset + j) % robots;
    if (std::find(gaps.begin(), gaps.end(), gap) == gaps.end()) gaps.push_back(gap);
  }
  std::sort(gaps.begin(), gaps.end());
  return generateRing(in, robots, objects, gaps,
                      "r" + std::to_string(robots) + "-o" + std::to_string(objects) + "-w" + std::to_string(walls));
}

}  // namespace dash
