#pragma once
// EventHub: the server's live updates, fanned out to every server-sent-event stream. Producers (the
// batch manager's progress callbacks, the database watcher) publish small JSON messages; each stream
// waits for messages newer than the last one it sent. A bounded ring of recent messages means a slow
// stream never holds memory: if it falls too far behind it is told so ("resync") and the page
// refetches. Thread safe.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

namespace dash::http {

struct HubMessage {
  std::uint64_t seq = 0;
  std::string event;  ///< SSE event name: "batch", "batches", "run", "sizes"
  std::string key;    ///< what it is about (a batch id, a run uuid), for filtering
  std::string data;   ///< one line of JSON
};

struct HubWait {
  std::vector<HubMessage> messages;
  bool gap = false;     ///< messages after `after` were dropped from the ring before this wait
  bool closed = false;  ///< the hub is shutting down: end the stream
};

class EventHub {
 public:
  explicit EventHub(std::size_t capacity = 4096);

  /// Appends a message and wakes the waiting streams; returns its sequence number.
  std::uint64_t publish(std::string event, std::string key, std::string data);
  /// Messages with seq > `after`, waiting up to `timeout` for the first one.
  HubWait waitAfter(std::uint64_t after, std::chrono::milliseconds timeout) const;
  std::uint64_t lastSeq() const;
  /// Wakes every waiter; later waits return closed at once.
  void close();

  /// One SSE frame: "id: N\nevent: NAME\ndata: JSON\n\n".
  static std::string formatSse(const HubMessage& message);

 private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  mutable std::condition_variable cv_;
  std::deque<HubMessage> ring_;
  std::uint64_t next_seq_ = 1;
  bool closed_ = false;
};

}  // namespace dash::http
