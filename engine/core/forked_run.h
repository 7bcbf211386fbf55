#pragma once
// Runs a function in a child process forked from this one and returns the text it produced (through a
// pipe), its exit status and CPU time. The child starts from the parent's exact state (every
// process-wide generator included, e.g. OMPL's), so two runs forked from one state differ only by what
// the function itself does differently: the same-plan tests and tools compare runs this way.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

namespace dash {

struct ForkedRun {
  std::string output;      ///< what the function returned, as the child wrote it
  bool finished = false;   ///< the child exited with status 0 after writing all of it
  double cpu_seconds = 0;  ///< the child's user CPU time
};

template <class Work>
ForkedRun runForked(Work work) {
  ForkedRun run;
  int fds[2];
  if (pipe(fds) != 0) return run;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const std::string out = work();
    for (std::size_t done = 0; done < out.size();) {
      const ssize_t n = write(fds[1], out.data() + done, out.size() - done);
      if (n <= 0) _exit(1);
      done += static_cast<std::size_t>(n);
    }
    _exit(0);
  }
  close(fds[1]);
  char buffer[65536];
  for (ssize_t n; (n = read(fds[0], buffer, sizeof buffer)) > 0;)
    run.output.append(buffer, static_cast<std::size_t>(n));
  close(fds[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  run.finished = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  run.cpu_seconds = static_cast<double>(usage.ru_utime.tv_sec) + 1e-6 * static_cast<double>(usage.ru_utime.tv_usec);
  return run;
}

}  // namespace dash
