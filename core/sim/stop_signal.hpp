// SIGINT / SIGTERM as a request to stop: the command line installs a handler that only
// records the signal; the run loop (through a StopCondition) and the result writer
// check it, so a run ends at the next tick, nothing half-written is left at the output
// path, and a batch starts no new case. A second signal kills as usual (the handler is
// reset after the first). Library users (Python) never install it: stopSignal() is 0.
#pragma once
#include <stdexcept>
#include <string>

namespace packsim {

// resetAfterFirst: a second signal kills as usual (the command line); false keeps the
// handler (batch worker processes, which may get the signal twice: group and parent).
void installStopSignals(bool resetAfterFirst = true);
int stopSignal();         // the signal received (SIGINT, SIGTERM) or 0
void clearStopSignal();   // tests, and a batch that resumes in the same process
std::string stopSignalName(int sig);

// Thrown where a run or a write gives up because of a stop request.
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int sig, const std::string& what);
  int signal() const { return signal_; }
  int exitStatus() const { return 128 + signal_; }  // the shell's convention

 private:
  int signal_;
};

}  // namespace packsim
