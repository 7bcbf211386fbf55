// Lab (Lazy-DaSH, Sec. "Lab"): two three-axis gantries over one bench. Sealed specimen containers
// stand where both gantries reach; a small sanitisation platform stands where only gantry_0 reaches.
// gantry_0 can grasp (lids), gantry_1 can inspect, so every container needs both: gantry_0 lifts the
// lid onto the sanitisation zone, gantry_1 inspects the open container, gantry_0 puts the lid back.
// The zone holds two lids at a time, so lid placements can conflict. Layout: engine/scenarios/README.md.
#include <algorithm>
#include <cmath>

#include "engine/scenarios/layout_tools.h"
#include "engine/scenarios/portable_random.h"
#include "engine/scenarios/scenario_families.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/scenarios/scene_builder.h"

namespace dash {

namespace {

using layout::Vec2;

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

// gantry3: x in [0, 1], y in [0, 0.6] from its base; TCP at base z + 0.60 - 0.20 - z, z in [0, 0.3],
// so the TCP works between 0.10 and 0.40 m above the base. Both bases stand on the bench top.
constexpr double kGantry1OffsetX = 0.5;  ///< gantry_1 covers x in [0.5, 1.5], gantry_0 x in [0, 1]
constexpr double kContainerSize = 0.08;
constexpr double kContainerHeight = 0.12;  ///< lid top at 0.13: inside the TCP's band
constexpr double kLidThickness = 0.01;
constexpr double kInspectHeight = 0.04;  ///< TCP above the container's rim while inspecting
// Container spots: a grid in the shared band x in [0.56, 0.92], leaving gantry_1 room beyond x + 0.1
// while gantry_0 holds a lid (bridges and carriages are 0.08 and 0.1 wide).
constexpr double kSpotX[] = {0.56, 0.68, 0.80, 0.92};
constexpr double kSpotY[] = {0.12, 0.30, 0.48};
// Sanitisation platform: 0.2 x 0.1 holds two 8 cm lids side by side.
constexpr double kZoneLength = 0.20;
constexpr double kZoneWidth = 0.10;
constexpr double kZoneHeight = 0.12;
constexpr double kZoneXMin = 0.12, kZoneXMax = 0.32;  ///< centre range: only gantry_0 reaches
constexpr double kZoneYMin = 0.10, kZoneYMax = 0.50;
constexpr double kBenchThickness = 0.05;

}  // namespace

GeneratedLayout generateLab(const FamilyInput& in) {
  const int containers = in.params.get("containers");
  SceneBuilder b(in.library, sceneName(in, "c" + std::to_string(containers)), generatorRecord(in));
  b.addRobot("gantry_0", "gantry3", Vec3(0.0, 0.0, 0.0), 0.0, {0.0, 0.3, 0.0}, {"grasp"});
  b.addRobot("gantry_1", "gantry3", Vec3(kGantry1OffsetX, 0.0, 0.0), 0.0, {1.0, 0.3, 0.0}, {"inspect"});
  const Vec2 bench_min(-0.15, -0.12), bench_max(kGantry1OffsetX + 1.15, 0.72);
  const Vec2 bench_centre = 0.5 * (bench_min + bench_max);
  const Vec2 bench_size = bench_max - bench_min;
  b.addBox("bench", Vec3(bench_size.x(), bench_size.y(), kBenchThickness),
           Vec3(bench_centre.x(), bench_centre.y(), -0.5 * kBenchThickness));
  b.addRectSurface("bench_top", 0.0, bench_centre, bench_size);

  // Millimetre steps keep the numbers short.
  auto mm = [](double x) { return std::round(x * 1000.0) / 1000.0; };
  const Vec2 zone(mm(portable::uniform(in.rng, kZoneXMin, kZoneXMax)),
                  mm(portable::uniform(in.rng, kZoneYMin, kZoneYMax)));
  b.addBox("sanitiser", Vec3(kZoneLength, kZoneWidth, kZoneHeight), Vec3(zone.x(), zone.y(), 0.5 * kZoneHeight));
  b.addRectSurface("sanitisation_zone", kZoneHeight, zone, Vec2(kZoneLength, kZoneWidth));

  std::vector<Vec2> spots;
  for (const double x : kSpotX) {
    for (const double y : kSpotY) spots.emplace_back(x, y);
  }
  portable::shuffle(spots, in.rng);
  spots.resize(at(containers));
  std::sort(spots.begin(), spots.end(),
            [](const Vec2& a, const Vec2& c) { return a.x() < c.x() || (a.x() == c.x() && a.y() < c.y()); });
  for (int i = 0; i < containers; ++i) {
    const Vec2& s = spots[at(i)];
    const std::string n = std::to_string(i);
    b.addObject("container_" + n, Vec3(kContainerSize, kContainerSize, kContainerHeight),
                yawPose(Vec3(s.x(), s.y(), 0.5 * kContainerHeight), 0.0), std::nullopt, true);
    const Pose lid = yawPose(Vec3(s.x(), s.y(), kContainerHeight + 0.5 * kLidThickness), 0.0);
    b.addObject("lid_" + n, Vec3(kContainerSize, kContainerSize, kLidThickness), lid, lid);
  }
  for (int i = 0; i < containers; ++i) {
    const Vec2& s = spots[at(i)];
    // Tool pointing down: a half turn about x (gantry3.json's TCP frame).
    const Pose X_WT =
        makePose(Vec3(roundLength(s.x()), roundLength(s.y()), roundLength(kContainerHeight + kInspectHeight)),
                 Quat(0.0, 1.0, 0.0, 0.0));
    b.addInspectTask("container_" + std::to_string(i), X_WT, "lid_" + std::to_string(i), "inspect");
  }
  GeneratedLayout out{.scene = b.build(), .validation = {}};
  out.validation.handover_chains = false;  // lids come back to where they were; no handovers
  return out;
}

}  // namespace dash
