// dashbench controller: the agent that runs next to one arm and executes what the server dispatches.
#include <csignal>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "engine/core/check.h"
#include "engine/robots/robot_model.h"
#include "server/cli/args.h"
#include "server/cli/command.h"
#include "server/dispatch/controller_agent.h"
#include "server/dispatch/sim_driver.h"
#include "server/dispatch/ur_driver.h"

namespace dash::cli {

extern const char* const kControllerHelp;
const char* const kControllerHelp =
    "usage: dashbench controller --server URL --robot ROBOT_ID --token-file FILE --driver sim|ur [options]\n"
    "Run the controller agent of one arm: connect to the dashbench server at URL (e.g.\n"
    "http://192.168.1.10:8080), take dispatched trajectories from it (server-sent events: trajectory,\n"
    "start, abort) and report the arm's joint states and status back (50 Hz while moving). Reconnects on\n"
    "its own; if the connection drops while the arm moves, the arm is stopped. Stop with Ctrl-C.\n"
    "A server that refuses the token (HTTP 401) ends the agent with exit status 2 and says so.\n"
    "\n"
    "Common options:\n"
    "  --model NAME            robot model (data/robots/NAME.json), default ur5e\n"
    "  --report-hz HZ          state reports per second while moving (default 50)\n"
    "  --quiet                 no progress lines on stderr\n"
    "\n"
    "--driver sim: a simulated arm that follows the trajectory in real time within the model's speeds.\n"
    "  --sim-start Q1,..,QN    initial joint state (default all zeros)\n"
    "  --sim-speed S           follow at S times the plan's speed (0.7 = a lowered speed slider)\n"
    "  --sim-pause-rate R      pause at random, R times per second of motion on average (default 0)\n"
    "  --sim-pause-max SEC     each pause lasts 0 .. SEC seconds, uniformly (default 0)\n"
    "  --sim-gripper-time SEC  a grasp or release takes SEC seconds (default 0: at once); the goal ends\n"
    "                          only once the gripper has finished\n"
    "  --sim-gripper-jitter SEC  each gripper move takes --sim-gripper-time plus or minus up to SEC\n"
    "  --sim-seed N            seed of the pauses and the jitter (default 1)\n"
    "  --sim-stop-at SEC       fault injection: stop silently SEC seconds after the start\n"
    "  --sim-refuse            fault injection: refuse every goal (INVALID_GOAL)\n"
    "  --sim-drop-at SEC       fault injection: drop the server connection SEC seconds after the start\n"
    "                          (it reconnects on its own)\n"
    "\n"
    "--driver ur: a UR arm (UR5e) running the External Control URCap, which connects to this machine.\n"
    "  --robot-ip IP           the robot (RTDE joint states, port --rtde-port 30004), required\n"
    "  --host-ip IP            this machine's address as the robot sees it (default: found from the\n"
    "                          RTDE connection); must match the URCap's Host IP\n"
    "  --listen-host ADDR      where to listen (default 0.0.0.0)\n"
    "  --reverse-port P        default 50001   --script-port P          default 50002\n"
    "  --trajectory-port P     default 50003   --script-command-port P  default 50004\n"
    "                          (several robots on one machine need distinct ports)\n"
    "  --read-timeout-ms MS    the robot stops if no message comes within MS (default 100)\n"
    "  --keepalive-ms MS       keep-alive period (default 10)\n"
    "  --rtde-hz HZ            RTDE output frequency asked of the robot (default 500: e-series; CB3: 125)\n"
    "  --stale-ms MS           a joint state older than MS stops a running goal (default: 3 RTDE\n"
    "                          periods + 20 ms, 26 ms at 500 Hz)\n"
    "  --point-type spline|movej   how points are sent (default spline: cubic)\n"
    "  --gripper robotiq|none  grasp/release through Robotiq's URCap socket (default none)\n"
    "  --gripper-host H        default: --robot-ip      --gripper-port P  default 63352\n"
    "  --gripper-speed N       SPE of grasp and release moves, 0..255 (default 255)\n"
    "  --gripper-force N       FOR of grasp and release moves, 0..255 (default 255)\n"
    "  The gripper is reset and activated when the agent first reaches it (its fingers move); a grasp\n"
    "  that closes on nothing (OBJ 3) fails the dispatch. See docs/real-arms.md.\n";

namespace {

std::atomic<bool> g_stop{false};

void onSignal(int) { g_stop = true; }

std::string readToken(const std::string& path) {
  std::ifstream in(path);
  DASH_THROW_UNLESS(in.good(), "cannot read the token file '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  std::string token = text.str();
  while (!token.empty() && std::isspace(static_cast<unsigned char>(token.back()))) token.pop_back();
  std::size_t start = 0;
  while (start < token.size() && std::isspace(static_cast<unsigned char>(token[start]))) ++start;
  token = token.substr(start);
  DASH_THROW_UNLESS(!token.empty(), "the token file '" + path + "' is empty");
  return token;
}

int port(const Args& args, const std::string& name, int fallback) {
  const long long p = args.integer(name, fallback);
  DASH_THROW_UNLESS(p >= 0 && p <= 65535, "--" + name + ": not a port number");
  return static_cast<int>(p);
}

dispatch::AgentOptions agentOptions(const Args& args) {
  dispatch::AgentOptions agent;
  agent.server_url = args.require("server");
  agent.robot = args.require("robot");
  agent.token = readToken(args.require("token-file"));
  agent.report_hz = args.number("report-hz", 50.0);
  DASH_THROW_UNLESS(agent.report_hz >= 1.0, "--report-hz must be at least 1");
  if (args.has("sim-drop-at")) agent.drop_at = args.number("sim-drop-at", 0.0);
  if (!args.has("quiet")) {
    agent.log = [](const std::string& line) {
      std::fprintf(stderr, "dashbench controller: %s\n", line.c_str());
      std::fflush(stderr);
    };
  }
  return agent;
}

dispatch::SimDriverOptions simOptions(const Args& args, const RobotModel& model) {
  dispatch::SimDriverOptions sim;
  if (args.has("sim-start")) {
    const auto q = parseNumberList(args.require("sim-start"), "--sim-start");
    DASH_THROW_UNLESS(static_cast<int>(q.size()) == model.dof(),
                      "--sim-start: expected " + std::to_string(model.dof()) + " numbers");
    sim.initial = JointVector::Map(q.data(), static_cast<Eigen::Index>(q.size()));
  }
  sim.speed = args.number("sim-speed", 1.0);
  DASH_THROW_UNLESS(sim.speed > 0.0 && sim.speed <= 10.0, "--sim-speed must be within 0 .. 10");
  sim.pause_rate = args.number("sim-pause-rate", 0.0);
  sim.pause_max = args.number("sim-pause-max", 0.0);
  sim.gripper_time = args.number("sim-gripper-time", 0.0);
  sim.gripper_jitter = args.number("sim-gripper-jitter", 0.0);
  sim.seed = static_cast<std::uint64_t>(args.integer("sim-seed", 1));
  DASH_THROW_UNLESS(sim.pause_rate >= 0.0 && sim.pause_rate <= 100.0, "--sim-pause-rate: 0 to 100 per second");
  DASH_THROW_UNLESS(sim.pause_max >= 0.0 && sim.pause_max <= 60.0, "--sim-pause-max: 0 to 60 s");
  DASH_THROW_UNLESS(sim.gripper_time >= 0.0 && sim.gripper_time <= 30.0, "--sim-gripper-time: 0 to 30 s");
  DASH_THROW_UNLESS(sim.gripper_jitter >= 0.0 && sim.gripper_jitter <= sim.gripper_time,
                    "--sim-gripper-jitter: 0 to --sim-gripper-time");
  if (args.has("sim-stop-at")) sim.stop_at = args.number("sim-stop-at", 0.0);
  sim.refuse = args.has("sim-refuse");
  return sim;
}

dispatch::UrDriverOptions urOptions(const Args& args) {
  dispatch::UrDriverOptions ur;
  ur.robot_ip = args.require("robot-ip");
  ur.host_ip = args.get("host-ip", "");
  ur.listen_host = args.get("listen-host", "0.0.0.0");
  ur.reverse_port = port(args, "reverse-port", 50001);
  ur.script_port = port(args, "script-port", 50002);
  ur.trajectory_port = port(args, "trajectory-port", 50003);
  ur.script_command_port = port(args, "script-command-port", 50004);
  ur.rtde_port = port(args, "rtde-port", 30004);
  ur.read_timeout_ms = static_cast<int>(args.integer("read-timeout-ms", 100));
  ur.keepalive_ms = static_cast<int>(args.integer("keepalive-ms", 10));
  ur.rtde_frequency = args.number("rtde-hz", 500.0);
  DASH_THROW_UNLESS(ur.rtde_frequency >= 1.0 && ur.rtde_frequency <= 500.0, "--rtde-hz: 1 to 500");
  if (args.has("stale-ms")) {
    const long long stale = args.integer("stale-ms", 0);
    DASH_THROW_UNLESS(stale >= 1 && stale <= 10000, "--stale-ms: 1 to 10000");
    ur.state_stale_after = static_cast<double>(stale) * 1e-3;
  }
  const std::string point_type = args.get("point-type", "spline");
  DASH_THROW_UNLESS(point_type == "spline" || point_type == "movej", "--point-type: spline or movej");
  ur.point_type = point_type == "spline" ? dispatch::ur::PointType::kSpline : dispatch::ur::PointType::kMovej;
  const std::string gripper = args.get("gripper", "none");
  DASH_THROW_UNLESS(gripper == "robotiq" || gripper == "none", "--gripper: robotiq or none");
  ur.gripper = gripper == "robotiq";
  ur.gripper_host = args.get("gripper-host", "");
  ur.gripper_port = port(args, "gripper-port", dispatch::robotiq::kPort);
  for (const auto& [name, target] : {std::pair<const char*, int*>{"gripper-speed", &ur.gripper_speed},
                                     std::pair<const char*, int*>{"gripper-force", &ur.gripper_force}}) {
    const long long v = args.integer(name, 255);
    DASH_THROW_UNLESS(v >= 0 && v <= 255, std::string("--") + name + ": 0 to 255");
    *target = static_cast<int>(v);
  }
  return ur;
}

std::unique_ptr<dispatch::ArmDriver> makeDriver(const Args& args, const std::string& driver_name,
                                                const RobotModel& model, const std::string& robot) {
  if (driver_name == "sim") return std::make_unique<dispatch::SimDriver>(model, simOptions(args, model));
  if (driver_name != "ur") throw InputError("--driver: expected sim or ur, got '" + driver_name + "'");
  const dispatch::UrDriverOptions ur = urOptions(args);
  auto ur_driver = std::make_unique<dispatch::UrDriver>(model, ur);
  const auto p = ur_driver->ports();
  if (!args.has("quiet")) {
    std::fprintf(stderr,
                 "dashbench controller: %s: listening for the robot on %s: reverse %d, script %d, trajectory %d, "
                 "script command %d; RTDE from %s:%d\n",
                 robot.c_str(), ur.listen_host.c_str(), p.reverse, p.script, p.trajectory, p.script_command,
                 ur.robot_ip.c_str(), ur.rtde_port);
  }
  return ur_driver;
}

}  // namespace

int runController(const std::vector<std::string>& words) {
  Args args(words, {.options = {"server", "robot", "token-file", "driver", "model", "report-hz", "sim-start",
                                "sim-speed", "sim-stop-at", "sim-drop-at", "sim-pause-rate", "sim-pause-max",
                                "sim-gripper-time", "sim-gripper-jitter", "sim-seed", "robot-ip", "host-ip", "listen-host",
                                "reverse-port", "script-port", "trajectory-port", "script-command-port", "rtde-port",
                                "read-timeout-ms", "keepalive-ms", "point-type", "gripper", "gripper-host",
                                "gripper-port", "rtde-hz", "stale-ms", "gripper-speed", "gripper-force"},
                    .flags = {"sim-refuse", "quiet"}});
  const dispatch::AgentOptions agent = agentOptions(args);
  const bool quiet = args.has("quiet");
  const std::string driver_name = args.require("driver");
  const auto library = RobotLibrary::loadDefault();
  const RobotModel& model = library->get(args.get("model", "ur5e"));
  const std::unique_ptr<dispatch::ArmDriver> driver = makeDriver(args, driver_name, model, agent.robot);

  struct sigaction action {};
  action.sa_handler = onSignal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::signal(SIGPIPE, SIG_IGN);

  dispatch::ControllerAgent controller(agent, *driver);
  if (!quiet) {
    std::fprintf(stderr, "dashbench controller: %s (%s driver, %s) -> %s\n", agent.robot.c_str(), driver_name.c_str(),
                 model.name.c_str(), agent.server_url.c_str());
  }
  controller.start();
  std::string fatal;
  while (!g_stop && (fatal = controller.fatalError()).empty()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  driver->abort("the controller is stopping");
  controller.stop();
  driver->shutdown();
  if (!fatal.empty()) {
    std::fprintf(stderr, "dashbench controller: error: %s\n", fatal.c_str());
    return kExitBadInput;
  }
  return kExitOk;
}

}  // namespace dash::cli
