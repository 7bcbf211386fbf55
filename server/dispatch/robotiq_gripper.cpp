#include "server/dispatch/robotiq_gripper.h"

#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <thread>

namespace dash::dispatch {

namespace {

using SteadyClock = std::chrono::steady_clock;

constexpr std::size_t kMaxAnswer = 64;  ///< a longer answer is not the URCap talking

bool isSpace(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

void skipLeadingSpace(std::string& s) {
  std::size_t i = 0;
  while (i < s.size() && isSpace(s[i])) ++i;
  s.erase(0, i);
}

/// "VAR 123" exactly (no trailing bytes): true with the value.
bool parseVarValue(const std::string& text, const std::string& var, int& value) {
  if (text.size() < var.size() + 2 || text.compare(0, var.size(), var) != 0 || text[var.size()] != ' ') return false;
  const std::string digits = text.substr(var.size() + 1);
  if (digits.empty() || digits.size() > 3 ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return false;
  }
  value = std::stoi(digits);
  return true;
}

/// The variable name of "VAR ..." / "VAR" (letters only).
std::string leadingWord(const std::string& text) {
  std::size_t i = 0;
  while (i < text.size() && std::isalpha(static_cast<unsigned char>(text[i]))) ++i;
  return text.substr(0, i);
}

}  // namespace

const char* robotiq::objectStatusText(int obj) {
  switch (obj) {
    case 0:
      return "still moving";
    case 1:
      return "stopped by an object while opening";
    case 2:
      return "stopped by an object while closing";
    case 3:
      return "reached the position without meeting an object";
    default:
      return "unknown object status";
  }
}

bool RobotiqGripper::connect(const std::string& host, int port, int connect_timeout_ms, std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  socket_ = connectTcp(host, port, connect_timeout_ms);
  pending_.clear();
  if (!socket_.valid()) {
    error = "cannot connect to the gripper URCap at " + host + ":" + std::to_string(port);
    return false;
  }
  return true;
}

bool RobotiqGripper::connected() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return socket_.valid();
}

void RobotiqGripper::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  dropLocked();
}

void RobotiqGripper::dropLocked() {
  socket_.reset();
  pending_.clear();
}

IoResult RobotiqGripper::fill(int timeout_ms) {
  if (!waitReadable(socket_.fd(), timeout_ms)) return IoResult::kTimeout;
  char buffer[256];
  const ssize_t k = ::recv(socket_.fd(), buffer, sizeof buffer, MSG_DONTWAIT);
  if (k < 0 && (errno == EAGAIN || errno == EINTR)) return IoResult::kOk;
  if (k <= 0) return IoResult::kClosed;
  pending_.append(buffer, static_cast<std::size_t>(k));
  return IoResult::kOk;
}

bool RobotiqGripper::readAck(std::string& answer, std::string& error) {
  const auto deadline = SteadyClock::now() + std::chrono::milliseconds(timings_.answer_timeout_ms);
  for (;;) {
    skipLeadingSpace(pending_);  // a newline some URCap versions put after an earlier answer
    if (pending_.size() >= 3) {
      answer = pending_.substr(0, 3);
      pending_.erase(0, 3);
      if (answer == "ack") return true;
      error = "answered '" + answer + "' instead of 'ack'";
      return false;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now()).count();
    if (left <= 0) {
      error = "no 'ack' within " + std::to_string(timings_.answer_timeout_ms) + " ms";
      return false;
    }
    if (fill(static_cast<int>(left)) == IoResult::kClosed) {
      error = "the gripper closed the connection";
      return false;
    }
  }
}

bool RobotiqGripper::readValue(std::string& answer, std::string& error) {
  const auto deadline = SteadyClock::now() + std::chrono::milliseconds(timings_.answer_timeout_ms);
  for (;;) {
    skipLeadingSpace(pending_);
    const std::size_t nl = pending_.find('\n');
    if (nl != std::string::npos) {
      answer = pending_.substr(0, nl);
      if (!answer.empty() && answer.back() == '\r') answer.pop_back();
      pending_.erase(0, nl + 1);
      return true;
    }
    if (pending_.size() > kMaxAnswer) {
      error = "an answer longer than " + std::to_string(kMaxAnswer) + " bytes";
      return false;
    }
    int value = 0;
    if (parseVarValue(pending_, leadingWord(pending_), value)) {
      // Complete unless more digits follow at once (the URCap sends its answer in one piece).
      const IoResult r = fill(timings_.value_grace_ms);
      if (r == IoResult::kTimeout || (r == IoResult::kClosed && !pending_.empty())) {
        answer = pending_;
        pending_.clear();
        return true;
      }
      if (r == IoResult::kClosed) break;
      continue;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now()).count();
    if (left <= 0) {
      error = "no answer within " + std::to_string(timings_.answer_timeout_ms) + " ms";
      return false;
    }
    if (fill(static_cast<int>(left)) == IoResult::kClosed) break;
  }
  error = "the gripper closed the connection";
  return false;
}

