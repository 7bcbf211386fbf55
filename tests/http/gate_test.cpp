// GatedServer on its own, with tiny limits: what it does when the workers are all busy and when the
// waiting connections hold too many bytes.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <thread>
#include <vector>

#include "tests/http/raw_connection.h"

// clang-format off
#include "server/http/gated_server.h"  // includes httplib.h
// clang-format on

namespace dash::http::testing {
namespace {

class Gate {
 public:
  explicit Gate(GateOptions options) : server_(options) {
    server_.Get("/slow", [this](const httplib::Request&, httplib::Response& res) {
      release_.wait();
      res.set_content("done", "text/plain");
    });
    server_.Post("/echo", [](const httplib::Request& req, httplib::Response& res) {
      res.set_content(std::to_string(req.body.size()), "text/plain");
    });
    port_ = server_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { server_.listen_after_bind(); });
  }
  ~Gate() {
    release();  // a failed test must not leave a handler blocked
    server_.stop();
    thread_.join();
    server_.stopGate();
  }
  int port() const { return port_; }
  const GatedServer& server() const { return server_; }
  void release() {
    if (!released_flag_.exchange(true)) released_.set_value();
  }

 private:
  std::atomic<bool> released_flag_{false};
  std::promise<void> released_;
  std::shared_future<void> release_ = released_.get_future().share();
  GatedServer server_;
  int port_ = 0;
  std::thread thread_;
};

int statusOf(int port, const std::string& request) {
  RawConnection c(port);
  c.send(request);
  return RawConnection::statusOf(c.readUntil("\r\n\r\n", 5));
}

TEST(GatedServer, RefusesWhenEveryWorkerAndQueueSlotIsTaken) {
  GateOptions options;
  options.workers = 1;
  options.max_queued = 1;
  Gate gate(options);
  const std::string slow = "GET /slow HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
  std::vector<std::future<int>> answers;
  for (std::size_t i = 1; i <= 2; ++i) {  // one runs (blocked until released), one waits in the queue
    answers.push_back(std::async(std::launch::async, [&] { return statusOf(gate.port(), slow); }));
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (gate.server().inFlight() < i && std::chrono::steady_clock::now() < end) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_EQ(gate.server().inFlight(), i);
  }
  EXPECT_EQ(statusOf(gate.port(), slow), 503);
  gate.release();
  for (auto& a : answers) EXPECT_EQ(a.get(), 200);
  EXPECT_EQ(statusOf(gate.port(), slow), 200) << "free again";
}

TEST(GatedServer, DropsTheOldestWhenWaitingConnectionsHoldTooMuch) {
  GateOptions options;
  options.max_buffered_bytes = 100 * 1024;
  const Gate gate(options);
  const std::string head = "POST /echo HTTP/1.1\r\nHost: x\r\nContent-Length: 70000\r\n\r\n";
  RawConnection first(gate.port());
  first.send(head + std::string(60000, 'a'));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  RawConnection second(gate.port());
  second.send(head + std::string(60000, 'b'));
  EXPECT_EQ(first.readAll(5), "") << "dropped: closed without an answer";
  second.send(std::string(10000, 'b'));
  const std::string answer = second.readUntil("70000", 5);
  EXPECT_EQ(RawConnection::statusOf(answer), 200);
  EXPECT_NE(answer.find("70000"), std::string::npos);
}

}  // namespace
}  // namespace dash::http::testing
