// UR External Control encoding, byte for byte; goal conversion; result mapping; the served program.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "server/dispatch/tcp_socket.h"
#include "server/dispatch/ur_protocol.h"

namespace dash::dispatch {
namespace {

JointVector joints(std::initializer_list<double> v) {
  JointVector q(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v) q[i++] = x;
  return q;
}

ArmTrajectory twoSegments() {
  ArmTrajectory t;
  t.joint_names = {"a", "b", "c", "d", "e", "f"};
  const JointVector z = JointVector::Zero(6);
  t.points.push_back({joints({0, -1.5708, 1.5708, -1.5708, -1.5708, 0}), z, 0.0});
  t.points.push_back({joints({0.5, -1.3708, 1.2708, -1.3708, -1.2708, 0.6}), joints({0.1, 0, 0, 0, 0, -0.25}), 1.2});
  t.points.push_back({joints({0.5, -1.3708, 1.2708, -1.3708, -1.2708, 0.6}), z, 1.6});
  return t;
}

TEST(UrProtocol, ReverseMessagesAreEightBigEndianInts) {
  const auto bytes = ur::encode(ur::forwardMessage(100, ur::TrajectoryAction::kStart, 7));
  const std::uint8_t expected[32] = {0, 0, 0, 100, 0, 0, 0, 1, 0, 0, 0, 7, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 3};
  ASSERT_EQ(bytes.size(), 32u);
  for (int i = 0; i < 32; ++i) EXPECT_EQ(bytes[static_cast<std::size_t>(i)], expected[i]) << "byte " << i;

  const auto cancel = ur::encode(ur::forwardMessage(20, ur::TrajectoryAction::kCancel));
  EXPECT_EQ(cancel[4], 0xFF);  // -1
  EXPECT_EQ(cancel[7], 0xFF);
  EXPECT_EQ(cancel[31], 3);
  const auto idle = ur::decodeReverse(ur::encode(ur::idleMessage(0)).data());
  EXPECT_EQ(idle, (ur::ReverseMessage{0, 0, 0, 0, 0, 0, 0, 0}));
  const auto noop = ur::decodeReverse(ur::encode(ur::forwardMessage(50, ur::TrajectoryAction::kNoop)).data());
  EXPECT_EQ(noop, (ur::ReverseMessage{50, 0, 0, 0, 0, 0, 0, 3}));
}

TEST(UrProtocol, PointsSkipTheStartAndCarrySegmentDurations) {
  const ArmTrajectory t = twoSegments();
  std::vector<ur::PointMessage> points;
  ASSERT_EQ(ur::buildPointMessages(t, t.points[0].positions, 0.01, ur::PointType::kSpline, points), "");
  ASSERT_EQ(points.size(), 2u);  // the first point (t = 0, where the robot is) is skipped
  EXPECT_EQ(points[0][0], 500000);
  EXPECT_EQ(points[0][1], -1370800);
  EXPECT_EQ(points[0][6], 100000);     // velocity 0.1 rad/s
  EXPECT_EQ(points[0][11], -250000);   // velocity -0.25 rad/s
  EXPECT_EQ(points[0][12], 0);         // accelerations
  EXPECT_EQ(points[0][18], 1200000);   // segment duration 1.2 s
  EXPECT_EQ(points[1][18], 400000);    // 1.6 - 1.2: the segment's own duration
  EXPECT_EQ(points[0][19], 1);         // cubic spline
  EXPECT_EQ(points[0][20], 51);        // SPLINE

  const auto bytes = ur::encode(points[0]);
  ASSERT_EQ(bytes.size(), 84u);
  EXPECT_EQ(getInt32(bytes.data() + 4 * 18), 1200000);
  EXPECT_EQ(bytes[4 * 20 + 3], 51);
  EXPECT_EQ(ur::decodePoint(bytes.data()), points[0]);

  std::vector<ur::PointMessage> movej;
  ASSERT_EQ(ur::buildPointMessages(t, t.points[0].positions, 0.01, ur::PointType::kMovej, movej), "");
  EXPECT_EQ(movej[0][20], 0);
  EXPECT_EQ(movej[0][19], 0);  // blend radius
  EXPECT_EQ(movej[0][6], 0);
}

TEST(UrProtocol, RefusesOverflowNanAndAStartAwayFromTheRobot) {
  ArmTrajectory t = twoSegments();
  std::vector<ur::PointMessage> points;
  JointVector elsewhere = t.points[0].positions;
  elsewhere[2] += 0.05;
  EXPECT_NE(ur::buildPointMessages(t, elsewhere, 0.01, ur::PointType::kSpline, points), "");

  ArmTrajectory big = t;
  big.points[1].positions[0] = 2200.0;  // 2.2e9 urad > INT32_MAX
  EXPECT_NE(ur::buildPointMessages(big, t.points[0].positions, 0.01, ur::PointType::kSpline, points).find("overflows"),
            std::string::npos);
  ArmTrajectory nan = t;
  nan.points[2].velocities[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(ur::buildPointMessages(nan, t.points[0].positions, 0.01, ur::PointType::kSpline, points).find("NaN"),
            std::string::npos);
  ArmTrajectory slow = t;
  slow.points[2].time_from_start = 2200.0;  // a 2198.8 s segment overflows in us
  EXPECT_NE(ur::buildPointMessages(slow, t.points[0].positions, 0.01, ur::PointType::kSpline, points), "");

  std::int32_t out = 0;
  EXPECT_TRUE(ur::scaleToInt32(2147.483647, 1e6, out));
  EXPECT_EQ(out, std::numeric_limits<std::int32_t>::max());
  EXPECT_FALSE(ur::scaleToInt32(2147.4837, 1e6, out));
  EXPECT_FALSE(ur::scaleToInt32(std::numeric_limits<double>::infinity(), 1e6, out));
  EXPECT_TRUE(ur::scaleToInt32(-2147.483648, 1e6, out));
  EXPECT_EQ(out, std::numeric_limits<std::int32_t>::min());
}

TEST(UrProtocol, ResultsMapToCommonCodes) {
  EXPECT_EQ(ur::mapTrajectoryResult(0), ResultCode::kSuccessful);
  EXPECT_EQ(ur::mapTrajectoryResult(1), ResultCode::kCancelled);
  EXPECT_EQ(ur::mapTrajectoryResult(2), ResultCode::kPathToleranceViolated);
  EXPECT_EQ(ur::mapTrajectoryResult(7), ResultCode::kFault);
  EXPECT_STREQ(resultCodeName(ResultCode::kGoalToleranceViolated), "GOAL_TOLERANCE_VIOLATED");
  EXPECT_EQ(static_cast<int>(ResultCode::kInvalidJoints), -2);
  EXPECT_EQ(resultCodeFromName("CANCELLED"), ResultCode::kCancelled);
}

TEST(UrProtocol, ProgramHasItsPortsHostAndMarkers) {
  const std::string text = ur::program({"10.0.0.7", 51001, 51003, 51004});
  EXPECT_EQ(text.find("{{"), std::string::npos);
  EXPECT_NE(text.find("socket_open(\"10.0.0.7\", 51003, \"trajectory_socket\")"), std::string::npos);
  EXPECT_NE(text.find("socket_open(\"10.0.0.7\", 51004, \"script_command_socket\")"), std::string::npos);
  EXPECT_NE(text.find("socket_open(\"10.0.0.7\", 51001, \"reverse_socket\")"), std::string::npos);
  EXPECT_NE(text.find("MULT_jointstate = 1000000"), std::string::npos);
  for (const char* marker : {"# HEADER_BEGIN", "# HEADER_END", "# NODE_CONTROL_LOOP_BEGINS"}) {
    EXPECT_NE(text.find(marker), std::string::npos) << marker;
  }
  EXPECT_EQ(text.substr(text.size() - std::string(ur::kProgramEndMarker).size() - 1),
            std::string(ur::kProgramEndMarker) + "\n");
}

TEST(TcpSocket, BigEndianDoubles) {
  std::uint8_t bytes[8];
  putDouble(bytes, 1.0);
  EXPECT_EQ(bytes[0], 0x3F);
  EXPECT_EQ(bytes[1], 0xF0);
  EXPECT_EQ(getDouble(bytes), 1.0);
  putDouble(bytes, -2.5e-3);
  EXPECT_EQ(getDouble(bytes), -2.5e-3);
}

}  // namespace
}  // namespace dash::dispatch
