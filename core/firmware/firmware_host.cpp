#include "core/firmware/firmware_host.hpp"

#include "core/firmware/clock_ns.hpp"
#include "models/afe/byte_copy.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iterator>
#include <limits>
#include <optional>

namespace packsim {

namespace {

constexpr size_t kEventChars = 120;       // kept of one firmware event (the header's promise)
constexpr size_t kTelemetryKeep = 256;    // bytes kept of the last telemetry frame

FirmwareHost& host(psfw_board* b) { return *reinterpret_cast<FirmwareHost*>(b); }

// A firmware event that reads as a trip report but is not one ("TRIP cell_overvoltage",
// "trip:estop", "Trip: x"): "trip" in any case, then no letter, digit or '_' ("tripped"
// is a word of its own), without the exact "trip: " the host counts.
bool looksLikeATrip(const char* text) {
  static const char kWord[] = "trip";
  for (size_t i = 0; i + 1 < sizeof kWord; ++i)
    if (std::tolower(static_cast<unsigned char>(text[i])) != kWord[i]) return false;
  const unsigned char next = static_cast<unsigned char>(text[sizeof kWord - 1]);
  return !(std::isalnum(next) || next == '_');
}

// Whether the byte ranges [a, a + an) and [b, b + bn) may share a byte: true when they
// do; also when b lies in [a, a + an) with bn = 0 (nothing to share, a copy that changes
// nothing). Two unsigned compares, no tests of the lengths (at every bus transfer).
bool mayOverlap(const uint8_t* a, size_t an, const uint8_t* b, size_t bn) {
  const auto pa = reinterpret_cast<uintptr_t>(a), pb = reinterpret_cast<uintptr_t>(b);
  return pb - pa < an || pa - pb < bn;
}

// The port pins by number (psfw_gpio_in / psfw_gpio_out): an indexed field instead of
// a switch's jump per read or write (some seven reads and five writes a tick).
constexpr bool bms::Inputs::*kInputPins[] = {&bms::Inputs::eSwitchInternal, &bms::Inputs::eSwitchExternal,
                                             &bms::Inputs::relayAux,        &bms::Inputs::monitorFaultPin,
                                             &bms::Inputs::chargerPresent,  &bms::Inputs::runRequest,
                                             &bms::Inputs::resetRequest};
static_assert(PSFW_IN_ESWITCH_INTERNAL == 0 && PSFW_IN_ESWITCH_EXTERNAL == 1 && PSFW_IN_RELAY_AUX == 2 &&
                  PSFW_IN_MONITOR_FAULT == 3 && PSFW_IN_CHARGER_PRESENT == 4 && PSFW_IN_RUN_REQUEST == 5 &&
                  PSFW_IN_RESET_REQUEST == 6 && std::size(kInputPins) == 7,
              "kInputPins is indexed by psfw_gpio_in");
constexpr bool bms::Outputs::*kOutputPins[] = {&bms::Outputs::relayClose, &bms::Outputs::prechargeClose,
                                               &bms::Outputs::dischargeFetOn, &bms::Outputs::chargeFetOn,
                                               &bms::Outputs::chargerEnable};
static_assert(PSFW_OUT_RELAY == 0 && PSFW_OUT_PRECHARGE == 1 && PSFW_OUT_DISCHARGE_FET == 2 &&
                  PSFW_OUT_CHARGE_FET == 3 && PSFW_OUT_CHARGER_ENABLE == 4 && std::size(kOutputPins) == 5,
              "kOutputPins is indexed by psfw_gpio_out");

// The services as C entry points; each forwards to the host, marked as host code for
// the watchdog (FaultGuard::enterService) when the firmware runs under the guard (a
// library). A linked-in firmware runs without it: its table skips the marks (two
// thread-local writes per service call, on the per-tick path).
template <bool Guarded, typename R, typename F>
R service(F&& f) {
  if (Guarded) FaultGuard::enterService();
  const R r = f();
  if (Guarded) FaultGuard::leaveService();
  return r;
}
template <bool Guarded, typename F>
void serviceVoid(F&& f) {
  if (Guarded) FaultGuard::enterService();
  f();
  if (Guarded) FaultGuard::leaveService();
}

// Pins: the board's port pins and current / bus channels are wired (FirmwareBoard::pins),
// decided when the host is built: the services of the table skip the test at each call
// (some 15 calls a tick).
template <bool G, bool Pins>
psfw_board_api makeApi() {
  psfw_board_api a{};
  a.abi_version = PSFW_ABI_VERSION;
  a.now_ms = [](psfw_board* b) { return host(b).nowMs(); };
  a.now_us = [](psfw_board* b) { return host(b).nowUs(); };
  a.delay_us = [](psfw_board* b, uint32_t us) { serviceVoid<G>([&] { host(b).delayUs(us); }); };
  a.bus_transfer = [](psfw_board* b, uint8_t bus, const uint8_t* tx, uint16_t txLen, uint8_t* rx,
                      uint16_t rxLen) __attribute__((flatten)) {  // busTransfer inline: a call less per transfer
    return service<G, int32_t>([&] { return host(b).busTransfer(bus, tx, txLen, rx, rxLen); });
  };
  a.adc_read = [](psfw_board* b, uint8_t ch) { return host(b).adcReadOn<Pins>(ch); };
  a.gpio_read = [](psfw_board* b, uint8_t pin) { return host(b).gpioReadOn<Pins>(pin); };
  a.gpio_write = [](psfw_board* b, uint8_t pin, int32_t level) { host(b).gpioWriteOn<Pins>(pin, level); };
  a.dac_write = [](psfw_board* b, uint8_t ch, int32_t v) { host(b).dacWrite(ch, v); };
  a.telemetry_send = [](psfw_board* b, const uint8_t* bytes, uint16_t len) {
    serviceVoid<G>([&] { host(b).telemetrySend(bytes, len); });
  };
  a.event = [](psfw_board* b, const char* text) { serviceVoid<G>([&] { host(b).firmwareEvent(text); }); };
  a.set_task_period = [](psfw_board* b, uint32_t task, uint32_t period_ms, uint32_t budget_us) {
    return host(b).setTaskPeriod(task, period_ms, budget_us);
  };
  a.can_send = [](psfw_board* b, uint8_t can, uint32_t id, const uint8_t* data, uint8_t len) {
    return service<G, int32_t>([&] { return host(b).canSend(can, id, data, len); });
  };
  a.can_receive = [](psfw_board* b, uint8_t can, uint32_t* id, uint8_t* data) {
    return service<G, int32_t>([&] { return host(b).canReceive(can, id, data); });
  };
  a.nvm_read = [](psfw_board* b, uint32_t offset, uint8_t* data, uint32_t len) {
    return service<G, int32_t>([&] { return host(b).nvmRead(offset, data, len); });
  };
  a.nvm_write = [](psfw_board* b, uint32_t offset, const uint8_t* data, uint32_t len) {
    return service<G, int32_t>([&] { return host(b).nvmWrite(offset, data, len); });
  };
  return a;
}

}  // namespace

// One call into the firmware: the entry (task -2), init (-1) or task n.
struct FirmwareHost::Call {
  FirmwareHost* h;
  int task;
  const psfw_firmware* desc = nullptr;  // what the entry returned
  char name[65];                         // its name, read inside the guard (a pointer into the library);
                                         // set by the entry call only (not cleared per call: a rep stos each)
  static void run(void* p) {
    Call& c = *static_cast<Call*>(p);
    FirmwareHost& h = *c.h;
    psfw_board* board = reinterpret_cast<psfw_board*>(&h);
    if (c.task == -2) {
      c.name[0] = c.name[sizeof c.name - 1] = '\0';
      c.desc = h.linked_ ? h.linked_ : h.lib_->entry()();
      if (c.desc && c.desc->name) std::strncpy(c.name, c.desc->name, sizeof c.name - 1);
    } else if (c.task == -1) {
      h.initResult_ = h.fw_.init ? h.fw_.init(h.ram_.get(), board, &h.api_, h.config_.data(),
                                              static_cast<uint32_t>(h.config_.size()))
                                 : 0;
    } else {
      h.fw_.tasks[c.task].run(h.ram_.get(), board, &h.api_);
    }
  }
};

FirmwareHost::FirmwareHost(const FirmwareSettings& s, FirmwareBoard board, double tick_s, FirmwareSink& sink)
    : config_(s.config),
      watchdog_s_(s.watchdog_s),
      board_(std::move(board)),
      tick_ns_(toNs(tick_s)),
      sink_(sink),
      lib_(s.isTarget() ? nullptr : std::make_unique<FirmwareLibrary>(s.library_path)),
      guard_(s.isTarget() ? nullptr : std::make_unique<FaultGuard>(s.watchdog_s)),
      api_(board_.pins ? makeApi<true, true>() : makeApi<true, false>()),
      name_(s.library_path) {
  nvm_.fill(0xFF);
  if (s.isTarget())
    target_ = std::make_unique<TargetFirmware>(*this, s.library_path, static_cast<uint32_t>(std::llround(s.clock_hz)));
}

FirmwareHost::FirmwareHost(const psfw_firmware* linked, std::vector<uint8_t> config, FirmwareBoard board,
                           double tick_s, FirmwareSink& sink)
    : config_(std::move(config)),
      watchdog_s_(0.0),
      board_(std::move(board)),
      tick_ns_(toNs(tick_s)),
      sink_(sink),
      linked_(linked),
      api_(board_.pins ? makeApi<false, true>() : makeApi<false, false>()),
      name_(linked && linked->name ? linked->name : "(linked firmware)") {
  nvm_.fill(0xFF);
}

FirmwareHost::~FirmwareHost() = default;

void FirmwareHost::fault(double t_s, const std::string& cause) {
  dead_ = true;
  cause_ = cause;
  faultTime_s_ = t_s;
  sink_.event(t_s, "firmware_fault", cause + "; the MCU is stopped, its outputs hold their last levels");
}

void FirmwareHost::breakContract(const char* fmt, ...) {
  if (breakCause_[0] != '\0') return;  // the first break of the call is its cause
  breakAt_ns_ = clock_ns_;  // the simulated instant it broke: a call may run past its start (bus, delays)
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(breakCause_, sizeof breakCause_, fmt, ap);
  va_end(ap);
  if (guard_) FaultGuard::abandon();
}

// Runs one call (under the guard for a library); false (and the MCU dead) when it did
// not return cleanly or broke the contract. Inline (step and start are its callers): a
// linked-in firmware's task, twice a tick, runs without the call's own frame.
inline bool FirmwareHost::call(const char* what, int task) {
  if (target_) return target_->call(what, task);
  if (!guard_ && task >= 0) {  // a linked-in firmware's task (every tick): no guard, no descriptor
    breakCause_[0] = '\0';
    const uint64_t start_ns = clock_ns_;
    fw_.tasks[task].run(ram_.get(), reinterpret_cast<psfw_board*>(this), &api_);
    if (breakCause_[0] == '\0') return true;
    GuardResult r;
    r.outcome = GuardOutcome::ContractBreak;
    failed(static_cast<double>(start_ns) * 1e-9, callName(what, task), r);
    return false;
  }
  return callFull(what, task);
}

// Any other call: the entry, init, or a library's task under the guard (kept out of
// call()'s own frame, so that the linked-in task's path does not set up the Call).
bool FirmwareHost::callFull(const char* what, int task) {
  Call c;  // default-initialised: its name is not cleared (aggregate init would zero it)
  c.h = this;
  c.task = task;
  breakCause_[0] = '\0';
  const double start_s = clock_s();
  GuardResult r;
  if (guard_) {
    r = guard_->run(&Call::run, &c);
  } else {
    Call::run(&c);
    if (breakCause_[0] != '\0') r.outcome = GuardOutcome::ContractBreak;
  }
  if (r.outcome != GuardOutcome::Ok) {
    failed(start_s, callName(what, task), r);
    return false;
  }
  if (task == -2) {
    if (!c.desc) {
      fault(start_s, PSFW_ENTRY_SYMBOL " returned no descriptor");
      return false;
    }
    fw_ = *c.desc;
    name_ = c.name[0] ? c.name : "(unnamed)";
  }
  return true;
}

// "task 1 (period 10 ms)", "init": the call named in a firmware_fault.
std::string FirmwareHost::callName(const char* what, int task) const {
  std::string where = what;
  if (task >= 0) where += " " + std::to_string(task) + " (period " + std::to_string(fw_.tasks[task].period_ms) + " ms)";
  return where;
}

// The firmware_fault of a call that did not return cleanly.
void FirmwareHost::failed(double start_s, const std::string& where, const GuardResult& r) {
  switch (r.outcome) {
    case GuardOutcome::Ok: break;
    case GuardOutcome::Crashed: fault(start_s, "crash in " + where + ": " + signalName(r.signal)); break;
    case GuardOutcome::Hung:
      fault(start_s, "hang in " + where + ": still running after " + std::to_string(std::lround(watchdog_s_ * 1e3)) +
                         " ms of CPU time (watchdog_ms)");
      break;
    case GuardOutcome::ContractBreak:  // when it broke, not when the call began (an overrun: its budget's end)
      fault(std::max(start_s, static_cast<double>(breakAt_ns_) * 1e-9), "contract break in " + where + ": " + breakCause_);
      break;
  }
}

// Power-up at t_s: the descriptor, RAM, init; then the tasks' first due times.
void FirmwareHost::start(double t_s) {
  started_ = true;
  if (lib_ && !lib_->entry()) return fault(t_s, lib_->error());
  if (!call("the entry " PSFW_ENTRY_SYMBOL, -2)) return watchdogReset();
  if (const std::string bad = checkFirmwareDescriptor(fw_); !bad.empty()) return fault(t_s, bad);
  const size_t words = (std::max<uint32_t>(fw_.instance_bytes, 1u) + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t);
  ram_.reset(new std::max_align_t[words]);
  std::memset(ram_.get(), 0, words * sizeof(std::max_align_t));  // every byte: value-init skips padding
  runs_.assign(fw_.task_count, 0);
  worst_ns_.assign(fw_.task_count, 0);
  sink_.event(t_s, "firmware_loaded", "'" + name_ + "' (" + std::to_string(fw_.task_count) + " tasks, " +
                                   std::to_string(fw_.instance_bytes) + " bytes RAM, " +
                                   std::to_string(config_.size()) + " bytes configuration)");
  setBudget(clock_ns_, 0);
  inInit_ = true;
  const bool ok = call("init", -1);
  inInit_ = false;
  if (!ok) return watchdogReset();
  if (initResult_ != 0) return fault(t_s, "init returned " + std::to_string(initResult_) + " (not 0)");
  // Periods as init left them (set_task_period): first due one period after power-up.
  nextDue_ns_.assign(fw_.task_count, std::numeric_limits<uint64_t>::max());
  for (uint32_t i = 0; i < fw_.task_count; ++i) {
    const uint64_t p_ns = uint64_t{fw_.tasks[i].period_ms} * 1000000u;
    if (p_ns == 0) continue;  // switched off at init
    nextDue_ns_[i] = toNs(t_s) + p_ns;
    if ((p_ns % tick_ns_ != 0 || p_ns < tick_ns_) && resets_ == 0) {  // said once, not at every boot
      char note[200];
      std::snprintf(note, sizeof note,
                    "firmware task %u: its %u ms period is not a multiple of the %.0f ms BMS tick; it runs at its "
                    "own due times, its pins and outputs resolved to the tick",
                    i, fw_.tasks[i].period_ms, static_cast<double>(tick_ns_) * 1e-6);
      sink_.event(t_s, "config_warning", note);
    }
  }
}

void FirmwareHost::step(double t_s, const bms::Inputs& in, bms::Outputs& out) {
  if (dead_) return;
  heldInReset_ = false;  // the supply is back (a brown-out left started_ false: the MCU boots now)
  in_ = &in;
  out_ = &out;
  const uint64_t t_ns = toNs(t_s);
  clock_ns_ = std::max(clock_ns_, t_ns);
  const uint64_t windowEnd_ns = t_ns + tick_ns_;
  if (target_ && started_ && target_->watchdogExpired(t_ns)) {
    target_->expire();  // it ran out while the MCU waited for its next task
    watchdogReset();
  }
  if (resetPending_ && !bootAfterReset(windowEnd_ns, out)) return;  // (the usual tick: no call)
  if (target_) target_->monitorLine(in.monitorFaultPin, t_ns);  // its edge pends the ALERT interrupt
  // The task due first in this tick, found once for the check below and the loop's first
  // pass (a scan of the due times a tick saved); -1: none (or not started: none known).
  int next = started_ ? firstDue(windowEnd_ns) : -1;
  uint64_t irqAt_ns = 0;
  if (started_ && next < 0 && !(target_ && target_->nextIdleInterrupt(clock_ns_, windowEnd_ns, irqAt_ns))) return;
  // A library's calls run under the guard, its handlers installed only around ticks
  // that call into it.
  std::optional<FaultGuard::Scope> handlers;
  if (guard_) handlers.emplace();
  pinsNoted_ = pinsOf(out) == lastPins_;  // the writes below compare with `out` from here on
  bool known = started_;  // `next` is this pass's (start() or a task changes the due times)
  if (!started_) start(t_s);
  while (!dead_ && started_) {  // started_ false: a watchdog reset, the MCU boots in the tick of its instant
    if (!known) next = firstDue(windowEnd_ns);
    known = false;
    // Interrupts due before the task starts (at its instant too) pre-empt the idle loop first.
    if (target_ && !runInterrupts(next < 0 ? windowEnd_ns : std::max(clock_ns_, nextDue_ns_[static_cast<size_t>(next)]) + 1))
      return watchdogReset();
    if (dead_ || !started_) break;
    if (next < 0) break;
    const psfw_task& task = fw_.tasks[next];
    clock_ns_ = std::max(clock_ns_, nextDue_ns_[static_cast<size_t>(next)]);
    setBudget(clock_ns_, (task.budget_us ? uint64_t{task.budget_us} : uint64_t{task.period_ms} * 1000u) * 1000u);
    if (!call("task", next)) return watchdogReset();
    ++runs_[static_cast<size_t>(next)];
    worst_ns_[static_cast<size_t>(next)] = std::max(worst_ns_[static_cast<size_t>(next)], clock_ns_ - callStart_ns_);
    nextDue_ns_[static_cast<size_t>(next)] += uint64_t{task.period_ms} * 1000000u;
  }
  setBudget(callStart_ns_, 0);
}

// The task due first before end_ns (of several due at once, the first declared); -1: none.
// (The earliest time kept in a local: one load and compare per task.)
int FirmwareHost::firstDue(uint64_t end_ns) const {
  const uint64_t* due = nextDue_ns_.data();
  uint64_t first_ns = end_ns;
  int next = -1;
  for (uint32_t i = 0; i < fw_.task_count; ++i)
    if (due[i] < first_ns) {
      first_ns = due[i];
      next = static_cast<int>(i);
    }
  return next;
}

bool FirmwareHost::runInterrupts(uint64_t before_ns) {
  uint64_t at_ns = 0;
  while (!dead_ && started_ && target_->nextIdleInterrupt(clock_ns_, before_ns, at_ns)) {
    clock_ns_ = std::max(clock_ns_, at_ns);
    setBudget(clock_ns_, 0);
    if (!call("interrupt", TargetFirmware::kInterruptCall)) return false;
  }
  return true;
}

std::vector<std::string> FirmwareHost::targetSummary(double elapsed_s) const {
  std::vector<std::string> lines;
  if (!target_) return lines;
  const TargetFirmware& t = *target_;
  const double mhz = t.clock_hz() * 1e-6;
  char line[300];
  for (size_t i = 0; i < t.taskStats().size(); ++i) {
    const TargetTaskStats& s = t.taskStats()[i];
    if (s.calls == 0) continue;
    std::snprintf(line, sizeof line,
                  "task %zu (period %u ms): %llu calls, mean %.0f instructions / %.0f cycles (TRM range %.0f-%.0f), "
                  "worst %llu instructions / %llu cycles = %.1f us at %.0f MHz, stack %u bytes",
                  i, fw_.tasks[i].period_ms, static_cast<unsigned long long>(s.calls),
                  static_cast<double>(s.instructions) / static_cast<double>(s.calls),
                  static_cast<double>(s.cycles) / static_cast<double>(s.calls),
                  static_cast<double>(s.cyclesMin) / static_cast<double>(s.calls),
                  static_cast<double>(s.cyclesMax) / static_cast<double>(s.calls),
                  static_cast<unsigned long long>(s.worstInstructions), static_cast<unsigned long long>(s.worstCycles),
                  static_cast<double>(s.worstCycles) / mhz, mhz, s.stack_bytes);
    lines.push_back(line);
  }
  for (int i = 0; i < kTargetIrqLines; ++i) {
    const TargetIrqStats& s = t.irqStats()[static_cast<size_t>(i)];
    if (s.calls == 0) continue;
    std::snprintf(line, sizeof line,
                  "IRQ %d %s: %llu calls, mean %.0f cycles, worst %llu cycles = %.2f us, worst latency %.0f cycles = %.3f us",
                  i, TargetFirmware::irqName(i), static_cast<unsigned long long>(s.calls),
                  static_cast<double>(s.cycles) / static_cast<double>(s.calls),
                  static_cast<unsigned long long>(s.worstCycles), static_cast<double>(s.worstCycles) / mhz,
                  static_cast<double>(s.worstLatency_ns) * 1e-3 * mhz, static_cast<double>(s.worstLatency_ns) * 1e-3);
    lines.push_back(line);
  }
  const double load = elapsed_s > 0 ? static_cast<double>(t.totalCycles()) / (t.clock_hz() * elapsed_s) : 0.0;
  std::snprintf(line, sizeof line,
                "cortex-m4 at %.0f MHz: %llu instructions, %llu cycles (TRM range %llu-%llu), CPU load %.3f %%, "
                "stack high-water %u of %u bytes, %u watchdog resets",
                mhz, static_cast<unsigned long long>(t.totalInstructions()),
                static_cast<unsigned long long>(t.totalCycles()), static_cast<unsigned long long>(t.totalCyclesMin()),
                static_cast<unsigned long long>(t.totalCyclesMax()), 100.0 * load, t.stackHighWater_bytes(),
                t.stackSize_bytes(), t.resets());
  lines.push_back(line);
  return lines;
}

std::vector<std::pair<std::string, double>> FirmwareHost::targetFigures(double elapsed_s) const {
  std::vector<std::pair<std::string, double>> f;
  if (!target_) return f;
  const TargetFirmware& t = *target_;
  const auto d = [](uint64_t v) { return static_cast<double>(v); };
  f.emplace_back("target_clock_hz", t.clock_hz());
  f.emplace_back("target_instructions", d(t.totalInstructions()));
  f.emplace_back("target_cycles", d(t.totalCycles()));
  f.emplace_back("target_cycles_trm_min", d(t.totalCyclesMin()));
  f.emplace_back("target_cycles_trm_max", d(t.totalCyclesMax()));
  f.emplace_back("target_cpu_load", elapsed_s > 0 ? d(t.totalCycles()) / (t.clock_hz() * elapsed_s) : 0.0);
  f.emplace_back("target_stack_high_water_bytes", t.stackHighWater_bytes());
  f.emplace_back("target_stack_bytes", t.stackSize_bytes());
  f.emplace_back("target_watchdog_resets", t.resets());
  for (size_t i = 0; i < t.taskStats().size(); ++i) {
    const TargetTaskStats& s = t.taskStats()[i];
    const std::string p = "target_task" + std::to_string(i) + "_";
    const double n = s.calls ? d(s.calls) : 1.0;
    f.emplace_back(p + "calls", d(s.calls));
    f.emplace_back(p + "mean_instructions", d(s.instructions) / n);
    f.emplace_back(p + "mean_cycles", d(s.cycles) / n);
    f.emplace_back(p + "worst_instructions", d(s.worstInstructions));
    f.emplace_back(p + "worst_cycles", d(s.worstCycles));
    f.emplace_back(p + "stack_bytes", s.stack_bytes);
  }
  for (int i = 0; i < kTargetIrqLines; ++i) {
    const TargetIrqStats& s = t.irqStats()[static_cast<size_t>(i)];
    if (s.calls == 0) continue;
    const std::string p = "target_irq" + std::to_string(i) + "_";
    f.emplace_back(p + "calls", d(s.calls));
    f.emplace_back(p + "mean_cycles", d(s.cycles) / d(s.calls));
    f.emplace_back(p + "worst_cycles", d(s.worstCycles));
    f.emplace_back(p + "worst_latency_s", d(s.worstLatency_ns) * 1e-9);
  }
  return f;
}

std::string FirmwareHost::status() const {
  std::string telemetry = "; " + std::to_string(telemetryFrames_) + " telemetry frames";
  if (!lastTelemetry_.empty()) {
    telemetry += ", the last:";
    char hex[4];
    for (size_t i = 0; i < std::min<size_t>(lastTelemetry_.size(), 16); ++i) {
      std::snprintf(hex, sizeof hex, " %02x", lastTelemetry_[i]);
      telemetry += hex;
    }
    if (lastTelemetry_.size() > 16) telemetry += " ...";
  }
  if (!dead_) return name_ + ": ran to the end" + telemetry;
  char t[32];
  std::snprintf(t, sizeof t, "%.3f s", faultTime_s_);
  return name_ + ": firmware_fault at " + t + ": " + cause_ + telemetry;
}

// --- board services -------------------------------------------------------------

bool FirmwareHost::overBudget() {
  breakContract(target_ ? "ran %.6f ms of simulated time (its code on the MCU clock, bus transfers and delays), over "
                          "its %.3f ms budget"
                        : "ran %.3f ms of simulated time (bus transfers and delays), over its %.3f ms budget",
                static_cast<double>(clock_ns_ - callStart_ns_) * 1e-6, static_cast<double>(callBudget_ns_) * 1e-6);
  return false;
}

// Target mode, after a call that did not return: if the watchdog ran out, the MCU
// resets (RAM reloaded except .noinit) and, at the tick that holds the reset's instant,
// its outputs drop to their reset level and it boots again (bootAfterReset); else the
// firmware is dead (recorded).
void FirmwareHost::watchdogReset() {
  if (!target_ || !target_->resetPending()) return;
  const uint64_t at_ns = target_->watchdogDeadline_ns();
  char detail[240];
  std::snprintf(detail, sizeof detail,
                "watchdog: not kicked for %.3f ms; the MCU resets: outputs off, RAM reloaded from the ELF except "
                ".noinit, the entry and init run again (reset %u)",
                static_cast<double>(target_->watchdogTimeout_ns()) * 1e-6,
                target_->resets() + 1);
  sink_.event(static_cast<double>(at_ns) * 1e-9, "mcu_reset", detail);
  target_->reset(true);
  ++resets_;
  started_ = false;
  resetPending_ = true;
  resetAt_ns_ = at_ns;
  nextDue_ns_.clear();
  setBudget(callStart_ns_, 0);
}

void FirmwareHost::holdInReset(double t_s, const std::string& why, bms::Outputs& out) {
  if (dead_ || heldInReset_) return;
  heldInReset_ = true;
  ++resets_;
  const std::string clears = target_ ? "RAM reloaded from the ELF except .noinit"
                                     : "the instance RAM zeroed (the library's static variables are not reloaded)";
  sink_.event(t_s, "mcu_reset",
              why + "; held in reset with its outputs off until the supply recovers, then " + clears +
                  ", the entry and init run again; the NVM page is kept (reset " + std::to_string(resets_) + ")");
  out.relayClose = out.prechargeClose = out.dischargeFetOn = out.chargeFetOn = false;
  out.chargerEnable = false;
  out.chargerCurrentRequest_mA = 0;
  if (lastPins_ != PinLevels{}) {  // the pins drop at the tick that finds the supply low
    lastPins_ = PinLevels{};
    pinChanges_.push_back({t_s, lastPins_});
  }
  if (target_)
    target_->reset(false);
  else if (ram_)  // the RAM's content is lost (a probe of packsim's core reads zeros until it boots)
    std::memset(ram_.get(), 0, fw_.instance_bytes);
  started_ = false;
  resetPending_ = false;
  nextDue_ns_.clear();
  setBudget(callStart_ns_, 0);
  clock_ns_ = std::max(clock_ns_, toNs(t_s));
}

// At the tick whose window holds the reset's instant: the outputs drop to their reset
// level and the MCU boots; false while that tick has not come yet.
bool FirmwareHost::bootAfterReset(uint64_t windowEnd_ns, bms::Outputs& out) {
  if (!resetPending_) return true;
  if (resetAt_ns_ >= windowEnd_ns) return false;
  out.relayClose = out.prechargeClose = out.dischargeFetOn = out.chargeFetOn = false;
  out.chargerEnable = false;
  out.chargerCurrentRequest_mA = 0;
  resetPending_ = false;
  if (lastPins_ != PinLevels{}) {  // the pins drop at the reset's instant
    lastPins_ = PinLevels{};
    pinChanges_.push_back({static_cast<double>(resetAt_ns_) * 1e-9, lastPins_});
  }
  return true;
}

void FirmwareHost::delayUs(uint32_t us) {
  clock_ns_ += uint64_t{us} * 1000u;
  checkBudget();
}

int32_t FirmwareHost::busTransfer(uint8_t bus, const uint8_t* tx, uint16_t txLen, uint8_t* rx, uint16_t rxLen) {
  if (breakCause_[0] != '\0') return PSFW_BUS_ERROR;  // a linked-in firmware that broke the contract this call
  if (bus >= board_.buses.size()) {
    breakContract("bus_transfer on bus %u, this board has %zu", bus, board_.buses.size());
    return PSFW_BUS_ERROR;
  }
  // (The two lengths' test as one, the two buffers' without short-circuits: some 4
  // instructions less a transfer on a host than the tests one by one.)
  if (std::max(txLen, rxLen) > PSFW_BUS_MAX_FRAME) {
    breakContract("bus_transfer of %u bytes out, %u in: more than PSFW_BUS_MAX_FRAME (%u)", txLen, rxLen,
                  PSFW_BUS_MAX_FRAME);
    return PSFW_BUS_ERROR;
  }
  if (static_cast<int>(txLen > 0 && tx == nullptr) | static_cast<int>(rxLen > 0 && rx == nullptr)) {
    breakContract("bus_transfer with a null buffer and a non-zero length");
    return PSFW_BUS_ERROR;
  }
  // A library's buffers are touched first (under the guard): a bad pointer faults here,
  // before the chain's state is touched. tx is copied when the reply may land on it (a
  // library's always); rx is cleared and the chain answers into it, then the bytes past
  // what it received are cleared again (so rx holds exactly the reply, zeros after it,
  // as on any failure). Trusted code (linked in, or the virtual MCU's memory) has no bad
  // pointer to find first: tx is copied only if rx overlaps it, and rx is not cleared
  // before (every chain writes each byte it reports received: the clear after covers the
  // rest), two library calls less per transfer (some 70 instructions a tick).
  // (copyBytes / zeroBytes: library calls, not the inline rep movs / stos GCC makes of a
  // length bounded by the buffers, slow to start for a frame of a few bytes)
  uint8_t txCopy[PSFW_BUS_MAX_FRAME];
  const uint8_t* txIn = tx;
  if (guard_ || txLen == 0 || mayOverlap(tx, txLen, rx, rxLen)) {
    if (txLen > 0) copyBytes(txCopy, tx, txLen);
    txIn = txCopy;
  }
  if (guard_ && rxLen > 0) zeroBytes(rx, rxLen);
  MonitorBus& b = *board_.buses[bus];
  const double t_s = clock_s();
  BusTransfer r;
  bool threw = false;
  try {
    b.advanceTo(t_s);
    r = b.chain->transfer(b.time_s, txIn, txLen, rx, rxLen);
  } catch (const std::exception&) {
    threw = true;
  }
  if (threw || r.received > static_cast<int>(rxLen)) {
    if (rxLen > 0) zeroBytes(rx, rxLen);
    if (threw)
      breakContract("the monitor chain rejected the transaction on bus %u", bus);
    else
      breakContract("host error: the chain returned more bytes than asked for");
    return PSFW_BUS_ERROR;
  }
  const size_t got = r.received > 0 ? static_cast<size_t>(r.received) : 0u;
  if (got < rxLen) zeroBytes(rx + got, rxLen - got);
  clock_ns_ += toNs(r.duration_s);
  checkBudget();
  return r.received < 0 ? PSFW_BUS_TIMEOUT : r.received;
}

int32_t FirmwareHost::adcRead(uint8_t channel) const {
  return board_.pins ? adcReadOn<true>(channel) : adcReadOn<false>(channel);
}

template <bool Pins>
int32_t FirmwareHost::adcReadOn(uint8_t channel) const {
  if (Pins && channel == PSFW_ADC_CURRENT) return in_->currentCode;
  if (Pins && channel == PSFW_ADC_BUS_VOLTAGE) return in_->busVoltageCode;
  const int n = static_cast<int>(channel) - PSFW_ADC_THERMISTOR0;
  if (n >= 0 && n < board_.mcuThermistors) {
    mcuThermistorsRead_ |= uint64_t{1} << n;
    return in_->mcuThermistorCode[n];
  }
  if (Pins) noteNoChannel(ServiceMisuse::kAdcRead, channel, 0, noChannel());
  return noChannel();
}

int32_t FirmwareHost::gpioRead(uint8_t pin) const {
  return board_.pins ? gpioReadOn<true>(pin) : gpioReadOn<false>(pin);
}

template <bool Pins>
int32_t FirmwareHost::gpioReadOn(uint8_t pin) const {
  if (!Pins) return noChannel();
  if (pin >= std::size(kInputPins)) {
    noteNoChannel(ServiceMisuse::kGpioRead, pin, 0, noChannel());
    return noChannel();
  }
  return in_->*kInputPins[pin];
}

void FirmwareHost::gpioWrite(uint8_t pin, int32_t level) {
  if (board_.pins) gpioWriteOn<true>(pin, level);  // a member board's port pins drive nothing of the pack
}

template <bool Pins>
void FirmwareHost::gpioWriteOn(uint8_t pin, int32_t level) {
  if (!Pins) return;
  if (pin >= std::size(kOutputPins)) {  // unconnected
    noteNoChannel(ServiceMisuse::kGpioWrite, pin, level, 0);
    if (!pinsNoted_) notePins();
    return;
  }
  // (A reference, not a pointer that may be null: no test of the field's address, five
  // writes a tick.)
  bool& field = out_->*kOutputPins[pin];
  const bool on = level != 0;
  if (pinsNoted_ && field == on) return;  // the level it has: no change to note
  field = on;
  notePins();
}

void FirmwareHost::notePins() {
  pinsNoted_ = true;
  const PinLevels p = pinsOf(*out_);
  if (p == lastPins_) return;
  lastPins_ = p;
  pinChanges_.push_back({clock_s(), p});
}

void FirmwareHost::dacWrite(uint8_t channel, int32_t value) {
  if (channel == PSFW_DAC_CHARGER_CURRENT_MA) {
    const int32_t mA = std::max<int32_t>(0, value);
    if (pinsNoted_ && out_->chargerCurrentRequest_mA == mA) return;
    out_->chargerCurrentRequest_mA = mA;
  } else {
    if (board_.pins) noteNoChannel(ServiceMisuse::kDacWrite, channel, value, 0);
    if (pinsNoted_) return;
  }
  notePins();
}

void FirmwareHost::noteNoChannel(ServiceMisuse::Service s, uint8_t channel, int32_t value, int32_t returned) const {
  if (!misuse_.first(s, channel)) return;
  // The event is host code: a library's watchdog must not cut through it (FaultGuard).
  if (guard_) FaultGuard::enterService();
  sink_.event(clock_s(), "firmware_misuse", ServiceMisuse::text(s, channel, value, returned, board_.mcuThermistors));
  if (guard_) FaultGuard::leaveService();
}

int32_t FirmwareHost::setTaskPeriod(uint32_t task, uint32_t period_ms, uint32_t budget_us) {
  if (!inInit_ || task >= fw_.task_count) return noChannel();
  fw_.tasks[task].period_ms = period_ms;
  fw_.tasks[task].budget_us = budget_us;
  return 0;
}

int32_t FirmwareHost::canSend(uint8_t can, uint32_t id, const uint8_t* data, uint8_t len) {
  if (can != 0 || board_.can == nullptr) return noChannel();
  if (id > 0x7FFu || len > 8) {
    breakContract("can_send of id 0x%X with %u bytes: a classic frame has an 11-bit id and at most 8 bytes", id, len);
    return PSFW_BUS_ERROR;
  }
  if (len > 0 && data == nullptr) {
    breakContract("can_send with a null buffer and a non-zero length");
    return PSFW_BUS_ERROR;
  }
  uint8_t copy[8];  // copied first: a bad pointer faults before the bus changes
  if (len > 0) std::memcpy(copy, data, len);
  return board_.can->send(board_.canNode, clock_s(), id, copy, len) ? 0 : PSFW_BUS_TIMEOUT;
}

int32_t FirmwareHost::canReceive(uint8_t can, uint32_t* id, uint8_t* data) {
  if (can != 0 || board_.can == nullptr) return noChannel();
  if (id == nullptr || data == nullptr) {
    breakContract("can_receive with a null id or data buffer");
    return PSFW_BUS_ERROR;
  }
  uint32_t got = 0;
  uint8_t bytes[8];
  const int len = board_.can->receive(board_.canNode, clock_s(), got, bytes);
  if (len < 0) return PSFW_BUS_TIMEOUT;
  *id = got;
  if (len > 0) std::memcpy(data, bytes, static_cast<size_t>(len));
  return len;
}

int32_t FirmwareHost::nvmRead(uint32_t offset, uint8_t* data, uint32_t len) {
  if (uint64_t{offset} + len > PSFW_NVM_BYTES) return noChannel();
  if (len > 0 && data == nullptr) {
    breakContract("nvm_read with a null buffer and a non-zero length");
    return PSFW_BUS_ERROR;
  }
  if (len > 0) std::memcpy(data, nvm_.data() + offset, len);
  return static_cast<int32_t>(len);
}

int32_t FirmwareHost::nvmWrite(uint32_t offset, const uint8_t* data, uint32_t len) {
  if (uint64_t{offset} + len > PSFW_NVM_BYTES) return noChannel();
  if (len > 0 && data == nullptr) {
    breakContract("nvm_write with a null buffer and a non-zero length");
    return PSFW_BUS_ERROR;
  }
  if (len == 0) return 0;
  uint8_t copy[PSFW_NVM_BYTES];  // copied first: a bad pointer faults before the page changes
  std::memcpy(copy, data, len);
  std::memcpy(nvm_.data() + offset, copy, len);
  const uint32_t pages = (offset + len - 1) / PSFW_NVM_WRITE_PAGE_BYTES - offset / PSFW_NVM_WRITE_PAGE_BYTES + 1;
  clock_ns_ += uint64_t{pages} * PSFW_NVM_WRITE_US * 1000u;
  checkBudget();
  return static_cast<int32_t>(len);
}

void FirmwareHost::telemetrySend(const uint8_t* bytes, uint16_t len) {
  if (len > 0 && bytes == nullptr) return breakContract("telemetry_send with a null buffer and a non-zero length");
  const size_t n = std::min<size_t>(len, kTelemetryKeep);
  if (!guard_) {  // trusted code (linked in, or read from the virtual MCU's memory): kept at once
    ++telemetryFrames_;
    lastTelemetry_.resize(n);
    if (n > 0) copyBytes(lastTelemetry_.data(), bytes, n);
    return;
  }
  uint8_t kept[kTelemetryKeep];  // a library's: copied first, a bad pointer faults before host data changes
  if (n > 0) copyBytes(kept, bytes, n);
  ++telemetryFrames_;
  lastTelemetry_.resize(n);
  if (n > 0) copyBytes(lastTelemetry_.data(), kept, n);
}

void FirmwareHost::firmwareEvent(const char* text) {
  if (text == nullptr) return breakContract("event with a null text");
  char kept[kEventChars + 1];
  size_t n = 0;
  for (; n < kEventChars && text[n] != '\0'; ++n) kept[n] = (text[n] >= 0x20 && text[n] < 0x7F) ? text[n] : '?';
  kept[n] = '\0';
  const double t_s = clock_s();
  static const char kTrip[] = "trip: ";
  if (std::strncmp(kept, kTrip, sizeof kTrip - 1) == 0) {
    sink_.trip(t_s, kept + sizeof kTrip - 1);
  } else if (!tripTextWarned_ && looksLikeATrip(kept)) {
    // Not counted: without a word the summary said "no trip" and expect: {no_trip: true}
    // passed while the firmware had isolated the pack (said once a run).
    tripTextWarned_ = true;
    char note[360];
    std::snprintf(note, sizeof note,
                  "firmware event '%s' at %.6f s reads as a trip report but is not counted as one: a trip is an "
                  "event that starts exactly with 'trip: ' (lower case, a colon, a space), then the reason; the "
                  "summary and expect: judge the run without it",
                  kept, t_s);
    sink_.event(t_s, "config_warning", note);
  }
  sink_.event(t_s, "firmware", kept);
}

}  // namespace packsim
