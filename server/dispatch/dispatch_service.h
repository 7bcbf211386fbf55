#pragma once
// DispatchService: the server side of dispatching plans to real (or simulated) arms. It keeps the
// registry of controller agents (one per robot, connected over HTTP: dispatch_protocol.h), runs the
// pre-flight checks (preflight.h), and executes the plan one of two ways:
//  - "timed" (the default): sends each arm its goal, starts every arm at one common time a little in
//    the future, and compares every measured state with the plan at the same time;
//  - "tpg" (by dependencies, tpg_execution.h): sends each arm its next segment of the plan's temporal
//    plan graph once the segments it waits for are reported done, and compares every measured state
//    with the segment's path.
// Either way it aborts every arm on a path deviation, a fault, a lost agent, a missed deadline, or a
// request. Sources: dispatch_service.cpp (requests), dispatch_agents.cpp (agents' streams and
// reports), dispatch_monitor.cpp (while arms move), dispatch_tpg.cpp (execution by dependencies).
//
// HTTP is elsewhere: dispatch_routes.h mounts the service on an httplib::Server. Persistence and the
// dashboard attach through DispatchListener. Thread safe; one dispatch at a time.
//
// Shutdown order for the owner: service.shutdown() (ends the agents' streams), then server.stop().
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "engine/plan/plan.h"
#include "engine/robots/robot_model.h"
#include "engine/scene/scene.h"
#include "server/dispatch/command_stream.h"
#include "server/dispatch/controller_info.h"
#include "server/dispatch/dispatch_listener.h"
#include "server/dispatch/dispatch_protocol.h"
#include "server/dispatch/dispatch_status.h"
#include "server/dispatch/preflight.h"
#include "server/dispatch/tpg_execution.h"
#include "engine/tpg/tpg.h"

namespace dash::dispatch {

/// A stored run's plan and scene, as JSON text (what the server's run-id callback returns).
struct PlanSource {
  std::string plan_json;
  std::string scene_json;
};

struct DispatchConfig {
  std::shared_ptr<const RobotLibrary> library;  ///< resolves scene robots; nullptr: RobotLibrary::loadDefault()
  /// Resolves `{"run_id": ...}` dispatch requests; nullopt = unknown run. Unset: run ids are refused.
  std::function<std::optional<PlanSource>(const std::string& run_id)> resolve_run;
  double start_delay = 0.5;          ///< s from "every arm armed" to the common start time
  double start_tolerance = 0.01;     ///< rad (m): measured start vs the plan's first point
  /// Per joint (tolerances.h, as ros2_control's trajectory controller): measured vs planned at the
  /// same time until the arm's end time; the final state vs the last point; the time past the end
  /// time an arm may take to get there.
  ToleranceSpec path_tolerance{kDefaultPathTolerance, {}};
  ToleranceSpec goal_tolerance{kDefaultGoalTolerance, {}};
  double goal_time_tolerance = kDefaultGoalTimeTolerance;
  double arm_timeout = 3.0;          ///< s for every agent to accept (check and load) its goal
  double state_timeout = 0.5;        ///< s without a state report from a dispatched arm = lost
  /// s without a new joint state sample from a running arm = lost (its agent may still report).
  double sample_timeout = 0.5;
  double settle_timeout = 2.0;       ///< s after an abort to wait for every arm's final report
  double heartbeat_interval = 0.05;  ///< s between pings on an idle command stream
  double monitor_period = 0.01;      ///< s between checks of deadlines and silences
  double state_event_hz = 10.0;      ///< cap on onControllerState calls per agent for joint states alone
  double trace_hz = 20.0;            ///< planned-vs-actual trace points kept per arm per second
  std::size_t trace_max = 4000;      ///< trace points kept per arm
  bool validate_geometry = true;     ///< pre-flight runs the validator's collision sampling
  int validator_threads = 0;         ///< 0 = the hardware's
  /// Execution by dependencies: a segment may take segment_time_factor x its planned duration plus
  /// segment_time_margin s before the arm counts as stalled; a grasp or release gripper_allowance s more.
  double segment_time_factor = 3.0;
  double segment_time_margin = 2.0;
  double gripper_allowance = 5.0;
};

/// Per-request overrides of the config (unset: the config's value).
struct DispatchOptions {
  std::optional<double> start_delay;
  std::optional<double> start_tolerance;
  std::optional<ToleranceSpec> path_tolerance;
  std::optional<ToleranceSpec> goal_tolerance;
  std::optional<double> goal_time_tolerance;
  /// Multiplies every time of the plan (and its gripper events), for every arm alike so they stay
  /// coordinated: > 1 slower, < 1 faster. The pre-flight speed check runs on the scaled times, so a
  /// scale that would take any joint past its velocity limit is refused (the reason names the
  /// smallest scale that passes).
  double time_scale = 1.0;
  std::optional<bool> validate_geometry;
  /// "timed": one common start, the plan's timetable; "tpg": by dependencies (tpg_execution.h).
  std::string execution = "timed";
};

struct DispatchOutcome {
  bool accepted = false;
  int http_status = 0;  ///< 202 accepted; 409 busy, arms not ready or a goal refused; 422 bad plan; 504 no answer
  std::string error;    ///< "busy", "preflight", "refused", "timeout", "aborted" (empty when accepted)
  std::string reason;   ///< one clear sentence
  PreflightReport preflight;
  std::optional<DispatchStatus> status;  ///< the dispatch record, when one was created
};

struct AbortOutcome {
  bool had_dispatch = false;  ///< a dispatch was arming or running
  std::string dispatch_id;
  int controllers_notified = 0;
  std::int64_t at_us = 0;
};

enum class ReportResult { kOk, kStaleSession };

class DispatchService {
 public:
  explicit DispatchService(DispatchConfig config = {});
  ~DispatchService();
  DispatchService(const DispatchService&) = delete;
  DispatchService& operator=(const DispatchService&) = delete;

