// Runs one call into a user firmware so that whatever the firmware does, the simulator
// survives it:
//   crash     SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT (abort, assert) inside the call
//             (or in a board service it called with bad arguments)
//   hang      the call used more than `watchdog_s` of this thread's CPU time (a
//             per-thread CPU-time timer, so a loaded machine or a batch's other
//             threads do not make a healthy call look hung)
//   contract  a board service found a broken rule and called abandon()
// Each ends the call at once with siglongjmp back into run(); the firmware is not
// called again (its RAM may be half-written). Handlers are installed by a Scope
// around the calls of one BMS tick and the previous ones restored when it closes;
// the handlers are process-wide but act only on a thread inside run() (a batch runs
// cases in threads), otherwise they hand the signal to the previous handler. Each
// thread gets its own alternate signal stack, so a stack overflow is caught too.
#pragma once
#include <string>

namespace packsim {

enum class GuardOutcome { Ok, Crashed, Hung, ContractBreak };

struct GuardResult {
  GuardOutcome outcome = GuardOutcome::Ok;
  int signal = 0;  // the signal of a crash
};

class FaultGuard {
 public:
  explicit FaultGuard(double watchdog_s);
  ~FaultGuard();
  FaultGuard(const FaultGuard&) = delete;
  FaultGuard& operator=(const FaultGuard&) = delete;

  // Handlers installed while a Scope lives (nested scopes share one installation).
  class Scope {
   public:
    Scope();
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;
  };

  // fn(ctx) under the guard; needs a live Scope. fn must not hold objects with
  // destructors across the call into the firmware (the way out is a longjmp).
  GuardResult run(void (*fn)(void*), void* ctx);
  // From a board service called inside run(): end the firmware call as a contract break.
  [[noreturn]] static void abandon();
  static bool inside();  // this thread is inside run()
  // Around the host's own code inside a board service: a watchdog expiring there is
  // held until leaveService(), so the way out never cuts through the simulator's own
  // data structures (a heap update, an event being logged).
  static void enterService();
  static void leaveService();

 private:
  double watchdog_s_;
  void* timer_ = nullptr;  // timer_t, created on first use on this thread
  bool timerOk_ = false;
};

std::string signalName(int sig);

}  // namespace packsim
