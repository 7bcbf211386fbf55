#include "sim_gripper.h"

#include <algorithm>
#include <sstream>
#include <utility>

#include "server/dispatch/dispatch_types.h"

namespace dash::dispatch::test {

namespace {

/// "SET A 1 B 2" -> {(A, 1), (B, 2)}; empty if malformed.
std::vector<std::pair<std::string, int>> setVars(const std::string& line) {
  std::vector<std::pair<std::string, int>> vars;
  std::istringstream in(line.substr(4));
  std::string name, value;
  while (in >> name) {
    if (!(in >> value) || value.empty() || value.size() > 3 ||
        !std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return {};
    }
    vars.emplace_back(name, std::stoi(value));
  }
  return vars;
}

}  // namespace

SimGripper::SimGripper(SimGripperOptions options) : options_(options) {
  listener_ = listenTcp("127.0.0.1", 0);
  port_ = boundPort(listener_);
  thread_ = std::thread([this] { loop(); });
}

SimGripper::~SimGripper() {
  stopping_ = true;
  if (thread_.joinable()) thread_.join();
}

std::vector<SimGripper::Command> SimGripper::commands() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return commands_;
}

std::vector<std::string> SimGripper::sets() const {
  std::vector<std::string> out;
  for (const Command& c : commands()) {
    if (c.line.rfind("SET ", 0) == 0) out.push_back(c.line);
  }
  return out;
}

bool SimGripper::activated() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return act_ == 1 && steadyMicros() - act_us_ >= static_cast<std::int64_t>(options_.activation_delay * 1e6);
}

void SimGripper::setObjectPresent(bool present) {
  std::lock_guard<std::mutex> lock(mutex_);
  options_.object = present;
}

void SimGripper::kill() { dead_ = true; }

int SimGripper::positionLocked(std::int64_t now_us, int* obj) const {
  if (!moved_) {
    if (obj != nullptr) *obj = 0;
    return from_;
  }
  const bool closing = requested_ > from_;
  int end = requested_;
  bool blocked = false;
  if (closing && options_.object && options_.object_position > from_ && options_.object_position < requested_) {
    end = options_.object_position;
    blocked = true;
  }
  const double needed = options_.stroke_time * std::abs(end - from_) / 255.0;
  const double elapsed = (now_us - move_us_) * 1e-6;
  if (elapsed >= needed) {
    if (obj != nullptr) *obj = blocked ? 2 : 3;
    return end;
  }
  if (obj != nullptr) *obj = 0;
  return from_ + static_cast<int>(std::lround((end - from_) * elapsed / std::max(needed, 1e-9)));
}

std::string SimGripper::answerLocked(const std::string& line, std::int64_t now_us) {
  const bool active = act_ == 1 && now_us - act_us_ >= static_cast<std::int64_t>(options_.activation_delay * 1e6);
  if (line.rfind("SET ", 0) == 0) {
    const auto vars = setVars(line);
    if (vars.empty()) return "?";
    const int now_at = positionLocked(now_us, nullptr);  // before POS changes the move in progress
    bool go = false;
    for (const auto& [name, value] : vars) {
      if (name == "ACT") {
        if (value == 1 && act_ != 1) act_us_ = now_us;
        act_ = value == 1 ? 1 : 0;
      } else if (name == "POS") {
        requested_ = std::clamp(value, 0, 255);
      } else if (name == "GTO") {
        go = value == 1;
      } else if (name != "SPE" && name != "FOR" && name != "ATR") {
        return "?";
      }
    }
    if (go && active) {  // a move starts from where the fingers are now
      from_ = now_at;
      move_us_ = now_us;
      moved_ = true;
    }
    return "ack";
  }
  if (line.rfind("GET ", 0) != 0) return "?";
  const std::string var = line.substr(4);
  int obj = 0;
  const int position = positionLocked(now_us, &obj);
  int value = 0;
  if (var == "STA") {
    value = act_ == 0 ? 0 : active ? 3 : 1;
  } else if (var == "ACT") {
    value = act_;
  } else if (var == "PRE") {
    value = moved_ ? requested_ : 0;
  } else if (var == "POS") {
    value = position;
  } else if (var == "OBJ") {
    value = obj;
  } else if (var == "GTO") {
    value = moved_ ? 1 : 0;
  } else {
    return "?";
  }
  return var + " " + std::to_string(value);
}

void SimGripper::loop() {
  while (!stopping_ && !dead_) {
    Socket client = acceptTcp(listener_, 50);
    if (!client.valid()) continue;
    while (!stopping_ && !dead_) {
      std::string line;
      const IoResult r = readLine(client.fd(), line, 50);
      if (r == IoResult::kTimeout) continue;
      if (r == IoResult::kClosed) break;
      std::string answer;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        const std::int64_t now = steadyMicros();
        answer = answerLocked(line, now);
        commands_.push_back({line, answer, now});
      }
      // As the URCap: no newline after "ack" or after a GET's value.
      if (!writeAll(client.fd(), answer.data(), answer.size())) break;
    }
  }
  listener_.reset();  // dead: nothing listens any more
}

}  // namespace dash::dispatch::test
