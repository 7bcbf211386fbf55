#pragma once
// The controller agent: runs next to one arm (`dashbench controller`), connects to the dispatch
// server, takes its commands from a server-sent event stream (dispatch_protocol.h) and reports the
// arm's joint states and status back in batched POSTs (50 Hz while a goal is armed or running).
// It reconnects on its own after a dropped connection; if the connection drops while the arm is
// moving, it stops the arm first (the server aborts the other arms on its side). A server that
// refuses the token (HTTP 401 or 403) will not take it later either: the agent says so and gives up
// (fatalError()). Every goal's end is logged with its result.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "server/dispatch/arm_driver.h"

namespace dash::dispatch {

struct AgentOptions {
  std::string server_url;  ///< "http://host:port"
  std::string robot;       ///< the scene robot's id
  std::string token;       ///< sent as "Authorization: Bearer TOKEN"
  double sample_hz = 100.0;       ///< joint state samples per second
  double report_hz = 50.0;        ///< POSTs per second while a goal is armed or running
  double idle_report_hz = 10.0;   ///< POSTs per second otherwise
  double reconnect_delay = 0.25;  ///< s before reconnecting (doubles up to max_reconnect_delay)
  double max_reconnect_delay = 2.0;
  double stream_timeout = 1.0;    ///< s of silence on the stream (pings come every 50 ms) = lost server
  std::optional<double> drop_at;  ///< fault injection: s after a start, drop the connection once
  double drop_for = 0.5;          ///< s to stay away after that drop
  std::function<void(const std::string&)> log;  ///< progress lines (may be empty)
};

class ControllerAgent {
 public:
  ControllerAgent(AgentOptions options, ArmDriver& driver);
  ~ControllerAgent();
  ControllerAgent(const ControllerAgent&) = delete;
  ControllerAgent& operator=(const ControllerAgent&) = delete;

  void start();
  void stop();  ///< idempotent; the destructor calls it

  bool connected() const;
  int connections() const;  ///< command streams opened so far (1 + reconnections)
  /// Why the agent gave up (the server refused its token), or empty while it keeps going.
  std::string fatalError() const;
  /// Estimated server clock minus local steady clock, in microseconds.
  std::int64_t clockOffsetUs() const;

 private:
  void streamLoop();
  void reportLoop();
  bool handleEvent(const std::string& event, const std::string& data);
  void log(const std::string& line) const;
  void kick();  ///< report now (a status change)
  /// Gives up for good: the server refused the token (HTTP `status`).
  void refusedToken(int status);
  /// Logs the goal's end once, when the driver's status becomes final.
  void logGoalEnd(const DriverProgress& p, ArmStatus& logged);
  // reportLoop's steps.
  /// What one state report says, read together under the goal lock and the agent's lock.
  struct ReportSnapshot {
    DriverState state;
    DriverProgress progress;
    std::string session, dispatch_id;
    bool connected = false;
    bool synchronised = false;  ///< the clock offset to the server is known
    std::int64_t offset = 0;    ///< server time - local time, microseconds
  };
  /// Waits until `next_sample` (local steady microseconds), a kick or stop(); whether it was kicked.
  bool waitForSample(std::int64_t next_sample);
  ReportSnapshot snapshot(std::int64_t now, ArmStatus& logged);
  AgentReport report(const ReportSnapshot& s, const std::vector<JointSample>& samples);
  /// One round trip (local send t0, answer t1) and the server's time in its answer.
  void addOffsetSample(std::int64_t t0, std::int64_t t1, std::int64_t server_time);

  AgentOptions options_;
  ArmDriver& driver_;
  mutable std::mutex mutex_;
  /// Held while a goal is loaded (its id set and the driver's status changed together) and while a
  /// report reads them, so a report never pairs a new goal's id with the previous goal's status.
  std::mutex goal_mutex_;
  std::condition_variable cv_;
  std::atomic<bool> stopping_{false};
  bool connected_ = false;
  bool reconnect_ = false;  ///< the server called our session stale
  std::string session_;
  int connections_ = 0;
  std::string dispatch_id_;
  std::optional<std::int64_t> start_local_us_;  ///< local steady time of the current goal's start
  bool dropped_ = false;
  std::int64_t away_until_us_ = 0;
  bool kicked_ = false;
  std::string fatal_;
  // Clock offset: the estimate from the round trip with the smallest delay among the recent ones.
  std::int64_t offset_us_ = 0;
  bool offset_known_ = false;
  bool same_clock_ = false;  ///< the server runs on this machine (same steady clock): offset 0
  std::deque<std::pair<std::int64_t, std::int64_t>> offset_samples_;  ///< (rtt, offset)
  std::thread stream_thread_, report_thread_;
};

}  // namespace dash::dispatch
