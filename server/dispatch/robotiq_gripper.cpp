#include "server/dispatch/robotiq_gripper.h"

#include <algorithm>

namespace dash::dispatch {

bool RobotiqGripper::connect(const std::string& host, int port, int timeout_ms, std::string& error) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    socket_ = connectTcp(host, port, timeout_ms);
    timeout_ms_ = timeout_ms;
    if (!socket_.valid()) {
      error = "cannot connect to the gripper at " + host + ":" + std::to_string(port);
      return false;
    }
  }
  return expectAck("SET ACT 1", error) && expectAck("SET GTO 1", error);
}

bool RobotiqGripper::connected() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return socket_.valid();
}

void RobotiqGripper::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  socket_.reset();
}

bool RobotiqGripper::command(const std::string& line, std::string& answer, std::string& error) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!socket_.valid()) {
    error = "the gripper is not connected";
    return false;
  }
  const std::string text = line + "\n";
  if (!writeAll(socket_.fd(), text.data(), text.size())) {
    socket_.reset();
    error = "the gripper connection dropped";
    return false;
  }
  const IoResult r = readLine(socket_.fd(), answer, timeout_ms_);
  if (r != IoResult::kOk) {
    socket_.reset();
    error = r == IoResult::kTimeout ? "the gripper did not answer '" + line + "'" : "the gripper connection dropped";
    return false;
  }
  return true;
}

bool RobotiqGripper::expectAck(const std::string& line, std::string& error) {
  std::string answer;
  if (!command(line, answer, error)) return false;
  if (answer != "ack") {
    error = "the gripper answered '" + answer + "' to '" + line + "'";
    return false;
  }
  return true;
}

bool RobotiqGripper::setPosition(int position, std::string& error) {
  return expectAck("SET POS " + std::to_string(std::clamp(position, 0, 255)), error);
}

}  // namespace dash::dispatch
