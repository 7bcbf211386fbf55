#pragma once
// The wire protocol between the dispatch server and its controller agents (one agent per arm).
//
// Server -> agent: one long-lived `GET /api/controllers/ROBOT/stream` answered with server-sent
// events, one JSON object per `data:` line:
//   hello       {"session", "server_time_us", "robot", "clock"} first event of every stream
//   ping        {"server_time_us"}                              every heartbeat interval
//   trajectory  {"dispatch_id", "trajectory": {...}, "limits": {...}}   load (check) a goal
//   start       {"dispatch_id", "start_time_us"}                start at that server time
//   abort       {"dispatch_id", "reason"}                       stop now
// Agent -> server: `POST /api/controllers/ROBOT/state` with an AgentReport (samples batched, sent at
// 50 Hz or more while a goal is armed or executing, at once on every status change), answered
// {"server_time_us"} (for the agent's clock offset) or 409 when the session is stale.
// Times are the server's steady clock in microseconds; agents convert with their estimated offset.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "server/dispatch/arm_trajectory.h"
#include "server/dispatch/dispatch_types.h"
#include "server/dispatch/tolerances.h"

namespace dash::dispatch {

/// Tolerances an agent applies to its goal (tolerances.h: as ros2_control's trajectory controller).
struct GoalLimits {
  double start_tolerance = 0.01;  ///< rad (m): first point vs the measured state
  JointVector goal_tolerance;     ///< rad (m) per joint: final state vs the last point (empty: the default)
  double goal_time_tolerance = kDefaultGoalTimeTolerance;  ///< s after the end to get within goal_tolerance

  /// goal_tolerance, or kDefaultGoalTolerance for each of `dof` joints when it is empty.
  JointVector goalTolerance(Eigen::Index dof) const {
    return goal_tolerance.size() == dof ? goal_tolerance : JointVector::Constant(dof, kDefaultGoalTolerance);
  }
};

struct HelloMessage {
  std::string session;
  std::int64_t server_time_us = 0;
  std::string robot;
  std::string clock;  ///< steadyClockId() of the server: an agent with the same id shares its clock
};

inline constexpr std::size_t kMaxClockIdLength = 64;
/// Names this machine's steady clock (its boot id; empty if unknown). Two processes with the same
/// id read the same clock: their offset is exactly 0, with no estimate needed.
std::string steadyClockId();

struct TrajectoryCommand {
  std::string dispatch_id;
  ArmTrajectory trajectory;
  GoalLimits limits;
};

struct StartCommand {
  std::string dispatch_id;
  std::int64_t start_time_us = 0;
};

struct AbortCommand {
  std::string dispatch_id;
  std::string reason;
};

/// What an agent tells the server, batched.
struct AgentReport {
  std::string session;
  std::string driver;  ///< "sim", "ur"
  std::string model;   ///< robot model name, e.g. "ur5e"
  std::vector<std::string> joint_names;
  bool ready = false;  ///< can take a goal now (robot connected, state known)
  std::string detail;  ///< why not ready, or what it is doing
  ArmStatus status = ArmStatus::kIdle;
  std::string dispatch_id;  ///< the goal `status` and `result` refer to
  ResultCode result = ResultCode::kSuccessful;
  std::string message;  ///< result message
  std::string gripper;  ///< "open", "closed" or empty (no gripper)
  std::vector<JointSample> samples;  ///< oldest first, stamped in server time
};

// Codecs. Parsing throws InputError naming the field on malformed input.
std::string helloToJson(const HelloMessage& m);
HelloMessage parseHello(const std::string& json);
std::string pingToJson(std::int64_t server_time_us);
std::string trajectoryCommandToJson(const TrajectoryCommand& c);
TrajectoryCommand parseTrajectoryCommand(const std::string& json);
std::string startCommandToJson(const StartCommand& c);
StartCommand parseStartCommand(const std::string& json);
std::string abortCommandToJson(const AbortCommand& c);
AbortCommand parseAbortCommand(const std::string& json);
std::string agentReportToJson(const AgentReport& r);
AgentReport parseAgentReport(const std::string& json);
/// The "server_time_us" of a JSON object, if present.
std::optional<std::int64_t> parseServerTime(const std::string& json);

/// One server-sent event.
struct SseEvent {
  std::string event;  ///< "message" when the stream names none
  std::string data;   ///< data lines joined with '\n'
};
/// "event: NAME\ndata: DATA\n\n" (DATA must hold no newline; JSON from the codecs above holds none).
std::string formatSse(const std::string& event, const std::string& data);

/// Splits a text/event-stream into events as chunks arrive (any chunk boundaries; LF or CRLF).
class SseParser {
 public:
  /// Appends a chunk and returns the events it completed.
  std::vector<SseEvent> feed(const char* data, std::size_t size);

 private:
  void line(const std::string& text, std::vector<SseEvent>& out);
  std::string buffer_;
  SseEvent current_;
  bool has_data_ = false;
};

}  // namespace dash::dispatch
