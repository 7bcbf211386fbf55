#pragma once
// Shared fixtures of the dispatch tests: a small valid multi-arm scene and plan (the contract's
// pick-and-place arm plus UR5e arms far away moving between two configurations), a dispatch server on
// loopback, in-process agents (simulated arms, a UR agent with the simulated UR robot and gripper), and
// `dashbench controller` child processes.
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "engine/plan/plan.h"
#include "engine/robots/robot_model.h"
#include "engine/scene/scene.h"
#include "server/dispatch/controller_agent.h"
#include "server/dispatch/dispatch_recorder.h"
#include "server/dispatch/dispatch_service.h"
#include "server/dispatch/sim_driver.h"
#include "server/dispatch/ur_driver.h"
#include "sim_ur_robot.h"
#include "tests/common/child_process.h"
#include "tests/common/robot_library.h"

namespace httplib {
class Server;
}

namespace dash::dispatch::test {

inline constexpr const char* kToken = "test-token-3141";

// Settings that keep the tests independent of the machine's load (a loaded 2-core machine can keep a
// thread off the CPU for tens of milliseconds): the robot's keep-alive read timeout and the UR
// driver's joint state staleness bound, well above such pauses. The defaults (100 ms, 26 ms) are for
// a dedicated PC next to the robot; the checks themselves are the same.
inline constexpr int kLoadProofReadTimeoutMs = 1000;
inline constexpr int kLoadProofStaleMs = 500;
/// Server timeouts for silent agents and arms without joint states, likewise.
inline constexpr double kLoadProofStateTimeout = 1.5;
/// A path tolerance for tests about protocols and faults rather than tracking (rad): a timing error of
/// a loaded machine (tens of milliseconds at up to 3 rad/s) stays far inside it.
inline constexpr double kLoadProofPathTolerance = 0.5;

using dash::test::library;  // the robot models of data/robots (tests/common/robot_library.h)
/// The contract's pick-and-place scene (ur5e_0 picks obj_0) plus `extra_arms` UR5e arms at x = 2.5,
/// -2.5, ... m, clear of everything.
Scene multiArmScene(int extra_arms);
/// ur5e_0 follows the contract's example plan (grasp at 1.39 s, release at 2.48 s, makespan 3.38 s);
/// every other arm goes home -> offset configuration -> home.
Plan multiArmPlan(const Scene& scene);
std::string sceneJson(const Scene& scene);
std::string planJson(const Plan& plan);
/// {"plan": ..., "scene": ..., "options": {...}} (options_json: an object's text, or empty).
std::string dispatchBody(const Plan& plan, const Scene& scene, const std::string& options_json = "");
JointVector homeOf(const Scene& scene, const std::string& robot);

/// The dispatch service mounted on an httplib server on 127.0.0.1 (any free port); with `db_path`,
/// a DispatchRecorder writes every dispatch there and serves the history routes.
class TestServer {
 public:
  explicit TestServer(DispatchConfig config = {}, const std::string& db_path = "");
  ~TestServer();
  DispatchService& service() { return *service_; }
  DispatchRecorder* recorder() { return recorder_.get(); }
  std::string url() const { return "http://127.0.0.1:" + std::to_string(port_); }
  int port() const { return port_; }

 private:
  std::unique_ptr<DispatchService> service_;
  std::shared_ptr<DispatchRecorder> recorder_;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  int port_ = 0;
};

struct HttpReply {
  int status = 0;  ///< 0: no answer
  std::string body;
};
HttpReply httpPost(const std::string& url, const std::string& path, const std::string& body,
                   const std::string& token = kToken);
HttpReply httpGet(const std::string& url, const std::string& path, const std::string& token = kToken);
/// Reads the server-sent events of GET `path` (with the token) until `enough` says so or `timeout_s`
/// passes; returns the events as (name, data).
std::vector<std::pair<std::string, std::string>> readEvents(
    const std::string& url, const std::string& path,
    const std::function<bool(const std::vector<std::pair<std::string, std::string>>&)>& enough, double timeout_s);

/// A simulated arm and its agent, in this process.
struct SimArm {
  std::unique_ptr<SimDriver> driver;
  std::unique_ptr<ControllerAgent> agent;

