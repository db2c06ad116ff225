// The board a firmware runs on (bms/packsim_fw.h, docs/firmware.md): a user's library
// (loaded at run time) or a firmware linked into packsim (its own core, bms_firmware.hpp).
// The host gives it zeroed RAM, runs its init and its periodic tasks, and implements the
// board services on the simulated hardware.
//
// Scheduling (non-preemptive, like a cooperative main loop on the MCU): init runs at
// t = 0; task i runs at n·period_i (n = 1, 2, ...). step(t) runs every instance due in
// [t, t + tick) in time order, several due at once in declaration order. Each starts
// at its due time or when the previous call finished, whichever is later; bus
// transfers and delay_us advance the MCU clock by the time they take. The pins and ADC
// hold what was sampled at t (step 1 of the tick) and the outputs act from the tick's
// actuation (step 3): a task whose period is not a multiple of the BMS tick still runs
// at its own due times on its clock, with its I/O resolved to the tick it falls in.
//
// Isolation: a contract break (bad bus id or frame length, a null buffer, init
// returning non-zero, an ABI mismatch, a task running past its budget in simulated time
// through bus traffic or delays) stops the firmware for good: one firmware_fault event,
// the MCU is dead and its outputs hold their last levels, as for a hung host. A library
// runs under the fault guard (fault_guard.hpp), which also catches a crash or a hang
// past the watchdog and ends the call at once; a linked-in firmware is trusted code run
// without the guard's signal handlers (its per-tick cost), so a service that finds a
// contract break returns an error and the firmware is stopped when the call returns.
#pragma once
#include <bms/bms_hal.hpp>
#include <bms/packsim_fw.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/firmware/can_bus.hpp"
#include "core/firmware/fault_guard.hpp"
#include "core/firmware/firmware_library.hpp"
#include "core/firmware/monitor_bus.hpp"
#include "core/firmware/pin_timeline.hpp"
#include "core/firmware/service_misuse.hpp"
#include "core/firmware/target_firmware.hpp"
#include "core/scenario/firmware_config.hpp"

namespace packsim {

// Where the host's events go (the run's event log).
class FirmwareSink {
 public:
  virtual ~FirmwareSink() = default;
  virtual void event(double t_s, const std::string& kind, const std::string& detail) = 0;
  // The firmware reported a trip: event text "trip: <reason>".
  virtual void trip(double t_s, const std::string& reason) = 0;
};

// What the MCU a firmware runs on is wired to.
struct FirmwareBoard {
  std::vector<MonitorBus*> buses;  // bus id n reaches buses[n] (not owned)
  int mcuThermistors = 0;          // thermistor channels on the MCU's own ADC (PSFW_ADC_THERMISTOR0 + n)
  bool pins = true;                // current-sense and bus ADC, GPIO in and out wired (the pack host);
                                   // false: a member board's MCU, reading PSFW_NO_CHANNEL there
  CanBus* can = nullptr;           // CAN bus 0, shared with the pack's other boards (not owned); none alone
  int canNode = 0;                 // this MCU's node on it
};

class FirmwareHost {
 public:
  // A user library (s.library_path, s.config, s.watchdog_s) on `board`; with s.target,
  // the ELF at s.library_path on the virtual MCU (target_firmware.hpp).
  FirmwareHost(const FirmwareSettings& s, FirmwareBoard board, double tick_s, FirmwareSink& sink);
  // A firmware linked into packsim, with its configuration blob.
  FirmwareHost(const psfw_firmware* linked, std::vector<uint8_t> config, FirmwareBoard board, double tick_s,
               FirmwareSink& sink);
  ~FirmwareHost();
  FirmwareHost(const FirmwareHost&) = delete;
  FirmwareHost& operator=(const FirmwareHost&) = delete;

  // Step 2 of the tick at t_s: init on the first call, then the task instances due in
  // [t_s, t_s + tick). `in` holds the pins and codes sampled at t_s; `out` receives the
  // GPIO and DAC writes (left as they are once the firmware is dead).
  void step(double t_s, const bms::Inputs& in, bms::Outputs& out);
  // The output changes since the last call, each at the MCU clock's instant of the
  // write (a watchdog reset's drop at the reset's instant), in time order.
  std::vector<PinChange> takePinChanges() { return std::move(pinChanges_); }
  // Brown-out: the MCU's supply is below its threshold at the tick t_s (instead of
  // step()). On the first such tick the MCU resets: one mcu_reset event (`why` and what
  // the reset clears), the outputs drop to their reset level at t_s, no call runs; its
  // RAM is lost. The next step() boots it: entry and init again on zeroed instance RAM
  // (target mode: RAM reloaded from the ELF except .noinit). The NVM page is kept. A
  // firmware that has failed (dead()) stays stopped.
  void holdInReset(double t_s, const std::string& why, bms::Outputs& out);
  bool heldInReset() const { return heldInReset_; }
  // MCU resets so far (watchdog and brown-out).
  uint32_t resets() const { return resets_; }

