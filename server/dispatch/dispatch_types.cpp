#include "server/dispatch/dispatch_types.h"

#include <cmath>
#include <limits>

namespace dash::dispatch {

namespace {

constexpr ResultCode kAllCodes[] = {
    ResultCode::kSuccessful,           ResultCode::kInvalidGoal,          ResultCode::kInvalidJoints,
    ResultCode::kOldHeaderTimestamp,   ResultCode::kPathToleranceViolated, ResultCode::kGoalToleranceViolated,
    ResultCode::kCancelled,            ResultCode::kFault,
};

constexpr ArmStatus kAllStatuses[] = {ArmStatus::kIdle,      ArmStatus::kArmed,  ArmStatus::kExecuting,
                                      ArmStatus::kSucceeded, ArmStatus::kFailed, ArmStatus::kAborted};

}  // namespace

const char* resultCodeName(ResultCode code) {
  switch (code) {
    case ResultCode::kSuccessful: return "SUCCESSFUL";
    case ResultCode::kInvalidGoal: return "INVALID_GOAL";
    case ResultCode::kInvalidJoints: return "INVALID_JOINTS";
    case ResultCode::kOldHeaderTimestamp: return "OLD_HEADER_TIMESTAMP";
    case ResultCode::kPathToleranceViolated: return "PATH_TOLERANCE_VIOLATED";
    case ResultCode::kGoalToleranceViolated: return "GOAL_TOLERANCE_VIOLATED";
    case ResultCode::kCancelled: return "CANCELLED";
    case ResultCode::kFault: return "FAULT";
  }
  return "UNKNOWN";
}

std::optional<ResultCode> resultCodeFromName(const std::string& name) {
  for (ResultCode c : kAllCodes) {
    if (name == resultCodeName(c)) return c;
  }
  return std::nullopt;
}

std::optional<ResultCode> resultCodeFromInt(int code) {
  for (ResultCode c : kAllCodes) {
    if (code == static_cast<int>(c)) return c;
  }
  return std::nullopt;
}

const char* armStatusName(ArmStatus status) {
  switch (status) {
    case ArmStatus::kIdle: return "idle";
    case ArmStatus::kArmed: return "armed";
    case ArmStatus::kExecuting: return "executing";
    case ArmStatus::kSucceeded: return "succeeded";
    case ArmStatus::kFailed: return "failed";
    case ArmStatus::kAborted: return "aborted";
  }
  return "unknown";
}

std::optional<ArmStatus> armStatusFromName(const std::string& name) {
  for (ArmStatus s : kAllStatuses) {
    if (name == armStatusName(s)) return s;
  }
  return std::nullopt;
}

double maxAbsDifference(const JointVector& a, const JointVector& b) {
  if (a.size() != b.size()) return std::numeric_limits<double>::infinity();
  if (a.size() == 0) return 0.0;
  return (a - b).cwiseAbs().maxCoeff();
}

}  // namespace dash::dispatch
