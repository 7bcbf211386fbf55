#include "dispatch_test_util.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "engine/plan/plan_json.h"
#include "engine/scene/scene_json.h"
#include "server/dispatch/dispatch_routes.h"
#include "tests/common/examples.h"

namespace dash::dispatch::test {

namespace {

const Vec3 kExtraBases[] = {Vec3(2.5, 0.0, 0.0), Vec3(-2.5, 0.0, 0.0), Vec3(0.0, 2.5, 0.0)};

}  // namespace

Scene multiArmScene(int extra_arms) {
  Scene scene = loadScene(dash::test::exampleScenePath(), library());
  for (int k = 0; k < extra_arms; ++k) {
    SceneRobot arm = scene.robots.front();
    arm.id = "ur5e_" + std::to_string(k + 1);
    arm.X_WB = makePose(kExtraBases[k]);
    scene.robots.push_back(arm);
  }
  return scene;
}

JointVector homeOf(const Scene& scene, const std::string& robot) {
  return scene.robots[static_cast<std::size_t>(scene.robotIndex(robot))].home;
}

Plan multiArmPlan(const Scene& scene) {
  Plan plan = loadPlan(dash::test::examplePlanPath());
  JointVector offset(6);
  offset << 0.5, 0.2, -0.3, 0.2, 0.3, 0.6;
  for (std::size_t i = 1; i < scene.robots.size(); ++i) {
    const SceneRobot& arm = scene.robots[i];
    const JointVector home = arm.home;
    const JointVector away = home + offset;
    plan.robots.push_back({arm.id, arm.model->joint_names, {{0.0, home}, {1.2, away}, {1.6, away}, {3.0, home}}});
  }
  return plan;
}

std::string sceneJson(const Scene& scene) { return sceneToJson(scene); }
std::string planJson(const Plan& plan) { return planToJson(plan); }

std::string dispatchBody(const Plan& plan, const Scene& scene, const std::string& options_json) {
  std::string body = "{\"plan\": " + planJson(plan) + ", \"scene\": " + sceneJson(scene);
  if (!options_json.empty()) body += ", \"options\": " + options_json;
  return body + "}";
}

TestServer::TestServer(DispatchConfig config, const std::string& db_path) {
  if (!config.library) config.library = library();
  service_ = std::make_unique<DispatchService>(std::move(config));
  if (!db_path.empty()) {
    recorder_ = std::make_shared<DispatchRecorder>(db_path);
    service_->addListener(recorder_);
  }
  server_ = std::make_unique<httplib::Server>();
  server_->new_task_queue = [] { return new httplib::ThreadPool(24); };
  server_->set_tcp_nodelay(true);
  registerDispatchRoutes(
      *server_, *service_,
      [](const httplib::Request& req) {
        return req.get_header_value("Authorization") == std::string("Bearer ") + kToken;
      },
      recorder_.get());
  port_ = server_->bind_to_any_port("127.0.0.1");
  thread_ = std::thread([this] { server_->listen_after_bind(); });
  waitFor([this] { return server_->is_running(); }, 5.0);
}

TestServer::~TestServer() {
  service_->shutdown();
  server_->stop();
  if (thread_.joinable()) thread_.join();
}

HttpReply httpPost(const std::string& url, const std::string& path, const std::string& body, const std::string& token) {
  httplib::Client client(url);
  client.set_read_timeout(std::chrono::seconds(30));
  httplib::Headers headers;
  if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
  auto res = client.Post(path, headers, body, "application/json");
  if (!res) return {};
  return {res->status, res->body};
}

HttpReply httpGet(const std::string& url, const std::string& path, const std::string& token) {
  httplib::Client client(url);
  client.set_read_timeout(std::chrono::seconds(10));
  httplib::Headers headers;
  if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
  auto res = client.Get(path, headers);
  if (!res) return {};
  return {res->status, res->body};
}

SimArm startSimArm(const std::string& url, const std::string& robot, const JointVector& initial, SimDriverOptions sim,
                   AgentOptions agent, const std::string& token) {
  SimArm arm;
  sim.initial = initial;
  arm.driver = std::make_unique<SimDriver>(library()->get("ur5e"), sim);
  agent.server_url = url;
  agent.robot = robot;
  agent.token = token;
  arm.agent = std::make_unique<ControllerAgent>(agent, *arm.driver);
  arm.agent->start();
  return arm;
}

UrArm startUrArm(const std::string& url, const std::string& robot, const JointVector& initial, AgentOptions agent,
                 UrArmSetup setup) {
  UrArm arm;
  arm.gripper = std::make_unique<SimGripper>(setup.gripper);
  SimUrRobotOptions robot_options = setup.robot;
  robot_options.initial = initial;
  arm.robot = std::make_unique<SimUrRobot>(robot_options);
  UrDriverOptions ur;
  ur.read_timeout_ms = kLoadProofReadTimeoutMs;
  ur.state_stale_after = setup.state_stale_after;
  ur.robot_ip = "127.0.0.1";
  ur.listen_host = "127.0.0.1";
  ur.reverse_port = ur.script_port = ur.trajectory_port = ur.script_command_port = 0;
  ur.rtde_port = arm.robot->rtdePort();
  ur.gripper = true;
  ur.gripper_host = "127.0.0.1";
  ur.gripper_port = arm.gripper->port();
  arm.driver = std::make_unique<UrDriver>(library()->get("ur5e"), ur);
  const UrDriver::Ports p = arm.driver->ports();
  arm.robot->setPcPorts(p.script, p.reverse, p.trajectory, p.script_command);
  arm.robot->start();
  agent.server_url = url;
  agent.robot = robot;
  agent.token = kToken;
  arm.agent = std::make_unique<ControllerAgent>(agent, *arm.driver);
  arm.agent->start();
  return arm;
}

bool waitFor(const std::function<bool()>& condition, double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::microseconds(static_cast<std::int64_t>(timeout_s * 1e6));
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return condition();
}

bool controllersReady(DispatchService& service, const std::vector<std::string>& robots) {
  const auto list = service.controllers();
  for (const std::string& robot : robots) {
    bool ok = false;
    for (const ControllerInfo& c : list) ok = ok || (c.robot == robot && c.connected && c.ready && c.last_sample);
    if (!ok) return false;
  }
  return true;
}

std::optional<DispatchStatus> waitFinal(DispatchService& service, double timeout_s) {
  waitFor([&] {
    const auto s = service.status();
    return s && s->final;
  }, timeout_s);
  return service.status();
}

const ArmDispatchStatus* armStatus(const DispatchStatus& status, const std::string& robot) {
  for (const ArmDispatchStatus& a : status.arms) {
    if (a.robot == robot) return &a;
  }
  return nullptr;
}

std::vector<int> freePorts(int count) {
  std::vector<Socket> held;
  std::vector<int> ports;
  for (int i = 0; i < count; ++i) {
    held.push_back(listenTcp("127.0.0.1", 0));
    ports.push_back(boundPort(held.back()));
  }
  return ports;
}

std::vector<std::pair<std::string, std::string>> readEvents(
    const std::string& url, const std::string& path,
    const std::function<bool(const std::vector<std::pair<std::string, std::string>>&)>& enough, double timeout_s) {
  std::vector<std::pair<std::string, std::string>> events;
  httplib::Client client(url);
  client.set_read_timeout(std::chrono::milliseconds(static_cast<int>(timeout_s * 1000)));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<int>(timeout_s * 1000));
  SseParser parser;
  httplib::Headers headers{{"Authorization", std::string("Bearer ") + kToken}};
  client.Get(path, headers, [&](const char* data, std::size_t size) {
    for (const SseEvent& e : parser.feed(data, size)) events.emplace_back(e.event, e.data);
    return !enough(events) && std::chrono::steady_clock::now() < deadline;
  });
  return events;
}