  SimArm() = default;
  SimArm(SimArm&&) = default;
  SimArm& operator=(SimArm&& other) {
    if (this != &other) {
      reset();
      driver = std::move(other.driver);
      agent = std::move(other.agent);
    }
    return *this;
  }
  ~SimArm() { reset(); }
  void reset() {  // the agent first: it uses the driver
    agent.reset();
    driver.reset();
  }
};
SimArm startSimArm(const std::string& url, const std::string& robot, const JointVector& initial,
                   SimDriverOptions sim = {}, AgentOptions agent = {}, const std::string& token = kToken);

/// A UR agent (UrDriver on free ports) with the simulated UR robot and gripper, in this process.
struct UrArm {
  std::unique_ptr<SimGripper> gripper;
  std::unique_ptr<UrDriver> driver;
  std::unique_ptr<SimUrRobot> robot;
  std::unique_ptr<ControllerAgent> agent;

  UrArm() = default;
  UrArm(UrArm&&) = default;
  UrArm& operator=(UrArm&& other) {
    if (this != &other) {
      reset();
      gripper = std::move(other.gripper);
      driver = std::move(other.driver);
      robot = std::move(other.robot);
      agent = std::move(other.agent);
    }
    return *this;
  }
  ~UrArm() { reset(); }
  void reset() {
    agent.reset();
    robot.reset();
    driver.reset();
    gripper.reset();
  }
};
struct UrArmSetup {
  SimGripperOptions gripper;
  SimUrRobotOptions robot;  ///< its `initial` is set from startUrArm's
  double state_stale_after = kLoadProofStaleMs * 1e-3;
};
UrArm startUrArm(const std::string& url, const std::string& robot, const JointVector& initial,
                 AgentOptions agent = {}, UrArmSetup setup = {});

/// Polls `condition` every 5 ms until true or `timeout` passes; returns the last value.
bool waitFor(const std::function<bool()>& condition, double timeout_s);
/// Every robot listed is connected and ready in the registry.
bool controllersReady(DispatchService& service, const std::vector<std::string>& robots);
/// The dispatch became final (succeeded, failed, aborted or refused).
std::optional<DispatchStatus> waitFinal(DispatchService& service, double timeout_s);
const ArmDispatchStatus* armStatus(const DispatchStatus& status, const std::string& robot);

/// Free TCP ports on 127.0.0.1 (bound then released).
std::vector<int> freePorts(int count);

/// `dashbench ARGS...` as child processes (tests/common/child_process.h).
using dash::test::ChildProcess;
using dash::test::dashbenchCommand;

std::string writeTokenFile(const std::string& name, const std::string& token = kToken);

/// `dashbench controller --driver ur` as a child process, with the simulated UR robot and its gripper
/// in this process on free ports. Members are destroyed agent first (it talks to the robot).
struct CliUrArm {
  std::unique_ptr<SimGripper> gripper;
  std::unique_ptr<SimUrRobot> robot;
  std::unique_ptr<ChildProcess> agent;

  void reset() {  // the agent first, as the destructor does
    agent.reset();
    robot.reset();
    gripper.reset();
  }
};
/// `setup`: the simulated robot's and gripper's options (the robot's `initial` and ports are set here).
CliUrArm startCliUrArm(const std::string& url, const std::string& robot, const JointVector& initial,
                       const std::string& token_file, const std::string& log_name, const UrArmSetup& setup = {});
/// `dashbench controller --driver sim --sim-start INITIAL [extra...]` as a child process.
std::unique_ptr<ChildProcess> startCliSimArm(const std::string& url, const std::string& robot,
                                             const JointVector& initial, const std::string& token_file,
                                             const std::string& log_name, const std::vector<std::string>& extra = {});
/// Joint values as the agents' command line takes them ("0,-1.5708,..."), full precision.
std::string csv(const JointVector& q);

}  // namespace dash::dispatch::test
