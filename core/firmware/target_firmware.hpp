// A firmware ELF on the virtual Cortex-M4 (bms.firmware.target: cortex-m4), driven by
// the firmware host (firmware_host.hpp) exactly as a library is: the host's scheduler
// calls the entry, init and the tasks (through the board-support layer's psbsp_entry,
// psbsp_init, psbsp_task), a SysTick-style tick, and the board's services are the
// host's own, reached from the firmware's supervisor calls (psbsp_board.c's numbers
// below). The MCU clock advances by the cycles the code takes (cycle_model.hpp) at the
// configured clock as well as by bus time and delays, so a task's budget counts its code.
//
// The watchdog (psbsp.h): started by the firmware, kicked after every task that returns
// (and by the firmware at will); a missed kick resets the MCU: its outputs drop to their
// reset level, RAM is reloaded from the ELF except .noinit, and the entry and init run
// again in the BMS tick that holds the reset's instant.
//
// Interrupts (target_mcu.hpp, target_nvic.hpp): the monitor ALERT / FAULT line (an edge
// at a tick's sample or after a bus transfer), the board's timer (psbsp.h) pend their
// NVIC lines at their instants; a running call stops at the instruction boundary its
// cycle count reaches there and enters the handler; between calls the MCU leaves its
// idle loop for it (FirmwareHost::step). Per interrupt: calls, handler cycles, latency.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/firmware/elf_image.hpp"
#include "core/firmware/target_mcu.hpp"

namespace packsim {

class FirmwareHost;

// The supervisor calls of psbsp_board.c.
enum TargetService : unsigned {
  kSvcNowMs = 1, kSvcNowUs, kSvcDelayUs, kSvcBusTransfer, kSvcAdcRead, kSvcGpioRead, kSvcGpioWrite, kSvcDacWrite,
  kSvcTelemetrySend, kSvcEvent, kSvcSetTaskPeriod, kSvcCanSend, kSvcCanReceive, kSvcNvmRead, kSvcNvmWrite
};

// What the code of one task cost, over the run.
struct TargetTaskStats {
  uint64_t calls = 0;
  uint64_t instructions = 0, cycles = 0;            // totals
  uint64_t worstInstructions = 0, worstCycles = 0;  // the longest call's
  uint64_t cyclesMin = 0, cyclesMax = 0;            // the totals at the TRM ranges' ends (the model's error)
  uint32_t stack_bytes = 0;                         // the deepest stack of any call
};

// What one interrupt's handler cost, over the run.
struct TargetIrqStats {
  uint64_t calls = 0;
  uint64_t cycles = 0, worstCycles = 0;  // its own (entry and return included, nested handlers not)
  uint64_t worstLatency_ns = 0;          // from the instant it was pended to its first instruction
};

// The board's peripheral page (psbsp.h): the timer's registers.
constexpr uint32_t kTimerCtrl = 0x000, kTimerPeriodUs = 0x004, kTimerCount = 0x008;
constexpr uint32_t kCanIer = 0x400;       // bit 0: the CAN receive interrupt while a frame waits
constexpr uint32_t kInstanceRam = 0xFF0;  // the firmware's RAM (psbsp_ram(), for handlers)

class TargetFirmware : public TargetPeripherals {
 public:
  TargetFirmware(FirmwareHost& host, const std::string& elfPath, uint32_t clock_hz);
  ~TargetFirmware() override;
  // Why the MCU could not be set up ("" if it was): a firmware_fault at power-up.
  const std::string& error() const { return error_; }

  // One call (the host's task numbering: -2 entry, -1 init, n task n, kInterruptCall an
  // interrupt taken from the idle loop). False when it
  // did not return: the host's MCU is then dead (a fault or contract break, recorded),
  // or it was reset by the watchdog (resetPending()).
  bool call(const char* what, int task);
  bool resetPending() const { return resetPending_; }
  static constexpr int kInterruptCall = -3;
  // The monitor ALERT / FAULT line's level at t_ns (the tick's sample, or after a bus
  // transfer): its assertion pends PSBSP_ALERT_IRQn (an EXTI line on its rising edge).
  void monitorLine(bool asserted, uint64_t t_ns);
  // While the MCU idles from now_ns: the first instant before before_ns at which an
  // interrupt is taken (the sources pended up to there); false if none.
  bool nextIdleInterrupt(uint64_t now_ns, uint64_t before_ns, uint64_t& at_ns);
  const std::array<TargetIrqStats, kTargetIrqLines>& irqStats() const { return irqStats_; }
  static const char* irqName(int irq);
  // The reset (the watchdog's, or a brown-out's): RAM reloaded except .noinit, the
  // watchdog stopped; the host runs the entry and init again.
  void reset(bool watchdog);
  // The watchdog's deadline on the MCU clock (ns), if it runs.
  bool watchdogExpired(uint64_t clock_ns) const { return wdgRunning_ && clock_ns > wdgLastKick_ns_ + wdgTimeout_ns_; }
  uint64_t watchdogDeadline_ns() const { return wdgLastKick_ns_ + wdgTimeout_ns_; }
  uint64_t watchdogTimeout_ns() const { return wdgTimeout_ns_; }
  void expire() { resetPending_ = true; }

