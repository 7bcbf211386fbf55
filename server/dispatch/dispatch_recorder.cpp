#include "server/dispatch/dispatch_recorder.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "server/dispatch/dispatch_json.h"
#include "server/dispatch/json_util.h"

namespace dash::dispatch {

namespace {

using json_util::Json;

std::int64_t unixMillisNow() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

/// The wall clock of a steady-clock stamp (the service's clock), by the offset between the two now.
std::string isoOfSteady(std::int64_t steady_us) {
  if (steady_us == 0) return "";
  return log::isoTimeFromUnixMillis(unixMillisNow() - (steadyMicros() - steady_us) / 1000);
}

/// The stored steps of an arm (JSON text), null when there are none or they do not parse.
Json segmentsOrNull(const std::string& text) {
  if (text.empty()) return nullptr;
  Json parsed = Json::parse(text, nullptr, false);
  return parsed.is_discarded() ? Json(nullptr) : parsed;
}

Json recordToJson(const log::DispatchRecord& r) {
  Json arms = Json::array();
  for (const log::DispatchArmRecord& a : r.arms) {
    arms.push_back({{"robot", a.robot},
                    {"driver", a.driver},
                    {"status", a.status},
                    {"result", a.result.empty() ? Json(nullptr)
                                                : Json{{"code", a.result_code}, {"name", a.result}, {"message", a.message}}},
                    {"message", a.message},
                    {"duration", a.duration},
                    {"max_deviation", a.max_deviation},
                    {"samples", a.samples},
                    {"segments", segmentsOrNull(a.segments)}});
  }
  Json preflight = nullptr;
  if (!r.preflight.empty()) preflight = Json::parse(r.preflight, nullptr, false);
  if (preflight.is_discarded()) preflight = nullptr;
  return {{"id", r.id},
          {"created", r.created},
          {"started", r.started.empty() ? Json(nullptr) : Json(r.started)},
          {"ended", r.ended.empty() ? Json(nullptr) : Json(r.ended)},
          {"state", r.state},
          {"reason", r.reason},
          {"run_id", r.run_uuid},
          {"scene", r.scene},
          {"planner", r.planner},
          {"requested_by", r.requested_by},
          {"client", r.client},
          {"execution", r.execution},
          {"time_scale", r.time_scale},
          {"duration", r.duration},
          {"elapsed", r.elapsed},
          {"preflight", preflight},
          {"arms", arms}};
}

}  // namespace

DispatchRecorder::DispatchRecorder(const std::string& db_path) : store_(db_path) {}

log::DispatchRecord DispatchRecorder::toRecord(const DispatchStatus& s, const std::string& preflight_json) {
  log::DispatchRecord r;
  r.id = s.id;
  r.created = s.created_unix_ms != 0 ? log::isoTimeFromUnixMillis(s.created_unix_ms) : isoOfSteady(s.created_us);
  r.started = isoOfSteady(s.start_time_us);
  r.ended = s.final ? isoOfSteady(s.end_time_us != 0 ? s.end_time_us : steadyMicros()) : "";
  r.state = dispatchStateName(s.state);
  r.reason = s.reason;
  r.run_uuid = s.origin.run_id;
  r.scene = s.scene;
  r.planner = s.planner;
  r.requested_by = s.origin.requested_by.empty() ? "token holder" : s.origin.requested_by;
  r.client = s.origin.client;
  r.time_scale = s.time_scale;
  r.execution = s.execution;
  r.duration = s.duration;
  r.elapsed = s.start_time_us != 0 ? std::max(0.0, s.elapsed) : 0.0;
  r.preflight = preflight_json;
  for (const ArmDispatchStatus& a : s.arms) {
    log::DispatchArmRecord arm;
    arm.robot = a.robot;
    arm.driver = a.driver;
    arm.status = armStatusName(a.status);
    // An arm that never took its goal (refused before arming, or still arming) has no result yet.
    const bool started = a.done || a.status != ArmStatus::kIdle;
    arm.result = started ? resultCodeName(a.result) : "";
    arm.result_code = static_cast<int>(a.result);
    arm.message = a.message;
    arm.duration = a.duration;
    arm.max_deviation = a.max_deviation;
    arm.samples = a.samples;
    if (s.execution == "tpg") arm.segments = segmentsToJson(a.segments);
    r.arms.push_back(std::move(arm));
  }
  return r;
}

void DispatchRecorder::save(const log::DispatchRecord& record) {
  try {
    store_.save(record);
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(mutex_);
    last_error_ = "dispatch " + record.id + " was not recorded: " + e.what();
    std::fprintf(stderr, "dashbench: %s\n", last_error_.c_str());
  }
}

void DispatchRecorder::onPreflight(const PreflightReport& report, const std::string& dispatch_id) {
  if (dispatch_id.empty()) return;  // refused: onDispatchRefused brings the record
  std::lock_guard<std::mutex> lock(mutex_);
  preflight_[dispatch_id] = preflightToJson(report);
}

void DispatchRecorder::onDispatchRefused(const DispatchStatus& record, const PreflightReport& report) {
  save(toRecord(record, preflightToJson(report)));
}

void DispatchRecorder::onDispatchStarted(const DispatchStatus& status) {
  std::string preflight;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    preflight = preflight_[status.id];
  }
  save(toRecord(status, preflight));
}

void DispatchRecorder::onDispatchFinished(const DispatchStatus& status) {
  std::string preflight;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = preflight_.find(status.id);
    if (it != preflight_.end()) {
      preflight = it->second;
      preflight_.erase(it);
    }
  }
  save(toRecord(status, preflight));
}

std::string DispatchRecorder::historyJson(int limit, int offset) const {
  Json list = Json::array();
  for (const log::DispatchRecord& r : store_.list(limit, offset)) list.push_back(recordToJson(r));
  return Json{{"dispatches", list}, {"total", store_.count()}, {"limit", limit}, {"offset", offset}}.dump();
}

std::string DispatchRecorder::recordJson(const std::string& id) const {
  const auto r = store_.get(id);
  return r ? recordToJson(*r).dump() : "";
}

std::string DispatchRecorder::lastError() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_error_;
}

}  // namespace dash::dispatch
