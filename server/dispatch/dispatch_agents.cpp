// DispatchService, agent side: the agents' streams and reports, the registry (dispatch_service.h).
#include <algorithm>

#include "server/dispatch/dispatch_service.h"
#include "server/dispatch/dispatch_service_util.h"

namespace dash::dispatch {

using namespace service_detail;

// ---------------------------------------------------------------- agents

DispatchService::StreamHandle DispatchService::openStream(const std::string& robot) {
  StreamHandle handle;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    handle.stream = std::make_shared<CommandStream>();
    if (stopping_) {
      handle.stream->close();
      return handle;
    }
    ControllerEntry& entry = controllers_[robot];
    const bool seen = !entry.info.robot.empty();
    if (entry.stream) entry.stream->close();
    if (entry.info.connected) {
      const ControllerInfo old = entry.info;
      noteLocked([old](DispatchListener& l) { l.onControllerDisconnected(old, "replaced by a new connection"); });
      const int arm = armIndexLocked(robot);
      if (arm >= 0 && isActive(run_->status.state) && !run_->status.arms[static_cast<std::size_t>(arm)].done) {
        auto& a = run_->status.arms[static_cast<std::size_t>(arm)];
        a.done = true;
        a.result = ResultCode::kFault;
        a.message = "the controller reconnected: its previous connection was lost";
        abortLocked(robot + ": the controller's connection was lost (it reconnected)", DispatchState::kAborted);
      }
    }
    entry.info.robot = robot;
    entry.info.session = "s" + std::to_string(next_session_++);
    entry.info.connected = true;
    entry.info.ready = false;
    entry.info.detail = "connected";
    entry.info.connected_since_us = now();
    entry.info.last_report_us = 0;
    if (seen) ++entry.info.reconnects;
    entry.stream = handle.stream;
    handle.session = entry.info.session;
    handle.stream->push(formatSse("hello", helloToJson({entry.info.session, now(), robot, steadyClockId()})));
    const ControllerInfo info = entry.info;
    noteLocked([info](DispatchListener& l) { l.onControllerConnected(info); });
  }
  drainNotes();
  return handle;
}

void DispatchService::closeStream(const std::string& robot, const std::string& session, const std::string& reason) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = controllers_.find(robot);
    if (it == controllers_.end() || it->second.info.session != session || !it->second.info.connected) return;
    ControllerEntry& entry = it->second;
    entry.info.connected = false;
    entry.info.ready = false;
    entry.info.detail = "disconnected: " + reason;
    if (entry.stream) entry.stream->close();
    entry.stream.reset();
    const ControllerInfo info = entry.info;
    noteLocked([info, reason](DispatchListener& l) { l.onControllerDisconnected(info, reason); });
    const int arm = armIndexLocked(robot);
    if (arm >= 0 && isActive(run_->status.state) && !run_->status.arms[static_cast<std::size_t>(arm)].done) {
      auto& a = run_->status.arms[static_cast<std::size_t>(arm)];
      a.done = true;
      a.result = ResultCode::kFault;
      a.message = "the controller disconnected (" + reason + ")";
      abortLocked(robot + ": the controller disconnected (" + reason + ")", DispatchState::kAborted);
    }
  }
  cv_.notify_all();
  drainNotes();
}

ReportResult DispatchService::report(const std::string& robot, const AgentReport& r) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = controllers_.find(robot);
    if (it == controllers_.end() || !it->second.info.connected || it->second.info.session != r.session) {
      return ReportResult::kStaleSession;
    }
    ControllerEntry& entry = it->second;
    ControllerInfo& info = entry.info;
    const bool changed = info.status != r.status || info.ready != r.ready || info.result != r.result ||
                         info.dispatch_id != r.dispatch_id || info.detail != r.detail || info.gripper != r.gripper ||
                         info.driver != r.driver || info.message != r.message;
    info.driver = r.driver;
    info.model = r.model;
    info.joint_names = r.joint_names;
    info.ready = r.ready;
    info.detail = r.detail;
    info.status = r.status;
    info.dispatch_id = r.dispatch_id;
    info.result = r.result;
    info.message = r.message;
    info.gripper = r.gripper;
    const std::int64_t t = now();
    info.last_report_us = t;
    if (!r.samples.empty()) info.last_sample = r.samples.back();
    const bool due = config_.state_event_hz > 0 &&
                     t - entry.last_state_event_us >= micros(1.0 / config_.state_event_hz);
    if (changed || due) {
      entry.last_state_event_us = t;
      const ControllerInfo copy = info;
      noteLocked([copy](DispatchListener& l) { l.onControllerState(copy); });
    }
    const int arm = armIndexLocked(robot);
    if (arm >= 0 && !run_->status.final) {
      processSamplesLocked(static_cast<std::size_t>(arm), r.samples);
      if (run_->tpg) {
        processTpgStatusLocked(static_cast<std::size_t>(arm), r);
      } else if (r.dispatch_id == run_->status.id) {
        processStatusLocked(static_cast<std::size_t>(arm), r);
      }
    }
  }
  cv_.notify_all();
  drainNotes();
  return ReportResult::kOk;
}

std::vector<ControllerInfo> DispatchService::controllers() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<ControllerInfo> out;
  for (const auto& [robot, entry] : controllers_) out.push_back(entry.info);
  return out;
}

// ---------------------------------------------------------------- dispatch

int DispatchService::armIndexLocked(const std::string& robot) const {
  if (!run_) return -1;
  for (std::size_t i = 0; i < run_->status.arms.size(); ++i) {
    if (run_->status.arms[i].robot == robot) return static_cast<int>(i);
  }
  return -1;
}

bool DispatchService::allArmsDoneLocked() const {
  return std::all_of(run_->status.arms.begin(), run_->status.arms.end(),
                     [](const ArmDispatchStatus& a) { return a.done; });
}

int DispatchService::pushToAllLocked(const std::string& event) {
  int n = 0;
  for (auto& [robot, entry] : controllers_) {
    if (entry.info.connected && entry.stream) {
      entry.stream->push(event);
      ++n;
    }
  }
  return n;
}

}  // namespace dash::dispatch
