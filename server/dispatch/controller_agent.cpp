#include "server/dispatch/controller_agent.h"

#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace dash::dispatch {

namespace {

constexpr std::size_t kOffsetWindow = 32;
constexpr std::size_t kMaxBatch = 500;  ///< samples kept while the server is unreachable
constexpr double kStableConnection = 2.0;  ///< s: a connection that lasted this long resets the backoff
/// Round trips measured before the agent calls itself ready: the hello's offset is off by the event's
/// delivery time (tens of milliseconds on a loaded machine), the best of a few round trips by at most
/// half the shortest round trip.
constexpr std::size_t kMinOffsetSamples = 3;

std::int64_t micros(double s) { return static_cast<std::int64_t>(s * 1e6); }

httplib::Headers authHeaders(const std::string& token) {
  return {{"Authorization", "Bearer " + token}};
}

}  // namespace

ControllerAgent::ControllerAgent(AgentOptions options, ArmDriver& driver)
    : options_(std::move(options)), driver_(driver) {}

ControllerAgent::~ControllerAgent() { stop(); }

void ControllerAgent::start() {
  stopping_ = false;
  stream_thread_ = std::thread([this] { streamLoop(); });
  report_thread_ = std::thread([this] { reportLoop(); });
}

void ControllerAgent::stop() {
  stopping_ = true;
  cv_.notify_all();
  if (stream_thread_.joinable()) stream_thread_.join();
  if (report_thread_.joinable()) report_thread_.join();
}

bool ControllerAgent::connected() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return connected_;
}

int ControllerAgent::connections() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return connections_;
}

std::int64_t ControllerAgent::clockOffsetUs() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return offset_us_;
}

std::string ControllerAgent::fatalError() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return fatal_;
}

void ControllerAgent::refusedToken(int status) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!fatal_.empty()) return;
    fatal_ = "the server at " + options_.server_url + " refused this agent's token (HTTP " + std::to_string(status) +
             "): the token file must hold the token of that server (the one `dashbench serve` uses); giving up";
  }
  log(fatalError());
  cv_.notify_all();
}

void ControllerAgent::logGoalEnd(const DriverProgress& p, ArmStatus& logged) {
  if (p.status == logged) return;
  logged = p.status;
  if (!isFinal(p.status)) return;
  std::string id;
  std::string took;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    id = dispatch_id_;
    if (start_local_us_) {
      char text[48];
      std::snprintf(text, sizeof text, " after %.2f s", (steadyMicros() - *start_local_us_) * 1e-6);
      took = text;
    }
  }
  const std::string result = p.status == ArmStatus::kSucceeded
                                 ? "succeeded"
                                 : std::string(armStatusName(p.status)) + ": " + resultCodeName(p.result) +
                                       (p.message.empty() ? "" : ": " + p.message);
  log("goal " + id + ": " + result + took);
}

void ControllerAgent::log(const std::string& line) const {
  if (options_.log) options_.log(options_.robot + ": " + line);
}

void ControllerAgent::kick() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    kicked_ = true;
  }
  cv_.notify_all();
}

bool ControllerAgent::handleEvent(const std::string& event, const std::string& data) {
  try {
    if (event == "hello") {
      const HelloMessage hello = parseHello(data);
      std::lock_guard<std::mutex> lock(mutex_);
      session_ = hello.session;
      connected_ = true;
      reconnect_ = false;
      ++connections_;
      same_clock_ = !hello.clock.empty() && hello.clock == steadyClockId();
      if (same_clock_) {  // on the server's machine: the same steady clock, nothing to estimate
        offset_us_ = 0;
        offset_known_ = true;
      } else if (!offset_known_) {
        offset_us_ = hello.server_time_us - steadyMicros();
        offset_known_ = true;
      }
      kicked_ = true;
      cv_.notify_all();
      log("connected (session " + hello.session + ")");
    } else if (event == "trajectory") {
      const TrajectoryCommand cmd = parseTrajectoryCommand(data);
      std::lock_guard<std::mutex> goal_lock(goal_mutex_);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        dispatch_id_ = cmd.dispatch_id;
        start_local_us_.reset();
      }
      std::string message;
      const ResultCode code = driver_.load(cmd.trajectory, cmd.limits, message);
      log("goal " + cmd.dispatch_id + ": " + (code == ResultCode::kSuccessful ? "armed" : std::string("refused: ") + resultCodeName(code) + ": " + message));
      kick();
    } else if (event == "start") {
      const StartCommand cmd = parseStartCommand(data);
      std::int64_t local = 0;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (cmd.dispatch_id != dispatch_id_) return true;
        local = cmd.start_time_us - offset_us_;
        start_local_us_ = local;
      }
      driver_.start(steadyFromMicros(local));
      log("goal " + cmd.dispatch_id + ": start in " + std::to_string((local - steadyMicros()) / 1000) + " ms");
      kick();
    } else if (event == "abort") {
      const AbortCommand cmd = parseAbortCommand(data);
      driver_.abort(cmd.reason.empty() ? "aborted by the server" : cmd.reason);
      log("abort: " + cmd.reason);
      kick();
    }
  } catch (const std::exception& e) {
    log("bad '" + event + "' event: " + e.what());
  }
  std::lock_guard<std::mutex> lock(mutex_);
  return !stopping_ && !reconnect_ && !(dropped_ && steadyMicros() < away_until_us_);
}

