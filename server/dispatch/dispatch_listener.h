#pragma once
// Hooks for the server around a DispatchService: persist dispatches (the results database), push them
// to the dashboard. Every method has an empty default. Calls come from the service's threads (HTTP
// workers and its monitor), never while the service holds its lock, in the order things happened
// for any one dispatch; keep them short and do not call DispatchService::dispatch() from them.
#include <string>

#include "server/dispatch/controller_info.h"
#include "server/dispatch/dispatch_status.h"
#include "server/dispatch/preflight.h"

namespace dash::dispatch {

class DispatchListener {
 public:
  virtual ~DispatchListener() = default;
  /// An agent opened its command stream (a first connection or a reconnection).
  virtual void onControllerConnected(const ControllerInfo& /*controller*/) {}
  /// Its stream closed, or it went silent, or another connection for the same robot replaced it.
  virtual void onControllerDisconnected(const ControllerInfo& /*controller*/, const std::string& /*reason*/) {}
  /// Its status, readiness or result changed; also its joint state, at most state_event_hz per agent.
  virtual void onControllerState(const ControllerInfo& /*controller*/) {}
  /// A dispatch request was checked (passed or not). `dispatch_id` is empty if it was refused.
  virtual void onPreflight(const PreflightReport& /*report*/, const std::string& /*dispatch_id*/) {}
  /// A request was refused before any goal was sent (a failed pre-flight check, or an arm that went
  /// away during the checks). `record` is final, state kRefused, with its own id; its arms are the
  /// plan's robots, never started (status idle, not done). Follows onPreflight(report, "").
  virtual void onDispatchRefused(const DispatchStatus& /*record*/, const PreflightReport& /*report*/) {}
  /// Every arm accepted its goal and the common start time was sent.
  virtual void onDispatchStarted(const DispatchStatus& /*status*/) {}
  /// The dispatch was aborted (on request, a deviation, a fault or a lost agent); arms' results may
  /// still arrive: onDispatchFinished follows with the final record.
  virtual void onDispatchAborted(const DispatchStatus& /*status*/, const std::string& /*reason*/) {}
  /// The final record of a dispatch (succeeded, failed, aborted or refused), once per dispatch.
  virtual void onDispatchFinished(const DispatchStatus& /*status*/) {}
};

}  // namespace dash::dispatch