  uint32_t clock_hz() const { return clock_hz_; }
  const std::vector<TargetTaskStats>& taskStats() const { return stats_; }
  uint64_t totalCycles() const { return mcu_ ? mcu_->cycles() : 0; }
  uint64_t totalCyclesMin() const { return mcu_ ? mcu_->cyclesMin() : 0; }
  uint64_t totalCyclesMax() const { return mcu_ ? mcu_->cyclesMax() : 0; }
  uint64_t totalInstructions() const { return mcu_ ? mcu_->instructions() : 0; }
  uint32_t stackHighWater_bytes() const { return stackHighWater_; }
  uint32_t stackSize_bytes() const { return mcu_ ? mcu_->stackBytes() : 0; }
  uint32_t resets() const { return resets_; }  // the watchdog's (PSBSP_WDG_RESETS)
  // The firmware's instance RAM as the descriptor sized it, and a copy of it out of the
  // MCU's memory (a debug probe of packsim's core); false before the entry ran.
  uint32_t instanceBytes() const { return instanceBytes_; }
  bool readInstanceRam(void* out, size_t n) const { return mcu_ && ram_ != 0 && mcu_->read(ram_, out, n); }

  uint32_t supervisorCall(TargetMcu& mcu, unsigned number) override;
  uint32_t peripheralRead(TargetMcu& mcu, uint32_t offset) override;
  void peripheralWrite(TargetMcu& mcu, uint32_t offset, uint32_t value) override;
  uint32_t watchdogRead(uint32_t offset) override;
  void watchdogWrite(TargetMcu& mcu, uint32_t offset, uint32_t value) override;

 private:
  void syncClock();
  // Cycles from now until the MCU clock reaches t_ns (0 if it has).
  uint64_t cyclesUntil(uint64_t t_ns) const;
  // The interrupt sources (the timer) pend what is due by t_ns; the next instant one will.
  void pendSources(uint64_t t_ns);
  uint64_t nextSourceInstant() const;
  void pend(int irq, uint64_t t_ns);
  // Handler bookkeeping: entry (the MCU's counts before it; the clock synced after it) and return.
  void entered(int irq, uint64_t cyclesBefore, uint64_t instructionsBefore);
  void returned(int irq);
  void setDeadline();
  bool copyIn(uint32_t addr, void* out, size_t n, const char* what);
  bool copyOut(uint32_t addr, const void* in, size_t n, const char* what);
  bool readDescriptor(uint32_t addr, std::string& why);

  FirmwareHost& host_;
  uint32_t clock_hz_;
  std::unique_ptr<ElfImage> elf_;
  std::unique_ptr<TargetMcu> mcu_;
  std::string error_;
  uint32_t desc_ = 0, ram_ = 0, config_ = 0;  // addresses in the MCU's memory
  uint64_t syncedCycles_ = 0;
  uint64_t cycleFraction_ = 0;  // cycles·1e9 not yet turned into whole ns
  uint64_t runawayCycles_;      // a call's hard limit when no budget applies
  uint64_t callStartCycles_ = 0, callStartMin_ = 0, callStartMax_ = 0;
  std::vector<TargetTaskStats> stats_;
  uint32_t stackHighWater_ = 0;
  bool wdgRunning_ = false, resetPending_ = false;
  uint32_t wdgTimeoutUs_ = 0;
  uint64_t wdgTimeout_ns_ = 0, wdgLastKick_ns_ = 0;
  uint32_t resets_ = 0;     // watchdog resets
  uint32_t brownouts_ = 0;  // brown-out resets

  std::array<TargetIrqStats, kTargetIrqLines> irqStats_{};
  std::array<uint64_t, kTargetIrqLines> pendAt_ns_;  // UINT64_MAX: not pended by a source
  struct Handler {
    int irq;
    uint64_t cycles, instructions, min, max;  // the MCU's counts before its entry
    uint64_t nested = 0;                      // cycles of handlers that pre-empted it
  };
  std::vector<Handler> handlers_;  // running, innermost last
  // The top-level handlers' totals in the running call (a task's own counts exclude them).
  uint64_t handlerCycles_ = 0, handlerInstructions_ = 0, handlerMin_ = 0, handlerMax_ = 0;
  bool lineKnown_ = false, lineLevel_ = false;
  bool timerOn_ = false;
  uint32_t timerPeriodUs_ = 0;
  uint64_t timerNext_ns_ = 0, timerCount_ = 0;
  bool canIe_ = false;
  uint32_t instanceBytes_ = 0;
};

}  // namespace packsim
