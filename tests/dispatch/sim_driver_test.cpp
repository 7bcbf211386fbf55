// The simulated arm's misbehaviour (issue 39, sim_driver.h): a speed factor, random pauses and a
// gripper that takes time, so that dry runs show what a real cell does to a timetable. Each test runs
// one short goal in real time and checks a lower bound on how long it took (a loaded machine only
// makes it longer), against the goal's own duration.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "dispatch_test_util.h"
#include "server/dispatch/sim_driver.h"

namespace dash::dispatch {
namespace {

using Clock = std::chrono::steady_clock;

constexpr double kGoalSeconds = 0.6;

/// Shoulder and elbow move 0.3 rad in kGoalSeconds (well within the UR5e's limits), from zero.
ArmTrajectory shortGoal(const RobotModel& model) {
  ArmTrajectory goal;
  goal.robot = "ur5e_0";
  goal.joint_names = model.joint_names;
  const JointVector q0 = JointVector::Zero(model.dof());
  JointVector q1 = q0;
  q1[1] = q1[2] = 0.3;
  goal.points.push_back({q0, JointVector::Zero(model.dof()), 0.0});
  goal.points.push_back({q1, JointVector::Zero(model.dof()), kGoalSeconds});
  return goal;
}

/// Loads `goal`, starts it now, and returns the seconds until the driver reports it succeeded (or
/// -1 if it ended otherwise or took over 20 s).
double secondsToSucceed(SimDriver& driver, const ArmTrajectory& goal) {
  std::string message;
  GoalLimits limits;
  limits.goal_time_tolerance = 10.0;
  EXPECT_EQ(driver.load(goal, limits, message), ResultCode::kSuccessful) << message;
  const auto t0 = Clock::now();
  driver.start(t0);
  for (;;) {
    const DriverProgress p = driver.progress();
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    if (p.status == ArmStatus::kSucceeded) return seconds;
    if (p.status == ArmStatus::kFailed || p.status == ArmStatus::kAborted || seconds > 20.0) {
      ADD_FAILURE() << "status " << armStatusName(p.status) << ": " << p.message;
      return -1.0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

TEST(SimDriverMisbehaves, AtSpeedSevenTenthsAGoalTakesItsDurationOverSevenTenths) {
  const RobotModel& model = test::library()->get("ur5e");
  SimDriverOptions options;
  options.speed = 0.7;
  SimDriver driver(model, options);
  const double took = secondsToSucceed(driver, shortGoal(model));
  EXPECT_GE(took, kGoalSeconds / 0.7 - 0.01);
  std::printf("[ measure  ] a %.2f s goal at speed 0.7 took %.3f s\n", kGoalSeconds, took);
}

TEST(SimDriverMisbehaves, RandomPausesMakeAGoalLastLongerThanItsDuration) {
  const RobotModel& model = test::library()->get("ur5e");
  SimDriverOptions options;
  options.pause_rate = 10.0;  // pauses per second of motion
  options.pause_max = 0.2;
  options.seed = 3;
  SimDriver driver(model, options);
  const double took = secondsToSucceed(driver, shortGoal(model));
  EXPECT_GE(took, kGoalSeconds + 0.15);
  std::printf("[ measure  ] a %.2f s goal with pauses took %.3f s\n", kGoalSeconds, took);
}

TEST(SimDriverMisbehaves, AGraspGoalEndsOnlyOnceTheGripperHasClosed) {
  const RobotModel& model = test::library()->get("ur5e");
  SimDriverOptions options;
  options.gripper_time = 0.5;
  options.gripper_jitter = 0.1;
  SimDriver driver(model, options);
  ArmTrajectory grasp;  // one point where the arm stands, and the gripper command at 0
  grasp.robot = "ur5e_0";
  grasp.joint_names = model.joint_names;
  grasp.points.push_back({JointVector::Zero(model.dof()), JointVector::Zero(model.dof()), 0.0});
  grasp.gripper.push_back({0.0, GripperCommand::Action::kGrasp, "obj_0"});
  EXPECT_EQ(driver.gripperState(), "open");
  const double took = secondsToSucceed(driver, grasp);
  EXPECT_GE(took, 0.5 - 0.1 - 0.01);
  EXPECT_EQ(driver.gripperState(), "closed");
  std::printf("[ measure  ] a grasp with a 0.5 +- 0.1 s gripper took %.3f s\n", took);
}

}  // namespace
}  // namespace dash::dispatch