  bool dead() const { return dead_; }
  const std::string& name() const { return name_; }
  const std::string& faultCause() const { return cause_; }
  double faultTime_s() const { return faultTime_s_; }
  // One line for the summary: "<name>: ran to the end" or the fault.
  std::string status() const;
  uint64_t telemetryFrames() const { return telemetryFrames_; }
  const std::vector<uint8_t>& lastTelemetry() const { return lastTelemetry_; }
  // (Through int64_t below 2^63 ns, 292 years: the same double, one instruction where
  // x86-64's unsigned 64-bit conversion takes a branch and several; at every bus transfer.)
  double clock_s() const {
    const double ns = clock_ns_ < (uint64_t{1} << 63) ? static_cast<double>(static_cast<int64_t>(clock_ns_))
                                                       : static_cast<double>(clock_ns_);
    return ns * 1e-9;
  }
  uint64_t taskRuns(int task) const { return runs_[static_cast<size_t>(task)]; }
  // The longest simulated time one call of `task` took so far (bus transfers and
  // delays: the firmware's own code takes none), 0 before it ran.
  double worstTaskTime_s(int task) const {
    return static_cast<size_t>(task) < worst_ns_.size() ? static_cast<double>(worst_ns_[static_cast<size_t>(task)]) * 1e-9
                                                       : 0.0;
  }
  // Off: a task may run past its budget (a probe that measures what a task needs).
  void enforceBudgets(bool on) {
    enforceBudgets_ = on;
    setBudget(callStart_ns_, callBudget_ns_);
  }
  // The firmware's RAM (null before init): for a debug probe of a linked-in firmware.
  const void* ram() const { return ram_.get(); }
  // Target mode: the virtual MCU's counts (null in host mode).
  const TargetFirmware* target() const { return target_.get(); }
  // Target mode: summary lines (per task: instructions, cycles, worst case; CPU load,
  // stack high-water, resets) over `elapsed_s` of run; empty in host mode.
  std::vector<std::string> targetSummary(double elapsed_s) const;
  // The same figures by name (target_cycles, target_task0_worst_cycles, ...); empty in host mode.
  std::vector<std::pair<std::string, double>> targetFigures(double elapsed_s) const;

  // The MCU-ADC thermistor inputs (bit n: PSFW_ADC_THERMISTOR0 + n) the firmware read at
  // least once: a firmware configured for fewer never sees the others (core/sim/read_coverage.hpp).
  uint64_t mcuThermistorsRead() const { return mcuThermistorsRead_; }

  // Board services (the psfw_board_api entries land here).
  uint32_t nowMs() const { return static_cast<uint32_t>(clock_ns_ / 1000000u); }
  uint32_t nowUs() const { return static_cast<uint32_t>(clock_ns_ / 1000u); }
  void delayUs(uint32_t us);
  int32_t busTransfer(uint8_t bus, const uint8_t* tx, uint16_t txLen, uint8_t* rx, uint16_t rxLen);
  int32_t adcRead(uint8_t channel) const;
  int32_t gpioRead(uint8_t pin) const;
  void gpioWrite(uint8_t pin, int32_t level);
  // The same three for a board whose pins are wired (Pins) or not, as the service table
  // built for the board calls them (board_.pins is tested once, at construction).
  template <bool Pins>
  int32_t adcReadOn(uint8_t channel) const;
  template <bool Pins>
  int32_t gpioReadOn(uint8_t pin) const;
  template <bool Pins>
  void gpioWriteOn(uint8_t pin, int32_t level);
  void dacWrite(uint8_t channel, int32_t value);
  void telemetrySend(const uint8_t* bytes, uint16_t len);
  void firmwareEvent(const char* text);
  int32_t setTaskPeriod(uint32_t task, uint32_t period_ms, uint32_t budget_us);
  int32_t canSend(uint8_t can, uint32_t id, const uint8_t* data, uint8_t len);
  int32_t canReceive(uint8_t can, uint32_t* id, uint8_t* data);
  int32_t nvmRead(uint32_t offset, uint8_t* data, uint32_t len);
  int32_t nvmWrite(uint32_t offset, const uint8_t* data, uint32_t len);
  // The NVM page as it is now (erased 0xFF at the run's start; kept across resets).
  const std::array<uint8_t, PSFW_NVM_BYTES>& nvm() const { return nvm_; }
  // "No such channel" in the firmware's contract version: its own code from version 3,
  // the code versions 1 and 2 shared with PSFW_BUS_TIMEOUT before (packsim_fw.h).
  int32_t noChannel() const { return fw_.abi_version >= 3u ? PSFW_NO_CHANNEL : PSFW_NO_CHANNEL_V2; }

