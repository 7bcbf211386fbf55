#pragma once
// The wire protocol between the dispatch server and its controller agents (one agent per arm).
//
// Server -> agent: one long-lived `GET /api/controllers/ROBOT/stream` answered with server-sent
// events, one JSON object per `data:` line:
//   hello       {"session", "server_time_us", "robot"}          first event of every stream
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

namespace dash::dispatch {

/// Tolerances an agent applies to its goal.
struct GoalLimits {
  double start_tolerance = 0.01;     ///< rad (m): first point vs the measured state
  double goal_tolerance = 0.01;      ///< rad (m): final state vs the last point
  double goal_time_tolerance = 1.0;  ///< s after the end to get within goal_tolerance
};

struct HelloMessage {
  std::string session;
  std::int64_t server_time_us = 0;
  std::string robot;
};

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
