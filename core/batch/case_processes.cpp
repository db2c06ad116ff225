#include "core/batch/case_processes.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <map>
#include <string>

#include "core/sim/stop_signal.hpp"

namespace packsim {

namespace {

struct Worker {
  size_t index;
  int fd;  // read end of the outcome pipe
};

// Outcome over the pipe: "<ok> <skipped> <wall_s>\n<error>".
// Kept well under a pipe's buffer: the parent reads it after the worker has exited.
void sendOutcome(int fd, const CaseOutcome& o) {
  const std::string text = std::to_string(o.ok ? 1 : 0) + " " + std::to_string(o.skipped ? 1 : 0) + " " +
                           std::to_string(o.wall_s) + "\n" + o.error.substr(0, 8000);
  size_t sent = 0;
  while (sent < text.size()) {
    const ssize_t n = write(fd, text.data() + sent, text.size() - sent);
    if (n <= 0 && errno != EINTR) break;
    if (n > 0) sent += static_cast<size_t>(n);
  }
}

std::string readAll(int fd) {
  std::string out;
  char buf[4096];
  for (;;) {
    const ssize_t n = read(fd, buf, sizeof buf);
    if (n > 0) out.append(buf, static_cast<size_t>(n));
    else if (n == 0 || errno != EINTR) break;
  }
  return out;
}

CaseOutcome parseOutcome(const std::string& text, int status) {
  CaseOutcome o;
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    o.error = "the case crashed (signal " + std::to_string(sig) + ", " + strsignal(sig) + ")";
    return o;
  }
  int ok = 0, skipped = 0;
  double wall = 0.0;
  const size_t nl = text.find('\n');
  if (nl == std::string::npos || std::sscanf(text.c_str(), "%d %d %lf", &ok, &skipped, &wall) != 3) {
    o.error = "the case's worker process ended without an outcome (exit status " +
              std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")";
    return o;
  }
  o.ok = ok != 0;
  o.skipped = skipped != 0;
  o.wall_s = wall;
  o.error = text.substr(nl + 1);
  return o;
}

}  // namespace

void runCasesInProcesses(const Sweep& sw, bool resume, int workers, std::vector<CaseOutcome>& outcomes,
                         const std::function<void(size_t)>& caseDone) {
  std::map<pid_t, Worker> running;
  size_t next = 0;
  bool forwarded = false;
  std::fflush(nullptr);  // nothing buffered is printed twice by a child
  while (next < sw.cases.size() || !running.empty()) {
    while (!stopSignal() && next < sw.cases.size() && static_cast<int>(running.size()) < workers) {
      int fds[2];
      if (pipe(fds) != 0) throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
      const size_t i = next++;
      const pid_t pid = fork();
      if (pid < 0) throw std::runtime_error(std::string("cannot start a worker process: ") + std::strerror(errno));
      if (pid == 0) {  // the worker
        close(fds[0]);
        installStopSignals(false);  // a forwarded second signal must not kill it mid-write
        sendOutcome(fds[1], runSweepCase(sw, sw.cases[i], resume));
        close(fds[1]);
        _exit(0);
      }
      close(fds[1]);
      running[pid] = Worker{i, fds[0]};
    }
    if (running.empty()) break;  // stopped before the remaining cases
    if (stopSignal() && !forwarded) {  // e.g. SIGTERM to the batch alone: stop the workers too
      for (const auto& kv : running) kill(kv.first, stopSignal());
      forwarded = true;
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;  // a stop signal: forward it, then wait again
      throw std::runtime_error(std::string("waiting for a worker failed: ") + std::strerror(errno));
    }
    auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::string text = readAll(it->second.fd);
    close(it->second.fd);
    const size_t i = it->second.index;
    running.erase(it);
    outcomes[i] = parseOutcome(text, status);
    caseDone(i);
  }
}

}  // namespace packsim
