#pragma once
// A one-node Slurm cluster on localhost for tests: munged with its own key and socket, slurmctld and
// slurmd in the foreground (no systemd), all started as root from a temporary directory, with a
// minimal slurm.conf: proctrack/linuxproc, task/none, select/cons_tres (CR_CPU), no cgroups, no
// accounting storage (so sacct has no data and the backend falls back to squeue and the shards).
// SLURM_CONF is set for this process, so sbatch, squeue and scancel started from it use the cluster.
#include <sys/types.h>

#include <string>
#include <vector>

namespace dash::batch::testing {

class SlurmCluster {
 public:
  /// Why the cluster cannot run here (not root, a command missing); empty when it can.
  static std::string unavailableReason();

  SlurmCluster();
  ~SlurmCluster();  ///< stops the daemons (SIGTERM, then SIGKILL) and removes the directory
  SlurmCluster(const SlurmCluster&) = delete;
  SlurmCluster& operator=(const SlurmCluster&) = delete;

  /// Starts the daemons and waits (up to `timeout` seconds) until the node is idle; false with
  /// `error` (and the daemons' logs) otherwise.
  bool start(double timeout, std::string& error);
  /// Stops the daemons; returns true when all of them ended.
  bool stop();
  const std::string& dir() const { return dir_; }

 private:
  pid_t spawnDaemon(const std::vector<std::string>& argv, const std::string& log);
  std::string logs() const;
  // start()'s steps: munged on `socket`, and slurm.conf (its path) for that socket and slurmd's node line.
  bool startMunge(const std::string& socket);
  std::string writeConf(const std::string& socket, const std::string& node_line);

  std::string dir_;
  std::vector<pid_t> daemons_;
};

}  // namespace dash::batch::testing
