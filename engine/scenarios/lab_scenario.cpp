// Lab (Lazy-DaSH, Sec. "Lab"): two three-axis gantries over one bench inspect specimens in sealed
// containers. Each container takes several stages: a gantry lifts its lid and puts it down in the
// sanitisation zone, a gantry inspects the open container, a gantry puts the lid back. Both gantries
// can lift lids and inspect, and every container and the whole zone lie where both reach, so the
// work splits between them and several lids are out at once. Lids may rest only in the zone (the
// scene's one resting surface a lid fits on; the containers stand on pads exactly their size), and
// the zone has room for fewer lids than there are containers (min(3, containers - 1)): placements in
// it conflict (vertex-vertex conflicts, paper). Feasible by construction: either gantry alone can do
// every container in turn with one lid position. Layout: engine/scenarios/README.md.
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
constexpr double kGantry1OffsetX = 0.3;  ///< gantry_1 covers x in [0.3, 1.3], gantry_0 x in [0, 1]
constexpr double kContainerSize = 0.08;
constexpr double kContainerHeight = 0.12;  ///< lid top at 0.13: inside the TCP's band
constexpr double kLidThickness = 0.01;
constexpr double kInspectHeight = 0.04;  ///< TCP above the container's rim while inspecting
constexpr double kPadInset = 0.0005;     ///< a container's pad is this much smaller on each side: no lid fits
// Container spots: a 6 x 4 grid (12 cm pitch) in the band both gantries reach, x in [0.36, 0.96]. Two
// bridges (8 cm) with their carriages (10 cm) fit over neighbouring columns.
constexpr int kColumns = 6, kRows = 4;
constexpr double kSpotX0 = 0.36, kSpotY0 = 0.20, kPitch = 0.12;
// Sanitisation zone: a strip in front of the containers (y 0.02..0.12), one lid deep, with room for
// `lids` lids side by side: 0.08 lids + 0.06 m long (floor(length / 0.08) = lids).
constexpr int kZoneLidsMax = 3;
constexpr double kZoneWidth = 0.10, kZoneY = 0.07, kZoneHeight = 0.12, kZoneSpare = 0.06;
constexpr double kSharedXMin = 0.34, kSharedXMax = 0.98;  ///< the zone stays inside both reaches
constexpr double kBenchThickness = 0.05;

}  // namespace

int labZoneLids(int containers) { return std::max(1, std::min(kZoneLidsMax, containers - 1)); }

GeneratedLayout generateLab(const FamilyInput& in) {
  const int containers = in.params.get("containers");
  SceneBuilder b(in.library, sceneName(in, "c" + std::to_string(containers)), generatorRecord(in));
  b.addRobot("gantry_0", "gantry3", Vec3(0.0, 0.0, 0.0), 0.0, {0.0, 0.3, 0.0}, {"grasp", "inspect"});
  b.addRobot("gantry_1", "gantry3", Vec3(kGantry1OffsetX, 0.0, 0.0), 0.0, {1.0, 0.3, 0.0}, {"grasp", "inspect"});
  const Vec2 bench_min(-0.15, -0.12), bench_max(kGantry1OffsetX + 1.15, 0.72);
  const Vec2 bench_centre = 0.5 * (bench_min + bench_max);
  const Vec2 bench_size = bench_max - bench_min;
  b.addBox("bench", Vec3(bench_size.x(), bench_size.y(), kBenchThickness),
           Vec3(bench_centre.x(), bench_centre.y(), -0.5 * kBenchThickness));

  // Millimetre steps keep the numbers short.
  auto mm = [](double x) { return std::round(x * 1000.0) / 1000.0; };
  const double zone_length = kContainerSize * labZoneLids(containers) + kZoneSpare;
  const Vec2 zone(mm(portable::uniform(in.rng, kSharedXMin + 0.5 * zone_length, kSharedXMax - 0.5 * zone_length)),
                  kZoneY);
  b.addBox("sanitiser", Vec3(zone_length, kZoneWidth, kZoneHeight), Vec3(zone.x(), zone.y(), 0.5 * kZoneHeight));
  b.addRectSurface("sanitisation_zone", kZoneHeight, zone, Vec2(zone_length, kZoneWidth));

  std::vector<Vec2> spots;
  for (int i = 0; i < kColumns; ++i)
    for (int j = 0; j < kRows; ++j) spots.emplace_back(kSpotX0 + kPitch * i, kSpotY0 + kPitch * j);
  portable::shuffle(spots, in.rng);
  spots.resize(at(containers));
  std::sort(spots.begin(), spots.end(),
            [](const Vec2& a, const Vec2& c) { return a.x() < c.x() || (a.x() == c.x() && a.y() < c.y()); });
  for (int i = 0; i < containers; ++i) {
    const Vec2& s = spots[at(i)];
    const std::string n = std::to_string(i);
    // The container stands on its own pad, a hair smaller than its footprint, so nothing else fits there.
    const double pad = kContainerSize - 2.0 * kPadInset;
    b.addRectSurface("container_" + n + "_pad", 0.0, s, Vec2(pad, pad));
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
