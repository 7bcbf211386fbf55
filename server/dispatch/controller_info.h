#pragma once
// What the server knows about one controller agent (one arm): the registry's row.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "server/dispatch/dispatch_types.h"

namespace dash::dispatch {

struct ControllerInfo {
  std::string robot;  ///< the scene robot's id
  std::string driver;  ///< "sim", "ur", ...
  std::string model;   ///< "ur5e", ...
  std::string session;  ///< changes with every (re)connection
  std::vector<std::string> joint_names;
  bool connected = false;  ///< its command stream is open
  bool ready = false;      ///< the agent says it can take a goal
  std::string detail;      ///< the agent's note (why not ready, ...)
  ArmStatus status = ArmStatus::kIdle;
  std::string dispatch_id;
  ResultCode result = ResultCode::kSuccessful;
  std::string message;
  std::string gripper;
  std::optional<JointSample> last_sample;
  std::int64_t connected_since_us = 0;
  std::int64_t last_report_us = 0;  ///< server time of the last state report
  int reconnects = 0;               ///< streams opened after the first
};

}  // namespace dash::dispatch