  const DispatchConfig& config() const { return config_; }
  const std::shared_ptr<const RobotLibrary>& library() const { return config_.library; }
  /// Server time: the steady clock in microseconds.
  std::int64_t now() const;

  void addListener(std::shared_ptr<DispatchListener> listener);
  void removeListener(const std::shared_ptr<DispatchListener>& listener);

  // ---- agent side (called by the routes) ----
  struct StreamHandle {
    std::shared_ptr<CommandStream> stream;
    std::string session;
  };
  /// Registers the robot's agent (replacing an older connection) and queues the hello event.
  StreamHandle openStream(const std::string& robot);
  /// The stream of `session` ended (the agent went away, or was replaced).
  void closeStream(const std::string& robot, const std::string& session, const std::string& reason);
  /// A state report; kStaleSession if `report.session` is not the robot's current stream.
  ReportResult report(const std::string& robot, const AgentReport& report);

  // ---- operator side ----
  std::vector<ControllerInfo> controllers() const;
  /// Pre-flight, arm every robot, start them together. Blocks until started or refused (at most about
  /// arm_timeout plus the validator's time). `origin` goes into the record.
  DispatchOutcome dispatch(const Plan& plan, const Scene& scene, const DispatchOptions& options = {},
                           const DispatchOrigin& origin = {});
  /// The pre-flight checks alone, against the registry as it is now: nothing is sent, nothing
  /// recorded (the dashboard's "Check" before "Start"; dispatch() checks again).
  PreflightReport check(const Plan& plan, const Scene& scene, const DispatchOptions& options = {}) const;
  /// Aborts every arm: sends abort to every connected agent, at once.
  AbortOutcome abort(const std::string& reason);
  /// The current dispatch, or the last one; nullopt before the first.
  std::optional<DispatchStatus> status(bool with_trace = false) const;

  /// Waits up to `period`, returning early (true) once shutdown() has begun; for long-lived streams.
  bool sleepUnlessStopping(std::chrono::microseconds period) const;

  /// Closes every agent stream and stops the monitor. Idempotent; the destructor calls it.
  void shutdown();

