#include "tests/slurm/slurm_cluster.h"

#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "server/batch/slurm_client.h"
#include "tests/common/examples.h"

extern char** environ;

namespace dash::batch::testing {

namespace fs = std::filesystem;

namespace {

/// A TCP port nothing listens on now (the kernel's choice for port 0).
int freePort() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  int port = 0;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0) {
    port = ntohs(addr.sin_port);
  }
  close(fd);
  return port;
}

std::string firstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

}  // namespace

std::string SlurmCluster::unavailableReason() {
  if (geteuid() != 0) return "the Slurm cluster test must run as root (it starts munged, slurmctld and slurmd)";
  for (const char* cmd : {"munged", "slurmctld", "slurmd", "sbatch", "squeue", "scancel", "sinfo", "scontrol"}) {
    // The daemons live in /usr/sbin, which a user's PATH may lack.
    if (!onPath(cmd) && !fs::exists(std::string("/usr/sbin/") + cmd)) {
      return std::string(cmd) + " is missing: install the Debian packages slurm-wlm and munge (./dashbench test does)";
    }
  }
  return "";
}

SlurmCluster::SlurmCluster() {
  std::string pattern = (fs::temp_directory_path() / "dash_slurm_cluster_XXXXXX").string();
  if (mkdtemp(pattern.data()) != nullptr) dir_ = pattern;
}

SlurmCluster::~SlurmCluster() {
  stop();
  std::error_code ec;
  if (!dir_.empty()) fs::remove_all(dir_, ec);
}

pid_t SlurmCluster::spawnDaemon(const std::vector<std::string>& argv, const std::string& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return -1;
  daemons_.push_back(pid);
  return pid;
}

std::string SlurmCluster::logs() const {
  std::string out;
  for (const char* name : {"munged.out", "slurmctld.out", "slurmd.out"}) {
    out += std::string("--- ") + name + "\n" + dash::test::readFile(dir_ + "/" + name);
  }
  return out;
}

bool SlurmCluster::start(double timeout, std::string& error) {
  if (dir_.empty()) {
    error = "cannot create a temporary directory";
    return false;
  }
  for (const char* sub : {"munge", "spool", "state"}) fs::create_directories(dir_ + "/" + sub);
  const std::string socket = dir_ + "/munge/munge.socket";
  if (!startMunge(socket)) {
    error = "cannot start munged";
    return false;
  }
  // The node's line from slurmd itself (CPUs, sockets, memory as it will report them), so that the
  // controller never drains the node for a mismatch.
  const CommandResult node = runCommand({"/usr/sbin/slurmd", "-C"});
  if (node.exit_code != 0 || node.out.rfind("NodeName=", 0) != 0) {
    error = "slurmd -C failed: " + node.out + node.err;
    return false;
  }
  const std::string conf = writeConf(socket, firstLine(node.out));
  setenv("SLURM_CONF", conf.c_str(), 1);

  // munged needs a moment to create its socket before the daemons authenticate.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout);
  while (!fs::exists(socket) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (spawnDaemon({"/usr/sbin/slurmctld", "-D", "-i", "-f", conf}, dir_ + "/slurmctld.out") < 0 ||
      spawnDaemon({"/usr/sbin/slurmd", "-D", "-f", conf}, dir_ + "/slurmd.out") < 0) {
    error = "cannot start slurmctld or slurmd";
    return false;
  }
  while (std::chrono::steady_clock::now() < deadline) {
    const CommandResult sinfo = runCommand({"sinfo", "-h", "-o", "%T"}, 5.0);
    if (sinfo.exit_code == 0 && sinfo.out.rfind("idle", 0) == 0) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
  error = "the node did not become idle within " + std::to_string(timeout) + " s\n" + logs();
  return false;
}

bool SlurmCluster::startMunge(const std::string& socket) {
  fs::permissions(dir_ + "/munge", fs::perms::owner_all, fs::perm_options::replace);
  // munged's key: 1 KiB of random bytes, readable by its owner only.
  {
    std::ofstream key(dir_ + "/munge/munge.key", std::ios::binary);
    std::random_device rd;
    for (int i = 0; i < 1024; ++i) key.put(static_cast<char>(rd() & 0xff));
  }
  fs::permissions(dir_ + "/munge/munge.key", fs::perms::owner_read | fs::perms::owner_write, fs::perm_options::replace);
  return spawnDaemon({"/usr/sbin/munged", "-F", "-f", "-S", socket, "--key-file", dir_ + "/munge/munge.key",
                      "--pid-file", dir_ + "/munge/munged.pid", "--log-file", dir_ + "/munge/munged.log",
                      "--seed-file", dir_ + "/munge/munged.seed"},
                     dir_ + "/munged.out") >= 0;
}

std::string SlurmCluster::writeConf(const std::string& socket, const std::string& node_line) {
  // The short host name is the node's name.
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  std::string short_host = host;
  short_host = short_host.substr(0, short_host.find('.'));
  const int ctld_port = freePort();
  int slurmd_port = freePort();
  while (slurmd_port == ctld_port) slurmd_port = freePort();
  const std::string conf = dir_ + "/slurm.conf";
  std::ofstream c(conf);
  c << "ClusterName=dashtest\n"
    << "SlurmctldHost=" << short_host << "(127.0.0.1)\n"
    << "SlurmctldPort=" << ctld_port << "\n"
    << "SlurmdPort=" << slurmd_port << "\n"
    << "SlurmUser=root\nSlurmdUser=root\n"
    << "AuthType=auth/munge\nCredType=cred/munge\n"
    << "AuthInfo=socket=" << socket << "\n"
    << "StateSaveLocation=" << dir_ << "/state\n"
    << "SlurmdSpoolDir=" << dir_ << "/spool\n"
    << "SlurmctldPidFile=" << dir_ << "/slurmctld.pid\n"
    << "SlurmdPidFile=" << dir_ << "/slurmd.pid\n"
    << "SlurmctldLogFile=" << dir_ << "/slurmctld.log\n"
    << "SlurmdLogFile=" << dir_ << "/slurmd.log\n"
    << "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n"
    << "SelectType=select/cons_tres\nSelectTypeParameters=CR_CPU\n"
    << "SchedulerType=sched/builtin\n"
    << "JobAcctGatherType=jobacct_gather/none\nAccountingStorageType=accounting_storage/none\n"
    << "JobCompType=jobcomp/none\nMpiDefault=none\n"
    << "ReturnToService=2\nKillWait=5\nMinJobAge=300\nInactiveLimit=0\n"
    << node_line << " NodeAddr=127.0.0.1 State=UNKNOWN\n"
    << "PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP\n";
  return conf;
}

bool SlurmCluster::stop() {
  bool all = true;
  // Reverse order: slurmd, slurmctld, then munged, which they need to the end.
  for (auto it = daemons_.rbegin(); it != daemons_.rend(); ++it) {
    kill(*it, SIGTERM);
    int status = 0;
    bool ended = false;
    for (int i = 0; i < 100 && !ended; ++i) {
      ended = waitpid(*it, &status, WNOHANG) == *it;
      if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (!ended) {
      kill(*it, SIGKILL);
      waitpid(*it, &status, 0);
      all = false;
    }
  }
  daemons_.clear();
  return all;
}

}  // namespace dash::batch::testing