bool RobotiqGripper::exchange(const std::string& line, bool ack, std::string& answer, std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!socket_.valid()) {
    error = "the gripper is not connected";
    return false;
  }
  pending_.clear();  // nothing may be left from an earlier exchange
  const std::string text = line + "\n";
  bool ok = writeAll(socket_.fd(), text.data(), text.size());
  if (!ok) {
    error = "the gripper connection dropped";
  } else {
    ok = ack ? readAck(answer, error) : readValue(answer, error);
  }
  if (!ok) {
    error = "'" + line + "': " + error;
    dropLocked();  // out of step with the URCap: start over
  }
  return ok;
}

bool RobotiqGripper::set(const std::vector<std::pair<std::string, int>>& vars, std::string& error) {
  std::string line = "SET";
  for (const auto& [name, value] : vars) line += " " + name + " " + std::to_string(value);
  std::string answer;
  return exchange(line, true, answer, error);
}

std::optional<int> RobotiqGripper::get(const std::string& var, std::string& error) {
  std::string answer;
  if (!exchange("GET " + var, false, answer, error)) return std::nullopt;
  int value = 0;
  if (!parseVarValue(answer, var, value)) {
    error = "'GET " + var + "' answered '" + answer + "'";
    close();
    return std::nullopt;
  }
  return value;
}

bool RobotiqGripper::waitFor(const std::string& var, int value, int timeout_ms, const std::function<bool()>& cancelled,
                             std::string& error) {
  const auto deadline = SteadyClock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    const std::optional<int> v = get(var, error);
    if (!v) return false;
    if (*v == value) return true;
    if (cancelled && cancelled()) {
      error = "cancelled while waiting for " + var + " " + std::to_string(value);
      return false;
    }
    if (SteadyClock::now() >= deadline) {
      error = var + " stayed " + std::to_string(*v) + ", not " + std::to_string(value) + ", for " +
              std::to_string(timeout_ms) + " ms";
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(timings_.poll_ms));
  }
}

bool RobotiqGripper::activate(const std::function<bool()>& cancelled, std::string& error) {
  const int timeout = timings_.activation_timeout_ms;
  if (!set({{"ACT", 0}}, error) || !set({{"ATR", 0}}, error)) return false;
  if (!waitFor("STA", 0, timeout, cancelled, error)) {
    error = "reset: " + error;
    return false;
  }
  if (!set({{"ACT", 1}}, error)) return false;
  if (!waitFor("STA", robotiq::kActive, timeout, cancelled, error)) {
    error = "activation: " + error;
    return false;
  }
  return true;
}

RobotiqGripper::MoveResult RobotiqGripper::move(int position, int speed, int force,
                                                const std::function<bool()>& cancelled) {
  MoveResult r;
  const int pos = std::clamp(position, 0, 255);
  if (!set({{"POS", pos}, {"SPE", std::clamp(speed, 0, 255)}, {"FOR", std::clamp(force, 0, 255)}, {"GTO", 1}},
           r.error)) {
    return r;
  }
  const auto deadline = SteadyClock::now() + std::chrono::milliseconds(timings_.move_timeout_ms);
  if (!waitFor("PRE", pos, timings_.move_timeout_ms, cancelled, r.error)) return r;
  for (;;) {
    const std::optional<int> obj = get("OBJ", r.error);
    if (!obj) return r;
    if (*obj != static_cast<int>(robotiq::ObjectStatus::kMoving)) {
      r.obj = *obj;
      break;
    }
    if (cancelled && cancelled()) {
      r.error = "cancelled while the fingers moved";
      return r;
    }
    if (SteadyClock::now() >= deadline) {
      r.error = "still moving " + std::to_string(timings_.move_timeout_ms) + " ms after the command";
      return r;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(timings_.poll_ms));
  }
  const std::optional<int> final_pos = get("POS", r.error);
  if (!final_pos) return r;
  r.position = *final_pos;
  r.ok = true;
  return r;
}

}  // namespace dash::dispatch
