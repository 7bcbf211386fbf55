// RobotiqGripper against the simulated URCap socket (which answers as the real one: "ack" with no
// newline, "VAR value" with no newline) and against hostile peers (garbage, silence, floods).
#include "server/dispatch/robotiq_gripper.h"

#include <gtest/gtest.h>
#include <sys/socket.h>

#include <atomic>
#include <thread>

#include "dispatch_test_util.h"

namespace dash::dispatch {
namespace {

using test::SimGripper;
using test::SimGripperOptions;

std::unique_ptr<RobotiqGripper> connected(int port, RobotiqTimings timings = {}) {
  auto g = std::make_unique<RobotiqGripper>(timings);
  std::string error;
  EXPECT_TRUE(g->connect("127.0.0.1", port, 1000, error)) << error;
  return g;
}

TEST(RobotiqGripper, ActivatesTheWayRobotiqsClientDoes) {
  SimGripper sim({.activation_delay = 0.3});
  auto gp = connected(sim.port());
  RobotiqGripper& g = *gp;
  std::string error;
  ASSERT_TRUE(g.activate({}, error)) << error;
  EXPECT_TRUE(sim.activated());
  EXPECT_EQ(sim.sets(), (std::vector<std::string>{"SET ACT 0", "SET ATR 0", "SET ACT 1"}));
  // It waited for STA 0 after the reset and for STA 3 after SET ACT 1 (the sim answered 1 meanwhile).
  const auto commands = sim.commands();
  std::int64_t act1_us = 0;
  bool reset = false, saw_reset_done = false, saw_activating = false;
  for (const auto& c : commands) {
    if (c.line == "SET ATR 0") reset = true;
    if (c.line == "SET ACT 1") act1_us = c.received_us;
    saw_reset_done = saw_reset_done || (reset && act1_us == 0 && c.line == "GET STA" && c.answer == "STA 0");
    saw_activating = saw_activating || (act1_us != 0 && c.answer == "STA 1");
  }
  EXPECT_TRUE(saw_reset_done) << "asked STA and got STA 0 between SET ATR 0 and SET ACT 1";
  EXPECT_TRUE(saw_activating) << "asked STA while the activation ran";
  EXPECT_EQ(commands.back().line, "GET STA");
  EXPECT_EQ(commands.back().answer, "STA 3");
  EXPECT_GE(commands.back().received_us - act1_us, 300000);
}

TEST(RobotiqGripper, GraspReportsAPartOrAMiss) {
  SimGripper sim({.activation_delay = 0.0, .stroke_time = 0.1});
  auto gp = connected(sim.port());
  RobotiqGripper& g = *gp;
  std::string error;
  ASSERT_TRUE(g.activate({}, error)) << error;
  RobotiqGripper::MoveResult grasp = g.move(robotiq::kClosed, 255, 100, {});
  ASSERT_TRUE(grasp.ok) << grasp.error;
  EXPECT_EQ(grasp.obj, 2);  // stopped by the part while closing
  EXPECT_EQ(grasp.position, 200);
  EXPECT_EQ(sim.sets().back(), "SET POS 255 SPE 255 FOR 100 GTO 1");
  RobotiqGripper::MoveResult release = g.move(robotiq::kOpen, 255, 100, {});
  ASSERT_TRUE(release.ok) << release.error;
  EXPECT_EQ(release.obj, 3);
  EXPECT_EQ(release.position, 0);
  // The release took its time: the fingers were reported moving (OBJ 0) after its SET.
  int moving_after_release = 0;
  bool released = false;
  for (const auto& c : sim.commands()) {
    released = released || c.line == "SET POS 0 SPE 255 FOR 100 GTO 1";
    moving_after_release += released && c.answer == "OBJ 0" ? 1 : 0;
  }
  EXPECT_GT(moving_after_release, 0);
  sim.setObjectPresent(false);
  RobotiqGripper::MoveResult miss = g.move(robotiq::kClosed, 255, 100, {});
  ASSERT_TRUE(miss.ok) << miss.error;
  EXPECT_EQ(miss.obj, 3);  // closed on nothing
  EXPECT_EQ(miss.position, 255);
}

/// A peer that answers every line with `reply` (or nothing), for the hostile cases.
class FakeUrcap {
 public:
  explicit FakeUrcap(std::string reply) : reply_(std::move(reply)) {
    listener_ = listenTcp("127.0.0.1", 0);
    port_ = boundPort(listener_);
    thread_ = std::thread([this] {
      Socket client = acceptTcp(listener_, 3000);
      while (client.valid() && !stop_) {
        std::string line;
        const IoResult r = readLine(client.fd(), line, 50);
        if (r == IoResult::kClosed) break;
        if (r == IoResult::kOk && !reply_.empty()) writeAll(client.fd(), reply_.data(), reply_.size());
      }
    });
  }
  ~FakeUrcap() {
    stop_ = true;
    thread_.join();
  }
  int port() const { return port_; }

 private:
  std::string reply_;
  Socket listener_;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

TEST(RobotiqGripper, RefusesWhatIsNotTheUrcapsAnswer) {
  const RobotiqTimings quick{.answer_timeout_ms = 200};
  {
    FakeUrcap peer("nak");
    auto gp = connected(peer.port(), quick);
    RobotiqGripper& g = *gp;
    std::string error;
    EXPECT_FALSE(g.set({{"ACT", 1}}, error));
    EXPECT_NE(error.find("answered 'nak'"), std::string::npos) << error;
    EXPECT_FALSE(g.connected()) << "out of step: the connection is dropped";
  }
  {
    FakeUrcap silent("");
    auto gp = connected(silent.port(), quick);
    RobotiqGripper& g = *gp;
    std::string error;
    EXPECT_FALSE(g.get("STA", error).has_value());
    EXPECT_NE(error.find("no answer within 200 ms"), std::string::npos) << error;
  }
  {
    FakeUrcap flood(std::string(300, 'X'));
    auto gp = connected(flood.port(), quick);
    RobotiqGripper& g = *gp;
    std::string error;
    EXPECT_FALSE(g.get("STA", error).has_value());
    EXPECT_NE(error.find("longer than"), std::string::npos) << error;
  }
  {
    FakeUrcap wrong("POS 3\n");
    auto gp = connected(wrong.port(), quick);
    RobotiqGripper& g = *gp;
    std::string error;
    EXPECT_FALSE(g.get("STA", error).has_value());
    EXPECT_NE(error.find("answered 'POS 3'"), std::string::npos) << error;
  }
  {
    // A URCap that ends its answers with a newline is understood as well.
    FakeUrcap newline("ack\n");
    auto gp = connected(newline.port(), quick);
    RobotiqGripper& g = *gp;
    std::string error;
    EXPECT_TRUE(g.set({{"GTO", 1}}, error)) << error;
    EXPECT_TRUE(g.set({{"GTO", 1}}, error)) << error;
  }
}

}  // namespace
}  // namespace dash::dispatch