void ControllerAgent::streamLoop() {
  double delay = options_.reconnect_delay;
  const std::string path = "/api/controllers/" + options_.robot + "/stream";
  while (!stopping_ && fatalError().empty()) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      const std::int64_t wait = away_until_us_ - steadyMicros();
      if (wait > 0) cv_.wait_for(lock, std::chrono::microseconds(wait), [&] { return stopping_.load(); });
    }
    if (stopping_) break;
    httplib::Client client(options_.server_url);
    client.set_tcp_nodelay(true);
    client.set_decompress(false);
    client.set_connection_timeout(std::chrono::milliseconds(1000));
    client.set_read_timeout(std::chrono::microseconds(micros(options_.stream_timeout)));
    httplib::Headers headers = authHeaders(options_.token);
    headers.emplace("Accept", "text/event-stream");
    headers.emplace("Accept-Encoding", "identity");
    SseParser parser;
    int status = 0;
    const auto opened = std::chrono::steady_clock::now();
    auto result = client.Get(
        path, headers,
        [&](const httplib::Response& response) {
          status = response.status;
          return response.status == 200;
        },
        [&](const char* data, std::size_t size) {
          for (const SseEvent& e : parser.feed(data, size)) {
            if (!handleEvent(e.event, e.data)) return false;
          }
          std::lock_guard<std::mutex> lock(mutex_);
          return !stopping_ && !reconnect_ && !(dropped_ && steadyMicros() < away_until_us_);
        });
    bool was_connected = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      was_connected = connected_;
      connected_ = false;
      session_.clear();
      reconnect_ = false;
    }
    if (stopping_) break;
    const DriverProgress p = driver_.progress();
    if (p.status == ArmStatus::kArmed || p.status == ArmStatus::kExecuting) {
      driver_.abort("lost the connection to the server");
      log("lost the server while running a goal: arm stopped");
    }
    if (status == 401 || status == 403) {
      refusedToken(status);
      break;
    }
    if (was_connected) {
      log("disconnected from " + options_.server_url);
    } else if (status != 0 && status != 200) {
      log("the server refused the stream: HTTP " + std::to_string(status));
    } else {
      log("cannot reach " + options_.server_url + " (" + httplib::to_string(result.error()) + ")");
    }
    const double lasted = std::chrono::duration<double>(std::chrono::steady_clock::now() - opened).count();
    delay = lasted > kStableConnection ? options_.reconnect_delay : std::min(delay * 2.0, options_.max_reconnect_delay);
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, std::chrono::microseconds(micros(was_connected ? options_.reconnect_delay : delay)),
                 [&] { return stopping_.load(); });
  }
}

bool ControllerAgent::waitForSample(std::int64_t next_sample) {
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait_until(lock, std::chrono::steady_clock::time_point(std::chrono::microseconds(next_sample)),
                 [&] { return stopping_.load() || kicked_; });
  const bool kicked = kicked_;
  kicked_ = false;
  return kicked;
}

ControllerAgent::ReportSnapshot ControllerAgent::snapshot(std::int64_t now, ArmStatus& logged) {
  ReportSnapshot r;
  r.state = driver_.state();
  std::lock_guard<std::mutex> goal_lock(goal_mutex_);
  r.progress = driver_.progress();
  logGoalEnd(r.progress, logged);
  std::lock_guard<std::mutex> lock(mutex_);
  r.offset = offset_us_;
  r.synchronised = same_clock_ || offset_samples_.size() >= kMinOffsetSamples;
  // Fault injection: drop the connection once, drop_at seconds after the start.
  if (options_.drop_at && !dropped_ && start_local_us_ && r.progress.status == ArmStatus::kExecuting &&
      now - *start_local_us_ >= micros(*options_.drop_at)) {
    dropped_ = true;
    away_until_us_ = now + micros(options_.drop_for);
    connected_ = false;
    log("dropping the connection (--sim-drop-at)");
  }
  r.connected = connected_;
  r.session = session_;
  r.dispatch_id = dispatch_id_;
  return r;
}