 private:
  struct ControllerEntry {
    ControllerInfo info;
    std::shared_ptr<CommandStream> stream;
    std::int64_t last_state_event_us = 0;
  };
  struct Run {
    DispatchStatus status;
    std::vector<ArmTrajectory> trajectories;  ///< parallel to status.arms
    std::vector<std::vector<TracePoint>> traces;  ///< parallel to status.arms
    std::vector<std::int64_t> last_trace_us;
    std::vector<std::int64_t> last_sample_us;  ///< server time a sample of the arm last arrived
    std::int64_t deadline_us = 0;
    std::int64_t settle_deadline_us = 0;
    std::optional<TpgRun> tpg;  ///< execution by dependencies
  };
  void monitorLoop();
  void abortLocked(const std::string& reason, DispatchState state);
  void finishLocked(DispatchState state, const std::string& reason);
  void finalizeLocked();
  void processSamplesLocked(std::size_t arm, const std::vector<JointSample>& samples);
  void processStatusLocked(std::size_t arm, const AgentReport& report);
  void checkArmsLocked();
  int pushToAllLocked(const std::string& event);
  DispatchStatus snapshotLocked(bool with_trace) const;
  int armIndexLocked(const std::string& robot) const;
  PreflightOptions preflightOptions(const DispatchOptions& options) const;
  /// Runs the checks; a plan that cannot be checked (or a bad option) fails plan_valid.
  PreflightReport runChecks(const Plan& plan, const Scene& scene, const DispatchOptions& options,
                            const std::vector<ControllerInfo>& snapshot) const;
  std::string newIdLocked();
  /// The record of a request refused before any goal went out; tells the listeners.
  /// A new dispatch's status: a fresh id, who asked, the plan's scene and planner, the options, now.
  DispatchStatus newStatusLocked(const Plan& plan, const DispatchOptions& options, const DispatchOrigin& origin,
                                 DispatchState state);
  void noteRefusedLocked(const Plan& plan, const DispatchOptions& options, const DispatchOrigin& origin,
                         const PreflightReport& report, const std::string& reason);
  bool allArmsDoneLocked() const;
  // dispatch() in steps (dispatch_service.cpp).
  bool beginRequestLocked(DispatchOutcome& outcome, std::vector<ControllerInfo>& snapshot);
  bool agentsUnchangedLocked(const std::vector<ControllerInfo>& snapshot, DispatchOutcome& outcome);
  void newRunLocked(const Plan& plan, const DispatchOptions& options, const DispatchOrigin& origin,
                    const PreflightReport& preflight);
  void armAndStartLocked(std::unique_lock<std::mutex>& lock, const DispatchOptions& options, DispatchOutcome& outcome);
  std::string armingRefusalLocked(bool& timed_out) const;
  void refuseArmedLocked(const std::string& refusal);
  // Execution by dependencies (dispatch_tpg.cpp).
  /// The plan's graph (its "tpg" field, else built), with the check "tpg_graph" added to `report`
  /// (segment speeds at the time scale included); nullopt when that check fails.
  std::optional<tpg::Graph> tpgGraph(const Plan& plan, const Scene& scene, const DispatchOptions& options,
                                     PreflightReport& report) const;
  void startTpgLocked(const Plan& plan, const tpg::Graph& graph, DispatchOutcome& outcome);
  /// Sends every step whose predecessors are done; finishes the dispatch when every step is.
  void releaseTpgLocked();
  void processTpgStatusLocked(std::size_t arm, const AgentReport& report);
  /// Aborts (and returns true) when a running step has taken longer than its allowance.
  bool checkTpgDeadlinesLocked();
  /// Arms waiting between steps when an abort comes have nothing to stop: done, cancelled.
  void settleIdleTpgArmsLocked();
  void fillTpgStatusLocked(DispatchStatus& status) const;
  /// Queues a listener call (under the lock); drainNotes() makes the calls, in order, outside it.
  void noteLocked(std::function<void(DispatchListener&)> call);
  void drainNotes();

  DispatchConfig config_;
  mutable std::mutex mutex_;
  mutable std::condition_variable cv_;  ///< mutable: sleepUnlessStopping() waits on it
  std::map<std::string, ControllerEntry> controllers_;
  std::vector<std::shared_ptr<DispatchListener>> listeners_;
  std::deque<std::function<void()>> pending_notes_;
  std::mutex notes_mutex_;  ///< held while draining, so listener calls never overlap or reorder
  std::optional<Run> run_;
  bool preflight_in_progress_ = false;
  std::uint64_t next_session_ = 1;
  std::uint64_t next_dispatch_ = 1;
  /// Random per service: dispatch ids stay unique across servers, so `db merge` can key on them.
  std::string id_tag_;
  bool stopping_ = false;
  std::thread monitor_;
};

}  // namespace dash::dispatch
