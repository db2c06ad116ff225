#include "core/firmware/fault_guard.hpp"

#include <setjmp.h>
#include <signal.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <ucontext.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/asan_interface.h>
#define PACKSIM_GUARD_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#include <sanitizer/asan_interface.h>
#define PACKSIM_GUARD_ASAN 1
#endif
#endif

namespace packsim {

namespace {

constexpr int kSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGXCPU};
constexpr int kSignalCount = sizeof kSignals / sizeof kSignals[0];
constexpr int kWatchdogSignal = SIGXCPU;

std::mutex gInstallMutex;
int gInstalled = 0;  // live Scopes over all threads
struct sigaction gPrevious[kSignalCount];

thread_local sigjmp_buf* tJump = nullptr;
thread_local volatile sig_atomic_t tSignal = 0;
thread_local volatile sig_atomic_t tInService = 0;
thread_local volatile sig_atomic_t tWatchdogPending = 0;
thread_local std::vector<char> tAltStack;
thread_local uintptr_t tFaultSp = 0;  // stack pointer of the interrupted code

uintptr_t stackPointerOf(void* uctx) {
  const ucontext_t* u = static_cast<const ucontext_t*>(uctx);
#if defined(__x86_64__)
  return static_cast<uintptr_t>(u->uc_mcontext.gregs[REG_RSP]);
#elif defined(__aarch64__)
  return static_cast<uintptr_t>(u->uc_mcontext.sp);
#else
  (void)u;
  return 0;
#endif
}

int indexOf(int sig) {
  for (int i = 0; i < kSignalCount; ++i)
    if (kSignals[i] == sig) return i;
  return -1;
}

void onSignal(int sig, siginfo_t* info, void* uctx) {
  if (tJump != nullptr && sig == kWatchdogSignal && tInService) {
    tWatchdogPending = 1;  // leaveService() takes the way out
    return;
  }
  if (tJump != nullptr) {
    tSignal = sig;
    tFaultSp = stackPointerOf(uctx);
    siglongjmp(*tJump, sig == kWatchdogSignal ? 2 : 1);
  }
  // Not inside a firmware call on this thread: behave as before the guard.
  if (sig == kWatchdogSignal) return;  // a watchdog tick that arrived after the call ended
  const int i = indexOf(sig);
  const struct sigaction& prev = gPrevious[i];
  if (prev.sa_flags & SA_SIGINFO) {
    if (prev.sa_sigaction) prev.sa_sigaction(sig, info, uctx);
    return;
  }
  if (prev.sa_handler == SIG_IGN) return;
  if (prev.sa_handler != SIG_DFL && prev.sa_handler != nullptr) {
    prev.sa_handler(sig);
    return;
  }
  signal(sig, SIG_DFL);  // returning re-executes the fault (or re-raise for abort) under the default
  if (sig == SIGABRT) raise(sig);
}

void ensureAltStack() {
  if (!tAltStack.empty()) return;
  stack_t current{};
  if (sigaltstack(nullptr, &current) == 0 && !(current.ss_flags & SS_DISABLE)) {
    tAltStack.assign(1, 0);  // this thread already has one (a sanitizer's, which it frees itself): keep it
    return;
  }
  tAltStack.assign(256 * 1024, 0);
  stack_t ss{};
  ss.ss_sp = tAltStack.data();
  ss.ss_size = tAltStack.size();
  ss.ss_flags = 0;
  sigaltstack(&ss, nullptr);
}

}  // namespace

std::string signalName(int sig) {
  switch (sig) {
    case SIGSEGV: return "SIGSEGV (invalid memory access)";
    case SIGBUS: return "SIGBUS (bus error)";
    case SIGFPE: return "SIGFPE (arithmetic exception, e.g. integer division by zero)";
    case SIGILL: return "SIGILL (illegal instruction)";
    case SIGABRT: return "SIGABRT (abort or failed assert)";
    default: return "signal " + std::to_string(sig);
  }
}

