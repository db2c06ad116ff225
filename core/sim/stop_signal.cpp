#include "core/sim/stop_signal.hpp"

#include <csignal>

namespace packsim {

namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void onStopSignal(int sig) { g_signal = sig; }

}  // namespace

void installStopSignals(bool resetAfterFirst) {
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = resetAfterFirst ? SA_RESETHAND : 0;  // a second Ctrl-C kills at once
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int stopSignal() { return g_signal; }

void clearStopSignal() { g_signal = 0; }

std::string stopSignalName(int sig) {
  if (sig == SIGINT) return "SIGINT";
  if (sig == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(sig);
}

Interrupted::Interrupted(int sig, const std::string& what) : std::runtime_error(what), signal_(sig) {}

}  // namespace packsim
