#pragma once
// Straight-line TCP motions as joint-space paths. A plan joins its points by straight joint-space
// segments (formats.md), and a joint-space segment between two configurations whose TCPs lie on a
// line sags off that line: over a 35 cm cubby approach by millimetres, enough to press a held item
// into the pedestal it is put on (issue 36, item 9). The approaches to and retreats from a transition
// configuration (grasp, placement, handover, inspection) of both planners are therefore Cartesian
// paths: waypoints on the TCP's straight line (inverse kinematics on the branch that joins the two
// ends), close enough that every point within `reach` of the TCP strays less than `deviation` from
// where the straight line puts it between two consecutive waypoints.
#include <optional>
#include <vector>

#include "engine/robots/robot_model.h"

namespace dash {

/// m: the most any point within the reach of the TCP may stray from the straight line between two
/// waypoints (0.02 mm: a fifth of the tolerance at a held object's lowest face, kHeldBottomTolerance).
inline constexpr double kCartesianDeviation = 2e-5;

struct CartesianPathOptions {
  double deviation = kCartesianDeviation;
  /// m: points this far from the TCP (a held object's corners) are kept within `deviation` too, so a
  /// turn of the tool counts as reach times its angle.
  double reach = 0.15;
  int max_points = 1024;  ///< a line that needs more waypoints is refused
  /// m per m: the deviation allowed grows by this much per metre of the line from q_from, where the
  /// line is far from what it comes down onto (0: the same everywhere).
  double growth = 0.0;
};

/// A back-off's line (backOffLine) may stray 0.02 mm plus this per metre from the transition
/// configuration: a fifth of the slope of the flattest one (a 35 cm cubby back-off rising 15 mm), so
/// that between two waypoints the held object stays well above what the line keeps it above there.
inline constexpr double kBackOffGrowth = 0.2 * 0.015 / 0.35;

/// The path q_from -> q_to (both included, exactly) whose TCP follows the straight line between
/// their TCP poses (position linearly, orientation by slerp): between two consecutive waypoints the
/// joint-space segment keeps every point within options.reach of the TCP within options.deviation
/// (plus options.growth times the distance of the segment's nearer end from q_from's TCP) of the
/// line (measured at its quarters and middle). nullopt when
/// the two ends are not on one IK branch along the line (a waypoint has no IK solution near the
/// joint-space segment, as at a wrist flip or out of reach) or it needs more than max_points.
std::optional<std::vector<JointVector>> cartesianPath(const RobotModel& model, const Pose& X_WB,
                                                      const JointVector& q_from, const JointVector& q_to,
                                                      const CartesianPathOptions& options = {});

/// A back-off's straight line from the transition configuration q to q_end (q first): cartesianPath
/// with the deviation growing by kBackOffGrowth away from q. What both planners check.
std::optional<std::vector<JointVector>> backOffLine(const RobotModel& model, const Pose& X_WB, const JointVector& q,
                                                    const JointVector& q_end);
/// The path of a back-off from q to q_end (q first), as both planners check it and the plan moves
/// along it: backOffLine ({q} when the ends are equal), or {q, q_end} when there is none (ends that no
/// back-off check made).
std::vector<JointVector> backOffPath(const RobotModel& model, const Pose& X_WB, const JointVector& q,
                                     const JointVector& q_end);

/// Whether a back-off from the TCP pose X_WT runs sideways: along its approach axis (its z), or along
/// the world direction direction_W when given, within about 45 degrees of horizontal.
bool backsOffSideways(const Pose& X_WT, const std::optional<Vec3>& direction_W = {});
/// Where a back-off from X_WT by `distance` goes (the same axis); a sideways one also rises by `lift`,
/// so that an object resting on a board or pedestal comes down onto it (and lifts off it) on a slope
/// rather than sliding along it. Both planners' approaches and retreats (issue 36, item 9).
Pose backOffPose(const Pose& X_WT, double distance, double lift, const std::optional<Vec3>& direction_W = {});

/// Sum of the joint-space lengths (Euclidean) of the path's segments.
double pathLength(const std::vector<JointVector>& path);

}  // namespace dash