AgentReport ControllerAgent::report(const ReportSnapshot& s, const std::vector<JointSample>& samples) {
  AgentReport report;
  report.session = s.session;
  report.driver = driver_.kind();
  report.model = driver_.model();
  report.joint_names = driver_.jointNames();
  report.ready = driver_.ready(report.detail);
  if (report.ready && !s.synchronised) {
    report.ready = false;
    report.detail = "measuring the clock offset to the server";
  }
  report.status = s.progress.status;
  report.dispatch_id = s.dispatch_id;
  report.result = s.progress.result;
  report.message = s.progress.message;
  report.gripper = driver_.gripperState();
  report.samples = samples;
  return report;
}

void ControllerAgent::addOffsetSample(std::int64_t t0, std::int64_t t1, std::int64_t server_time) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (same_clock_) return;
  offset_samples_.emplace_back(t1 - t0, server_time - (t0 + t1) / 2);
  if (offset_samples_.size() > kOffsetWindow) offset_samples_.pop_front();
  const auto best = std::min_element(offset_samples_.begin(), offset_samples_.end());
  offset_us_ = best->second;
  offset_known_ = true;
}

void ControllerAgent::reportLoop() {
  httplib::Client client(options_.server_url);
  client.set_tcp_nodelay(true);
  client.set_keep_alive(true);
  client.set_connection_timeout(std::chrono::milliseconds(500));
  client.set_read_timeout(std::chrono::milliseconds(1000));
  client.set_write_timeout(std::chrono::milliseconds(1000));
  const std::string path = "/api/controllers/" + options_.robot + "/state";
  const auto headers = authHeaders(options_.token);

  std::vector<JointSample> batch;
  ArmStatus logged = driver_.progress().status;
  DriverProgress last_sent;
  bool sent_any = false;
  std::int64_t next_sample = steadyMicros();
  std::int64_t last_post = 0;
  const std::int64_t sample_period = micros(1.0 / options_.sample_hz);
  while (!stopping_) {
    const bool kicked = waitForSample(next_sample);
    if (stopping_) break;
    const std::int64_t now = steadyMicros();
    if (now >= next_sample) next_sample = std::max(next_sample + sample_period, now);

    const ReportSnapshot s = snapshot(now, logged);
    if (s.state.valid) {
      const std::int64_t measured = s.state.stamp_us != 0 ? s.state.stamp_us : now;
      batch.push_back({measured + s.offset, s.state.q, s.state.qd});
      if (batch.size() > kMaxBatch) batch.erase(batch.begin());
    }
    if (!s.connected) continue;
    const DriverProgress& p = s.progress;
    const bool busy = p.status == ArmStatus::kArmed || p.status == ArmStatus::kExecuting;
    const double hz = busy ? options_.report_hz : options_.idle_report_hz;
    const bool changed = !sent_any || p.status != last_sent.status || p.result != last_sent.result;
    if (!kicked && !changed && now - last_post < micros(1.0 / hz)) continue;

    const AgentReport r = report(s, batch);
    const std::int64_t t0 = steadyMicros();
    auto res = client.Post(path, headers, agentReportToJson(r), "application/json");
    const std::int64_t t1 = steadyMicros();
    last_post = t1;
    if (!res) continue;  // unreachable: keep the samples for the next try
    if (res->status == 409) {  // our session is stale: reopen the stream
      std::lock_guard<std::mutex> lock(mutex_);
      reconnect_ = true;
      continue;
    }
    if (res->status == 401 || res->status == 403) {
      refusedToken(res->status);
      break;
    }
    if (res->status != 200) {
      log("state report refused: HTTP " + std::to_string(res->status) + " " + res->body);
      batch.clear();
      continue;
    }
    batch.clear();
    last_sent = p;
    sent_any = true;
    if (const auto server_time = parseServerTime(res->body)) addOffsetSample(t0, t1, *server_time);
  }
}

}  // namespace dash::dispatch
