#include "server/dispatch/ur_protocol.h"

#include <cmath>
#include <limits>

#include "server/dispatch/tcp_socket.h"

namespace dash::dispatch::ur {

namespace {

void replaceAll(std::string& text, const std::string& key, const std::string& value) {
  for (std::size_t pos = text.find(key); pos != std::string::npos; pos = text.find(key, pos + value.size())) {
    text.replace(pos, key.size(), value);
  }
}

std::string fixed(double v) {
  std::string s = std::to_string(v);
  return s;
}

}  // namespace

ReverseMessage idleMessage(int read_timeout_ms) {
  return {read_timeout_ms, 0, 0, 0, 0, 0, 0, static_cast<std::int32_t>(ControlMode::kIdle)};
}

ReverseMessage stoppedMessage(int read_timeout_ms) {
  return {read_timeout_ms, 0, 0, 0, 0, 0, 0, static_cast<std::int32_t>(ControlMode::kStopped)};
}

ReverseMessage forwardMessage(int read_timeout_ms, TrajectoryAction action, std::int32_t points) {
  return {read_timeout_ms, static_cast<std::int32_t>(action), points, 0, 0, 0, 0,
          static_cast<std::int32_t>(ControlMode::kForward)};
}

std::array<std::uint8_t, 4 * kReverseMessageInts> encode(const ReverseMessage& m) {
  std::array<std::uint8_t, 4 * kReverseMessageInts> out{};
  for (int i = 0; i < kReverseMessageInts; ++i) putInt32(out.data() + 4 * i, m[static_cast<std::size_t>(i)]);
  return out;
}

std::array<std::uint8_t, 4 * kPointMessageInts> encode(const PointMessage& m) {
  std::array<std::uint8_t, 4 * kPointMessageInts> out{};
  for (int i = 0; i < kPointMessageInts; ++i) putInt32(out.data() + 4 * i, m[static_cast<std::size_t>(i)]);
  return out;
}

ReverseMessage decodeReverse(const std::uint8_t* bytes) {
  ReverseMessage m{};
  for (int i = 0; i < kReverseMessageInts; ++i) m[static_cast<std::size_t>(i)] = getInt32(bytes + 4 * i);
  return m;
}

PointMessage decodePoint(const std::uint8_t* bytes) {
  PointMessage m{};
  for (int i = 0; i < kPointMessageInts; ++i) m[static_cast<std::size_t>(i)] = getInt32(bytes + 4 * i);
  return m;
}

bool scaleToInt32(double value, double mult, std::int32_t& out) {
  const double scaled = std::round(value * mult);
  if (!std::isfinite(scaled)) return false;
  if (scaled > static_cast<double>(std::numeric_limits<std::int32_t>::max()) ||
      scaled < static_cast<double>(std::numeric_limits<std::int32_t>::min())) {
    return false;
  }
  out = static_cast<std::int32_t>(scaled);
  return true;
}

std::string buildPointMessages(const ArmTrajectory& trajectory, const JointVector& current, double tolerance,
                               PointType type, std::vector<PointMessage>& out) {
  out.clear();
  const auto& points = trajectory.points;
  if (points.empty()) return "the trajectory has no points";
  for (const auto& p : points) {
    if (p.positions.size() != 6 || p.velocities.size() != 6) return "a UR arm takes 6 joints per point";
  }
  std::size_t first = 0;
  if (points.front().time_from_start == 0.0) {
    if (current.size() != 6) return "the robot's joint state is not known";
    const double off = maxAbsDifference(points.front().positions, current);
    if (!(off <= tolerance)) {
      return "the first point (t=0) is " + std::to_string(off) + " rad from the robot's position (tolerance " +
             std::to_string(tolerance) + ")";
    }
    first = 1;  // the robot is there already
  }
  double previous_t = 0.0;
  for (std::size_t i = first; i < points.size(); ++i) {
    const TrajectoryWaypoint& p = points[i];
    PointMessage m{};
    const std::string where = "point " + std::to_string(i);
    for (int j = 0; j < 6; ++j) {
      if (!scaleToInt32(p.positions[j], kMultJointState, m[static_cast<std::size_t>(j)])) {
        return where + ": position " + std::to_string(j) + " is NaN or overflows int32 once scaled";
      }
      const double v = type == PointType::kSpline ? p.velocities[j] : 0.0;
      if (!scaleToInt32(v, kMultJointState, m[static_cast<std::size_t>(6 + j)])) {
        return where + ": velocity " + std::to_string(j) + " is NaN or overflows int32 once scaled";
      }
      m[static_cast<std::size_t>(12 + j)] = 0;
    }
    const double segment = p.time_from_start - previous_t;
    if (!(segment > 0.0)) return where + ": its segment duration is not positive";
    if (!scaleToInt32(segment, kMultTime, m[18])) return where + ": segment duration overflows int32 once scaled";
    m[19] = type == PointType::kSpline ? static_cast<std::int32_t>(SplineType::kCubic) : 0;
    m[20] = static_cast<std::int32_t>(type);
    previous_t = p.time_from_start;
    out.push_back(m);
  }
  return "";
}

ResultCode mapTrajectoryResult(std::int32_t result) {
  switch (result) {
    case static_cast<std::int32_t>(TrajectoryResult::kSuccess): return ResultCode::kSuccessful;
    case static_cast<std::int32_t>(TrajectoryResult::kCancelled): return ResultCode::kCancelled;
    case static_cast<std::int32_t>(TrajectoryResult::kFailure): return ResultCode::kPathToleranceViolated;
    default: return ResultCode::kFault;
  }
}

std::string program(const ProgramParams& params) {
  std::string text = programTemplate();
  replaceAll(text, "{{SERVER_IP}}", params.server_ip);
  replaceAll(text, "{{REVERSE_PORT}}", std::to_string(params.reverse_port));
  replaceAll(text, "{{TRAJECTORY_PORT}}", std::to_string(params.trajectory_port));
  replaceAll(text, "{{SCRIPT_COMMAND_PORT}}", std::to_string(params.script_command_port));
  replaceAll(text, "{{MULT_JOINTSTATE}}", fixed(kMultJointState));
  replaceAll(text, "{{MULT_TIME}}", fixed(kMultTime));
  return text;
}

}  // namespace dash::dispatch::ur