std::string writeTokenFile(const std::string& name, const std::string& token) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << token << "\n";
  return path;
}

std::string csv(const JointVector& q) {
  std::ostringstream out;
  out.precision(17);
  for (Eigen::Index i = 0; i < q.size(); ++i) out << (i ? "," : "") << q[i];
  return out.str();
}

CliUrArm startCliUrArm(const std::string& url, const std::string& robot, const JointVector& initial,
                       const std::string& token_file, const std::string& log_name, const UrArmSetup& setup) {
  CliUrArm arm;
  arm.gripper = std::make_unique<SimGripper>(setup.gripper);
  const std::vector<int> ports = freePorts(4);  // reverse, script, trajectory, script command
  SimUrRobotOptions options = setup.robot;
  options.initial = initial;
  options.reverse_port = ports[0];
  options.script_port = ports[1];
  options.trajectory_port = ports[2];
  options.script_command_port = ports[3];
  arm.robot = std::make_unique<SimUrRobot>(options);
  arm.robot->start();
  const std::vector<std::string> args = {"controller",
                                         "--server", url,
                                         "--token-file", token_file,
                                         "--robot", robot,
                                         "--driver", "ur",
                                         "--robot-ip", "127.0.0.1",
                                         "--host-ip", "127.0.0.1",
                                         "--listen-host", "127.0.0.1",
                                         "--reverse-port", std::to_string(ports[0]),
                                         "--script-port", std::to_string(ports[1]),
                                         "--trajectory-port", std::to_string(ports[2]),
                                         "--script-command-port", std::to_string(ports[3]),
                                         "--rtde-port", std::to_string(arm.robot->rtdePort()),
                                         "--gripper", "robotiq",
                                         "--gripper-host", "127.0.0.1",
                                         "--gripper-port", std::to_string(arm.gripper->port()),
                                         "--read-timeout-ms", std::to_string(kLoadProofReadTimeoutMs),
                                         "--stale-ms", std::to_string(kLoadProofStaleMs)};
  arm.agent = std::make_unique<ChildProcess>(dashbenchCommand(args), ChildProcess::Options{.output = ::testing::TempDir() + log_name});
  return arm;
}

std::unique_ptr<ChildProcess> startCliSimArm(const std::string& url, const std::string& robot,
                                             const JointVector& initial, const std::string& token_file,
                                             const std::string& log_name, const std::vector<std::string>& extra) {
  std::vector<std::string> args = {"controller", "--server",   url,   "--token-file", token_file, "--robot",
                                   robot,        "--driver",   "sim", "--sim-start",  csv(initial)};
  args.insert(args.end(), extra.begin(), extra.end());
  return std::make_unique<ChildProcess>(dashbenchCommand(args), ChildProcess::Options{.output = ::testing::TempDir() + log_name});
}

}  // namespace dash::dispatch::test