 private:
  mutable uint64_t mcuThermistorsRead_ = 0;  // adcRead notes each thermistor channel read (at most 48)
  // A service called for a channel or pin this board does not have: its event, once per
  // service and channel (service_misuse.hpp); out of line, off the per-tick path.
  mutable ServiceMisuse misuse_;
  __attribute__((noinline)) void noteNoChannel(ServiceMisuse::Service s, uint8_t channel, int32_t value,
                                                int32_t returned) const;
  friend class TargetFirmware;  // runs the calls of target mode and serves its supervisor calls
  struct Call;  // one call into the firmware (guarded for a library)
  void watchdogReset();
  bool bootAfterReset(uint64_t windowEnd_ns, bms::Outputs& out);
  // Target mode: the interrupts taken before before_ns while the MCU idles between calls.
  bool runInterrupts(uint64_t before_ns);
  bool call(const char* what, int task);
  int firstDue(uint64_t end_ns) const;
  __attribute__((noinline)) bool callFull(const char* what, int task);
  std::string callName(const char* what, int task) const;
  void failed(double start_s, const std::string& where, const GuardResult& r);
  void start(double t_s);
  void fault(double t_s, const std::string& cause);
  // Records the cause; under the guard the call ends here (longjmp), else the service
  // returns and the firmware is stopped when its call returns.
  void breakContract(const char* fmt, ...) __attribute__((format(printf, 2, 3)));
  // After a bus transfer, delay or NVM write: within the running task's budget (inline:
  // several times a tick), else a contract break (overBudget).
  // (One compare with the running call's deadline: the clock never runs back, so
  // clock - start <= budget is clock <= start + budget.)
  bool checkBudget() { return clock_ns_ <= callDeadline_ns_ || overBudget(); }
  // The running call's start and budget (0: none) and its deadline: the far future without
  // a budget, with budgets off, or past the clock's range.
  void setBudget(uint64_t start_ns, uint64_t budget_ns) {
    callStart_ns_ = start_ns;
    callBudget_ns_ = budget_ns;
    const uint64_t never = ~uint64_t{0};
    callDeadline_ns_ = !enforceBudgets_ || budget_ns == 0 || budget_ns > never - start_ns ? never : start_ns + budget_ns;
  }
  bool overBudget();
  void notePins();  // after a GPIO or DAC write: a change of the levels, at the MCU clock

  std::vector<uint8_t> config_;
  double watchdog_s_;
  FirmwareBoard board_;
  uint64_t tick_ns_;
  FirmwareSink& sink_;
  std::unique_ptr<FirmwareLibrary> lib_;  // a user library; null for a linked-in firmware
  const psfw_firmware* linked_ = nullptr;
  std::unique_ptr<FaultGuard> guard_;     // libraries only
  std::unique_ptr<TargetFirmware> target_;  // target mode only
  bool resetPending_ = false;                // a watchdog reset whose tick has not come yet
  bool heldInReset_ = false;                 // brown-out: the supply is below the threshold
  uint32_t resets_ = 0;                      // MCU resets so far, either cause
  uint64_t resetAt_ns_ = 0;
  psfw_firmware fw_{};
  psfw_board_api api_{};
  std::unique_ptr<std::max_align_t[]> ram_;
  std::string name_;
  bool started_ = false, dead_ = false, inInit_ = false;
  bool tripTextWarned_ = false;  // a firmware event that reads as a trip but is not "trip: " was named
  std::string cause_;
  double faultTime_s_ = 0.0;
  char breakCause_[160] = {0};  // set before a longjmp out of a service
  uint64_t breakAt_ns_ = 0;      // the simulated clock when it was set
  uint64_t clock_ns_ = 0;
  std::vector<uint64_t> nextDue_ns_;
  std::vector<uint64_t> runs_;
  std::vector<uint64_t> worst_ns_;  // per task: the longest call
  bool enforceBudgets_ = true;
  uint64_t callStart_ns_ = 0, callBudget_ns_ = 0;  // the running task's start and budget (0: none): setBudget
  uint64_t callDeadline_ns_ = ~uint64_t{0};        // the clock past which it is over budget
  int32_t initResult_ = 0;
  const bms::Inputs* in_ = nullptr;
  bms::Outputs* out_ = nullptr;
  uint64_t telemetryFrames_ = 0;
  std::vector<uint8_t> lastTelemetry_;
  std::array<uint8_t, PSFW_NVM_BYTES> nvm_;  // the board's NVM page: outside the MCU, kept across its resets
  PinLevels lastPins_;                  // the levels of the last recorded change (all off at power-up)
  bool pinsNoted_ = false;              // the pins of *out_ are lastPins_: a write of a pin's own level changes nothing
  std::vector<PinChange> pinChanges_;   // since the last takePinChanges()
};

}  // namespace packsim
