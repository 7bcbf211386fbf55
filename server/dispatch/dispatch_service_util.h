#pragma once
// Internal to the DispatchService sources (dispatch_service.cpp, dispatch_agents.cpp,
// dispatch_monitor.cpp, dispatch_tpg.cpp): status codes, unit conversions, message text.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "server/dispatch/dispatch_types.h"

namespace dash::dispatch::service_detail {

inline constexpr int kAccepted = 202;
inline constexpr int kConflict = 409;
inline constexpr int kUnprocessable = 422;
inline constexpr int kUnavailable = 503;
inline constexpr int kGatewayTimeout = 504;
inline constexpr double kDeadlineSlack = 0.25;  ///< s on top of goal_time_tolerance before giving up on an arm

inline std::int64_t micros(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e6)); }

inline std::string fmt(double v, int decimals = 3) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

inline std::string resultText(ResultCode code, const std::string& message) {
  return std::string(resultCodeName(code)) + (message.empty() ? "" : ": " + message);
}

/// Wall-clock milliseconds, for dispatch ids that stay unique across server restarts (and a random
/// tag per service across servers).
inline long long wallMillis() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace dash::dispatch::service_detail
