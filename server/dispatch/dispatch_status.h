#pragma once
// The state of one dispatch (a plan sent to several arms), per arm planned vs actual.
#include <cstdint>
#include <string>
#include <vector>

#include "server/dispatch/dispatch_types.h"
#include "server/dispatch/tolerances.h"

namespace dash::dispatch {

enum class DispatchState {
  kArming,     ///< goals sent, waiting for every agent to accept its goal
  kRunning,    ///< start time sent; arms moving (or about to)
  kSucceeded,  ///< every arm reached its goal
  kFailed,     ///< an arm failed (its result says why); every arm was aborted
  kAborted,    ///< aborted: on request, on a path deviation, a fault or a lost agent
  kRefused,    ///< an agent refused its goal while arming; nothing moved
};

const char* dispatchStateName(DispatchState state);  ///< "arming", "running", ...
inline bool isActive(DispatchState s) { return s == DispatchState::kArming || s == DispatchState::kRunning; }

/// One point of an arm's planned-vs-actual trace (decimated for display).
struct TracePoint {
  double t = 0.0;  ///< s from the start
  JointVector planned;
  JointVector actual;
};

/// One step of an arm in execution by dependencies (tpg_execution.h): planned and executed times.
struct SegmentRecord {
  int node = -1;            ///< node of the temporal plan graph
  std::string kind;         ///< "motion", "gripper", "hold", "inspect"
  double planned_start = 0.0;  ///< s from the start, as the plan (scaled) has it
  double planned_end = 0.0;
  double start = -1.0;      ///< s from the dispatch's start when it was sent (-1: not yet)
  double end = -1.0;        ///< s when its agent reported it done (-1: not yet)
  JointVector q_start;      ///< measured when it started (empty if no sample yet)
  JointVector q_end;        ///< measured when it ended
};

struct ArmDispatchStatus {
  std::string robot;
  std::string driver;
  ArmStatus status = ArmStatus::kIdle;  ///< what the agent last reported for this dispatch
  ResultCode result = ResultCode::kSuccessful;
  std::string message;
  bool done = false;  ///< the arm reported a final status (or was given up on)
  double duration = 0.0;  ///< s: when this arm's goal ends
  JointVector planned;    ///< planned position at the time of the last sample
  JointVector actual;     ///< the last measured position
  double deviation = 0.0;      ///< max |actual - planned| of the last sample
  double max_deviation = 0.0;  ///< over the dispatch so far
  double last_sample_t = 0.0;  ///< s from the start (negative before it)
  int samples = 0;
  JointVector path_tolerance;  ///< per joint, resolved for this arm's joints (0: not checked)
  JointVector goal_tolerance;
  std::vector<TracePoint> trace;  ///< filled only when asked for
  // Execution by dependencies ("tpg") only:
  int step = -1;             ///< the step it is on (steps when every step is done)
  int steps = 0;
  std::string waiting_for;   ///< what its current step waits for; empty when it runs or is done
  std::vector<SegmentRecord> segments;  ///< every step, planned vs executed
};

/// Who asked for a dispatch and what it was (for the record: the results database keeps it).
struct DispatchOrigin {
  std::string requested_by;  ///< the request's user label; empty: the token holder, unnamed
  std::string client;        ///< the requesting client's address
  std::string run_id;        ///< the stored run whose plan it is; empty for a plan sent with the request
};

struct DispatchStatus {
  std::string id;
  DispatchOrigin origin;
  DispatchState state = DispatchState::kArming;
  std::string reason;  ///< why it ended (empty while active and on success)
  std::string scene;
  std::string planner;
  std::string execution = "timed";  ///< "timed" (one common start) or "tpg" (by dependencies)
  double time_scale = 1.0;
  double duration = 0.0;  ///< s: the latest arm end time
  std::int64_t created_us = 0;
  std::int64_t created_unix_ms = 0;  ///< wall clock of created_us, for the record
  std::int64_t start_time_us = 0;  ///< 0 until the start time is set
  std::int64_t end_time_us = 0;    ///< 0 while active
  double elapsed = 0.0;            ///< s since the start time (negative before it)
  bool final = false;  ///< no arm report will change it any more
  double start_tolerance = 0.0;
  ToleranceSpec path_tolerance;
  ToleranceSpec goal_tolerance;
  double goal_time_tolerance = 0.0;
  std::vector<ArmDispatchStatus> arms;
};

}  // namespace dash::dispatch
