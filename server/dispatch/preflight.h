#pragma once
// Pre-flight checks of a dispatch: nothing moves unless every one passes.
//  - plan_valid: the plan passes the project's plan validator for its scene (validatePlan);
//  - controller_connected / controller_ready: every plan robot has a connected agent that can take a goal;
//  - joint_names: the plan's joint names equal the model's and the agent's, in order;
//  - time_order: times start at 0 and strictly increase;
//  - speed_limits: every plan segment, and the curve the arm will actually follow (arm_trajectory.h),
//    stays within the model's velocity_max;
//  - start_state: the arm's measured state (fresh) equals the plan's first point within start_tolerance.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/plan/plan.h"
#include "engine/scene/scene.h"
#include "server/dispatch/arm_trajectory.h"
#include "server/dispatch/controller_info.h"

namespace dash::dispatch {

struct PreflightOptions {
  double start_tolerance = 0.01;   ///< rad (m)
  double time_scale = 1.0;         ///< applied to the plan's times before the speed checks
  double velocity_tolerance = 1e-6;  ///< relative, on velocity_max
  double state_timeout = 0.5;      ///< s: an older measured state does not count
  bool validate_geometry = true;   ///< run the validator's collision sampling
  int validator_threads = 0;       ///< 0 = the hardware's
  std::int64_t now_us = 0;         ///< server time of the check
};

struct PreflightCheck {
  std::string name;   ///< plan_valid, controller_connected, controller_ready, joint_names, time_order, speed_limits, start_state
  std::string robot;  ///< empty for whole-plan checks
  bool passed = true;
  std::string message;
  int http_status = 200;  ///< 422 for a bad plan, 409 for arms not in a state to run it
};

struct PreflightReport {
  bool passed = true;
  std::vector<PreflightCheck> checks;
  std::vector<ArmTrajectory> trajectories;  ///< one per plan robot, in plan order (when the plan allows)

  /// The first failed check's message, prefixed by its robot ("" if all passed).
  std::string reason() const;
  /// 422 if a failed check is about the plan, else 409 (200 if all passed).
  int httpStatus() const;
};

/// Runs every check; `controllers` is a snapshot of the registry.
PreflightReport runPreflight(const Scene& scene, const Plan& plan, const std::vector<ControllerInfo>& controllers,
                             const PreflightOptions& options);

}  // namespace dash::dispatch
