#pragma once
// The PC side of Universal Robots' External Control protocol (as used by UR's client library 2.12+
// and its ROS 2 driver), byte for byte: every integer is a big-endian int32; positions, velocities
// and accelerations are scaled by 1e6 (urad), times by 1e6 (us).
//  - reverse socket (PC port 50001), 8 ints: [read_timeout_ms, p1..p6, mode]; in FORWARD mode p1 is
//    the trajectory action and p2 the number of points. The robot applies read_timeout_ms to its
//    *next* read (0 = block) and stops if nothing arrives in time, so keep-alives (NOOP) must follow
//    within it.
//  - trajectory socket (50003), 21 ints per point: [0-5] positions, [6-11] velocities, [12-17]
//    accelerations, [18] the segment's own duration (time since the previous point), [19] blend
//    radius or spline type, [20] point type; after the last point the robot answers one int
//    (0 success, 1 cancelled, 2 failure). CANCEL always answers 1.
//  - script sender (50002): the robot sends exactly "request_program\n" and gets the program.
//  - script command (50004): no command is needed here (it has none for grippers).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "server/dispatch/arm_trajectory.h"
#include "server/dispatch/dispatch_types.h"

namespace dash::dispatch::ur {

inline constexpr int kReverseMessageInts = 8;
inline constexpr int kPointMessageInts = 21;
inline constexpr double kMultJointState = 1000000.0;
inline constexpr double kMultTime = 1000000.0;
inline constexpr const char* kProgramRequest = "request_program\n";

enum class ControlMode : std::int32_t { kStopped = -2, kIdle = 0, kServoj = 1, kSpeedj = 2, kForward = 3, kSpeedl = 4, kPose = 5, kFreedrive = 6 };
enum class TrajectoryAction : std::int32_t { kCancel = -1, kNoop = 0, kStart = 1, kStreamStart = 2, kStreamEnd = 3 };
enum class PointType : std::int32_t { kMovej = 0, kMovel = 1, kMovep = 2, kMovec = 3, kSpline = 51 };
enum class SplineType : std::int32_t { kCubic = 1, kQuintic = 2 };
enum class TrajectoryResult : std::int32_t { kSuccess = 0, kCancelled = 1, kFailure = 2 };

using ReverseMessage = std::array<std::int32_t, kReverseMessageInts>;
using PointMessage = std::array<std::int32_t, kPointMessageInts>;

/// [timeout, 0, 0, 0, 0, 0, 0, IDLE]
ReverseMessage idleMessage(int read_timeout_ms);
/// [timeout, 0, 0, 0, 0, 0, 0, STOPPED]: the program leaves its control loop, stops the arm and closes
/// its sockets (what UR's client library sends before it closes the reverse socket).
ReverseMessage stoppedMessage(int read_timeout_ms);
/// [timeout, action, points, 0, 0, 0, 0, FORWARD]
ReverseMessage forwardMessage(int read_timeout_ms, TrajectoryAction action, std::int32_t points = 0);

std::array<std::uint8_t, 4 * kReverseMessageInts> encode(const ReverseMessage& m);
std::array<std::uint8_t, 4 * kPointMessageInts> encode(const PointMessage& m);
ReverseMessage decodeReverse(const std::uint8_t* bytes);
PointMessage decodePoint(const std::uint8_t* bytes);

/// value * mult rounded to int32; false for NaN, infinity or a result outside int32.
bool scaleToInt32(double value, double mult, std::int32_t& out);

/// The point messages for a goal. A first point at t = 0 must equal `current` within `tolerance` and
/// is skipped (the robot is already there); [18] is each point's segment duration. Velocities go in
/// [6-11] (SPLINE: the cubic's end velocity), accelerations [12-17] are zero, [19] is the spline type
/// (cubic) or the blend radius (0) for MOVEJ. Returns an empty string, or why the goal cannot be sent
/// (a value that overflows int32 or is NaN, a first point off the current position).
std::string buildPointMessages(const ArmTrajectory& trajectory, const JointVector& current, double tolerance,
                               PointType type, std::vector<PointMessage>& out);

/// The robot's trajectory result as a common result code: 0 SUCCESSFUL (the caller still checks the
/// goal tolerance), 1 CANCELLED, 2 PATH_TOLERANCE_VIOLATED (the robot could not follow the
/// trajectory), anything else FAULT.
ResultCode mapTrajectoryResult(std::int32_t result);

struct ProgramParams {
  std::string server_ip;  ///< this PC's address as the robot sees it
  int reverse_port = 50001;
  int trajectory_port = 50003;
  int script_command_port = 50004;
};
/// The URScript program served on request_program: program_template.urscript with the parameters filled in.
std::string program(const ProgramParams& params);
/// The template itself (placeholders {{SERVER_IP}}, {{REVERSE_PORT}}, {{TRAJECTORY_PORT}},
/// {{SCRIPT_COMMAND_PORT}}, {{MULT_JOINTSTATE}}, {{MULT_TIME}}).
const std::string& programTemplate();
/// The program's last line; the robot's URCap reads the program up to it.
inline constexpr const char* kProgramEndMarker = "# NODE_CONTROL_LOOP_ENDS";

}  // namespace dash::dispatch::ur
