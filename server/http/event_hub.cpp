#include "server/http/event_hub.h"

namespace dash::http {

EventHub::EventHub(std::size_t capacity) : capacity_(capacity) {}

std::uint64_t EventHub::publish(std::string event, std::string key, std::string data) {
  std::uint64_t seq = 0;
  {
    std::lock_guard lock(mutex_);
    seq = next_seq_++;
    ring_.push_back(HubMessage{.seq = seq, .event = std::move(event), .key = std::move(key), .data = std::move(data)});
    while (ring_.size() > capacity_) ring_.pop_front();
  }
  cv_.notify_all();
  return seq;
}

HubWait EventHub::waitAfter(std::uint64_t after, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  cv_.wait_for(lock, timeout, [&] { return closed_ || next_seq_ - 1 > after; });
  HubWait out;
  out.closed = closed_;
  if (ring_.empty()) return out;
  out.gap = ring_.front().seq > after + 1 && next_seq_ - 1 > after;
  for (const HubMessage& m : ring_) {
    if (m.seq > after) out.messages.push_back(m);
  }
  return out;
}

std::uint64_t EventHub::lastSeq() const {
  std::lock_guard lock(mutex_);
  return next_seq_ - 1;
}

void EventHub::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  cv_.notify_all();
}

std::string EventHub::formatSse(const HubMessage& message) {
  return "id: " + std::to_string(message.seq) + "\nevent: " + message.event + "\ndata: " + message.data + "\n\n";
}

}  // namespace dash::http