FaultGuard::Scope::Scope() {
  std::lock_guard<std::mutex> lock(gInstallMutex);
  if (gInstalled++ > 0) return;
  for (int i = 0; i < kSignalCount; ++i) {
    struct sigaction sa{};
    sa.sa_sigaction = onSignal;
    sa.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_NODEFER;
    sigemptyset(&sa.sa_mask);
    sigaction(kSignals[i], &sa, &gPrevious[i]);
  }
}

FaultGuard::Scope::~Scope() {
  std::lock_guard<std::mutex> lock(gInstallMutex);
  if (--gInstalled > 0) return;
  for (int i = 0; i < kSignalCount; ++i) sigaction(kSignals[i], &gPrevious[i], nullptr);
}

FaultGuard::FaultGuard(double watchdog_s) : watchdog_s_(watchdog_s) {}

FaultGuard::~FaultGuard() {
  if (timerOk_) timer_delete(static_cast<timer_t>(timer_));
}

bool FaultGuard::inside() { return tJump != nullptr; }

void FaultGuard::enterService() { tInService = 1; }

void FaultGuard::leaveService() {
  tInService = 0;
  if (tWatchdogPending && tJump != nullptr) {
    tWatchdogPending = 0;
    siglongjmp(*tJump, 2);
  }
}

void FaultGuard::abandon() {
  if (tJump == nullptr) std::abort();  // a service called outside a guarded call: a host bug
  siglongjmp(*tJump, 3);
}

GuardResult FaultGuard::run(void (*fn)(void*), void* ctx) {
  ensureAltStack();
  if (!timerOk_) {  // this thread's CPU clock drives the watchdog
    struct sigevent sev{};
    sev.sigev_notify = SIGEV_THREAD_ID;
    sev.sigev_signo = kWatchdogSignal;
    sev._sigev_un._tid = static_cast<pid_t>(syscall(SYS_gettid));
    timer_t id;
    timerOk_ = timer_create(CLOCK_THREAD_CPUTIME_ID, &sev, &id) == 0;
    if (timerOk_) timer_ = static_cast<void*>(id);
  }
  struct itimerspec arm{};
  arm.it_value.tv_sec = static_cast<time_t>(watchdog_s_);
  arm.it_value.tv_nsec = static_cast<long>((watchdog_s_ - static_cast<double>(arm.it_value.tv_sec)) * 1e9);
  if (arm.it_value.tv_sec == 0 && arm.it_value.tv_nsec == 0) arm.it_value.tv_nsec = 1000000;
  const struct itimerspec disarm{};

  sigjmp_buf jump;
  GuardResult r;
  tSignal = 0;
  tInService = 0;
  tWatchdogPending = 0;
  const int how = sigsetjmp(jump, 1);  // 1: the signal mask comes back with the jump
  if (how == 0) {
    tJump = &jump;
    if (timerOk_) timer_settime(static_cast<timer_t>(timer_), 0, &arm, nullptr);
    fn(ctx);
  }
  if (timerOk_) timer_settime(static_cast<timer_t>(timer_), 0, &disarm, nullptr);
  tJump = nullptr;
  tInService = 0;
  tWatchdogPending = 0;
#ifdef PACKSIM_GUARD_ASAN
  // Left from a signal handler on the alternate stack, ASan cannot tell which frames
  // the jump abandoned: clear their redzones so later calls do not trip over them.
  const uintptr_t top = reinterpret_cast<uintptr_t>(__builtin_frame_address(0));
  if ((how == 1 || how == 2) && tFaultSp != 0 && tFaultSp < top)
    __asan_unpoison_memory_region(reinterpret_cast<void*>(tFaultSp), top - tFaultSp);
#endif
  tFaultSp = 0;
  if (how == 1) r = {GuardOutcome::Crashed, static_cast<int>(tSignal)};
  if (how == 2) r = {GuardOutcome::Hung, 0};
  if (how == 3) r = {GuardOutcome::ContractBreak, 0};
  return r;
}

}  // namespace packsim
