#include "core/firmware/target_firmware.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>

#include "core/firmware/firmware_host.hpp"
#include "core/firmware/target_memory_map.hpp"

namespace packsim {

namespace {

// A non-null stand-in for a function that lives in the MCU's flash: the host's
// descriptor checks ask only whether a task has one (psbsp_task calls the real one).
void targetTask(void*, psfw_board*, const psfw_board_api*) {}
int32_t targetInit(void*, psfw_board*, const psfw_board_api*, const uint8_t*, uint32_t) { return 0; }

constexpr uint32_t kDescriptorBytes = 20 + 12 * PSFW_MAX_TASKS;  // psfw_firmware on a 32-bit ARM
constexpr size_t kNameChars = 65;

uint32_t align8(uint32_t a) { return (a + 7u) & ~7u; }

// An instant on the CAN bus (s) as the MCU clock's ns at or just after it.
uint64_t toNsCeil(double t_s) { return static_cast<uint64_t>(std::llround(t_s * 1e9)) + 1u; }

uint32_t word(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

}  // namespace

TargetFirmware::TargetFirmware(FirmwareHost& host, const std::string& elfPath, uint32_t clock_hz)
    : host_(host), clock_hz_(clock_hz), runawayCycles_(UINT64_MAX) {
  pendAt_ns_.fill(UINT64_MAX);
  try {
    elf_ = std::make_unique<ElfImage>(readTargetElf(elfPath));
    mcu_ = std::make_unique<TargetMcu>(*elf_);
    mcu_->loadRam(false);
  } catch (const std::exception& e) {
    error_ = e.what();
    mcu_.reset();
  }
}

TargetFirmware::~TargetFirmware() = default;

uint64_t TargetFirmware::cyclesUntil(uint64_t t_ns) const {
  // The smallest n with clock + floor((n·1e9 + fraction) / f) >= t.
  if (t_ns <= host_.clock_ns_) return 0;
  const unsigned __int128 need = static_cast<unsigned __int128>(t_ns - host_.clock_ns_) * clock_hz_;
  if (need <= cycleFraction_) return 0;
  const unsigned __int128 n = (need - cycleFraction_ + 999999999u) / 1000000000u;
  return n > UINT64_MAX / 2 ? UINT64_MAX / 2 : static_cast<uint64_t>(n);
}

void TargetFirmware::pend(int irq, uint64_t t_ns) {
  TargetNvic& n = mcu_->nvic();
  if (!n.pending(irq)) pendAt_ns_[static_cast<size_t>(irq)] = t_ns;
  n.pend(irq);
}

void TargetFirmware::pendSources(uint64_t t_ns) {
  if (!mcu_) return;
  CanBus* can = host_.board_.can;
  if (canIe_ && can && !mcu_->nvic().active(kTargetIrqCanRx)) {  // a level: while a frame waits
    const double at = can->oldestArrived(host_.board_.canNode, static_cast<double>(t_ns) * 1e-9);
    if (std::isfinite(at)) pend(kTargetIrqCanRx, toNsCeil(at));
  }
  while (timerOn_ && timerNext_ns_ <= t_ns) {  // expiries while pending merge into one (the NVIC has one bit)
    pend(kTargetIrqTimer, timerNext_ns_);
    ++timerCount_;
    timerNext_ns_ += uint64_t{timerPeriodUs_} * 1000u;
  }
}

uint64_t TargetFirmware::nextSourceInstant() const {
  uint64_t next = timerOn_ ? timerNext_ns_ : UINT64_MAX;
  CanBus* can = host_.board_.can;
  if (canIe_ && can && mcu_ && !mcu_->nvic().active(kTargetIrqCanRx)) {
    // The next frame's arrival (1 ns after it, so that the bus has it at that instant).
    const double at = can->nextArrival(host_.board_.canNode, static_cast<double>(host_.clock_ns_) * 1e-9);
    if (std::isfinite(at)) next = std::min(next, toNsCeil(at));
  }
  return next;
}

void TargetFirmware::monitorLine(bool asserted, uint64_t t_ns) {
  if (mcu_ && lineKnown_ && asserted && !lineLevel_) pend(kTargetIrqAlert, t_ns);
  lineKnown_ = true;
  lineLevel_ = asserted;
}

bool TargetFirmware::nextIdleInterrupt(uint64_t now_ns, uint64_t before_ns, uint64_t& at_ns) {
  if (!mcu_) return false;
  pendSources(now_ns);
  const int prio = mcu_->executionPriority();  // thread mode: the masks the code left set
  if (mcu_->nvic().next(prio) >= 0) {
    at_ns = now_ns;
    return now_ns < before_ns;
  }
  for (uint64_t s = nextSourceInstant(); s < before_ns; s = nextSourceInstant()) {
    pendSources(s);
    if (mcu_->nvic().next(prio) >= 0) {
      at_ns = s;
      return true;
    }
  }
  return false;
}

const char* TargetFirmware::irqName(int irq) {
  switch (irq) {
    case kTargetIrqAlert: return "ALERT";
    case kTargetIrqCanRx: return "CAN receive";
    default: return "timer";
  }
}

void TargetFirmware::entered(int irq, uint64_t cyclesBefore, uint64_t instructionsBefore) {
  Handler hd{irq, cyclesBefore, instructionsBefore, 0, 0};
  hd.min = mcu_->cyclesMin() - (mcu_->cycles() - cyclesBefore);
  hd.max = mcu_->cyclesMax() - (mcu_->cycles() - cyclesBefore);
  handlers_.push_back(hd);
  uint64_t& at = pendAt_ns_[static_cast<size_t>(irq)];
  if (at != UINT64_MAX) {
    const uint64_t first_ns = host_.clock_ns_;  // synced after the entry: its first instruction's instant
    TargetIrqStats& s = irqStats_[static_cast<size_t>(irq)];
    s.worstLatency_ns = std::max(s.worstLatency_ns, first_ns > at ? first_ns - at : 0);
    at = UINT64_MAX;
  }
}

void TargetFirmware::returned(int irq) {
  if (handlers_.empty() || handlers_.back().irq != irq) return;
  const Handler hd = handlers_.back();
  handlers_.pop_back();
  const uint64_t total = mcu_->cycles() - hd.cycles;
  const uint64_t own = total - hd.nested;
  TargetIrqStats& s = irqStats_[static_cast<size_t>(irq)];
  ++s.calls;
  s.cycles += own;
  s.worstCycles = std::max(s.worstCycles, own);
  if (!handlers_.empty()) {
    handlers_.back().nested += total;
  } else {
    handlerCycles_ += total;
    handlerInstructions_ += mcu_->instructions() - hd.instructions;
    handlerMin_ += mcu_->cyclesMin() - hd.min;
    handlerMax_ += mcu_->cyclesMax() - hd.max;
  }
}

void TargetFirmware::syncClock() {
  const uint64_t n = mcu_->cycles() - syncedCycles_;
  syncedCycles_ = mcu_->cycles();
  const unsigned __int128 total = static_cast<unsigned __int128>(n) * 1000000000u + cycleFraction_;
  host_.clock_ns_ += static_cast<uint64_t>(total / clock_hz_);
  cycleFraction_ = static_cast<uint64_t>(total % clock_hz_);
}

// The cycle count at which the running call must stop to be judged: its budget ends,
// the watchdog runs out, or the runaway limit.
void TargetFirmware::setDeadline() {
  const FirmwareHost& h = host_;
  // Cycles whose time exceeds ns (by at least 1 ns after the clock's rounding down).
  const auto cyclesPast = [&](uint64_t ns) {
    return static_cast<uint64_t>(static_cast<unsigned __int128>(ns + 1) * clock_hz_ / 1000000000u) + 1;
  };
  uint64_t limit = callStartCycles_ + runawayCycles_;
  if (h.enforceBudgets_ && h.callBudget_ns_ != 0) {
    const uint64_t used = h.clock_ns_ - h.callStart_ns_;
    limit = std::min(limit, syncedCycles_ + cyclesPast(h.callBudget_ns_ > used ? h.callBudget_ns_ - used : 0));
  }
  if (wdgRunning_) {
    const uint64_t d = watchdogDeadline_ns();
    limit = std::min(limit, syncedCycles_ + cyclesPast(d > h.clock_ns_ ? d - h.clock_ns_ : 0));
  }
  mcu_->setCycleDeadline(limit);
  const uint64_t src = nextSourceInstant();
  mcu_->setInterruptDueCycles(src == UINT64_MAX ? UINT64_MAX : syncedCycles_ + cyclesUntil(src));
}

bool TargetFirmware::call(const char* what, int task) {
  FirmwareHost& h = host_;
  h.breakCause_[0] = '\0';
  resetPending_ = false;
  const double start_s = h.clock_s();
  std::string where = what;
  if (task >= 0) where += " " + std::to_string(task) + " (period " + std::to_string(h.fw_.tasks[task].period_ms) + " ms)";
  if (task == kInterruptCall) where = "an interrupt handler";
  if (!mcu_) {
    h.fault(start_s, error_);
    return false;
  }
  if (watchdogExpired(h.clock_ns_)) {  // it ran out while the MCU was idle between calls
    resetPending_ = true;
    return false;
  }
  runawayCycles_ = static_cast<uint64_t>(h.watchdog_s_ * clock_hz_);
  uint32_t fn = 0;
  std::vector<uint32_t> args;
  if (task == -2) {
    fn = elf_->symbol("psbsp_entry");
  } else if (task == -1) {
    fn = elf_->symbol("psbsp_init");
    args = {desc_, ram_, config_, static_cast<uint32_t>(h.config_.size())};
  } else if (task >= 0) {
    fn = elf_->symbol("psbsp_task");
    args = {desc_, static_cast<uint32_t>(task), ram_};
  }
  mcu_->paintStack();
  // A call that ends without returning (a fault, a contract break, a watchdog reset)
  // used its stack too: its depth joins the high-water on the way out (the summary said
  // "stack high-water 0" for an init that crashed). The return path scans below.
  struct StackOnExit {
    TargetFirmware& t;
    bool scanned = false;
    ~StackOnExit() {
      if (scanned) return;
      try {
        t.stackHighWater_ = std::max(t.stackHighWater_, t.mcu_->stackUsed_bytes());
      } catch (const std::exception&) {  // the emulator's read failed: the figure stays as it was
      }
    }
  } stackOnExit{*this};
  callStartCycles_ = syncedCycles_ = mcu_->cycles();
  callStartMin_ = mcu_->cyclesMin();
  callStartMax_ = mcu_->cyclesMax();
  const uint64_t startInstructions = mcu_->instructions();
  handlerCycles_ = handlerInstructions_ = handlerMin_ = handlerMax_ = 0;
  handlers_.clear();
  std::string why;
  TargetCallResult r;
  if (task == kInterruptCall) {  // the MCU leaves its idle loop: the exception's entry, then its handler
    pendSources(h.clock_ns_);
    const uint64_t c0 = mcu_->cycles(), n0 = mcu_->instructions();
    const int irq = mcu_->enterFromIdle(why);
    if (irq == -2) {
      h.fault(start_s, "fault in " + where + ": " + why);
      return false;
    }
    if (irq < 0) return true;  // nothing to take after all
    syncClock();
    entered(irq, c0, n0);
    where = "the handler of interrupt " + std::to_string(irq) + " (" + irqName(irq) + ")";
    setDeadline();
    r = mcu_->resume(*this);
  } else {
    setDeadline();
    r = mcu_->call(fn, args, *this);
  }
  for (;;) {
    syncClock();
    if (r.stop == TargetStop::Returned) break;
    if (r.stop == TargetStop::Fault) {
      h.fault(start_s, "fault in " + where + ": " + r.fault);
      return false;
    }
    if (r.stop == TargetStop::Interrupt || r.stop == TargetStop::ExceptionReturn) {
      pendSources(h.clock_ns_);
      if (r.stop == TargetStop::ExceptionReturn) {
        const int done = mcu_->exceptionReturn(why);
        if (done == -2) {
          h.fault(start_s, "fault in " + where + ": " + why);
          return false;
        }
        returned(done);
        syncClock();
        pendSources(h.clock_ns_);  // a level still up (a frame left in the FIFO) pends again
        if (mcu_->atReturnPage()) break;  // an interrupt taken from the idle loop has returned
      }
      const uint64_t c0 = mcu_->cycles(), n0 = mcu_->instructions();
      const int irq = mcu_->takeInterrupt(why);
      if (irq == -2) {
        h.fault(start_s, "fault in " + where + ": " + why);
        return false;
      }
      if (irq >= 0) {
        syncClock();
        entered(irq, c0, n0);
      }
      if (h.breakCause_[0] == '\0') h.checkBudget();  // the handlers' time counts to the task's
      if (h.breakCause_[0] != '\0') {
        char pc[32];
        std::snprintf(pc, sizeof pc, " (stopped at PC 0x%08x)", mcu_->pc());
        h.fault(start_s, "contract break in " + where + ": " + h.breakCause_ + pc);
        return false;
      }
      setDeadline();
      r = mcu_->resume(*this);
      continue;
    }
    if (h.breakCause_[0] == '\0') h.checkBudget();  // a deadline: the budget, the watchdog or a runaway
    if (h.breakCause_[0] != '\0') {
      char pc[32];
      std::snprintf(pc, sizeof pc, " (stopped at PC 0x%08x)", mcu_->pc());
      h.fault(start_s, "contract break in " + where + ": " + h.breakCause_ + pc);
      return false;
    }
    if (watchdogExpired(h.clock_ns_)) {
      resetPending_ = true;
      return false;
    }
    if (mcu_->cycles() - callStartCycles_ >= runawayCycles_) {
      char why[200];
      std::snprintf(why, sizeof why,
                    "runaway in %s: still running after %.0f ms of MCU time (%llu instructions; watchdog_ms), PC 0x%08x",
                    where.c_str(), h.watchdog_s_ * 1e3,
                    static_cast<unsigned long long>(mcu_->instructions() - startInstructions), mcu_->pc());
      h.fault(start_s, why);
      return false;
    }
    setDeadline();
    r = mcu_->resume(*this);
  }
  stackOnExit.scanned = true;
  const uint32_t stack = mcu_->stackUsed_bytes();
  stackHighWater_ = std::max(stackHighWater_, stack);
  if (stack >= mcu_->stackBytes()) {  // the paint is gone to the last word: it ran past the bottom
    h.fault(start_s, "stack overflow in " + where + ": the call used all " + std::to_string(mcu_->stackBytes()) +
                         " bytes of the stack (PSBSP_STACK_BYTES) and wrote below it, into the RAM under it");
    return false;
  }
  if (task >= 0) {  // the task's own code: the handlers that pre-empted it are theirs
    TargetTaskStats& s = stats_[static_cast<size_t>(task)];
    const uint64_t n = mcu_->instructions() - startInstructions - handlerInstructions_,
                   c = mcu_->cycles() - callStartCycles_ - handlerCycles_;
    ++s.calls;
    s.instructions += n;
    s.cycles += c;
    s.cyclesMin += mcu_->cyclesMin() - callStartMin_ - handlerMin_;
    s.cyclesMax += mcu_->cyclesMax() - callStartMax_ - handlerMax_;
    s.worstInstructions = std::max(s.worstInstructions, n);
    s.worstCycles = std::max(s.worstCycles, c);
    s.stack_bytes = std::max(s.stack_bytes, stack);
  }
  if (task == -2) {
    std::string why;
    if (!readDescriptor(r.r0, why)) {
      h.fault(start_s, why);
      return false;
    }
  } else if (task == -1) {
    h.initResult_ = static_cast<int32_t>(r.r0);
  }
  return true;
}

// The descriptor psfw_firmware_entry returned (r0), read from the MCU's memory into the
// host's copy; the instance RAM and the configuration blob placed after .bss.
bool TargetFirmware::readDescriptor(uint32_t addr, std::string& why) {
  FirmwareHost& h = host_;
  uint8_t d[kDescriptorBytes];
  char hex[16];
  std::snprintf(hex, sizeof hex, "0x%08x", addr);
  if (addr == 0) {
    why = PSFW_ENTRY_SYMBOL " returned no descriptor";
    return false;
  }
  if (!mcu_->read(addr, d, sizeof d)) {
    why = PSFW_ENTRY_SYMBOL " returned " + std::string(hex) + ", not a descriptor in the MCU's memory";
    return false;
  }
  psfw_firmware fw{};
  fw.abi_version = word(d);
  fw.instance_bytes = word(d + 8);
  fw.init = word(d + 12) ? &targetInit : nullptr;
  fw.task_count = word(d + 16);
  for (uint32_t i = 0; i < PSFW_MAX_TASKS; ++i) {
    fw.tasks[i].period_ms = word(d + 20 + 12 * i);
    fw.tasks[i].budget_us = word(d + 24 + 12 * i);
    fw.tasks[i].run = word(d + 28 + 12 * i) ? &targetTask : nullptr;
  }
  char name[kNameChars] = {0};
  if (word(d + 4) && !mcu_->readString(word(d + 4), name, sizeof name)) name[0] = '\0';
  h.fw_ = fw;
  h.name_ = name[0] ? name : "(unnamed)";
  desc_ = addr;
  if (resets_ + brownouts_ == 0) stats_.assign(std::min<uint32_t>(fw.task_count, PSFW_MAX_TASKS), TargetTaskStats{});  // over the run
  // Instance RAM, then the configuration blob, between .bss / .noinit and the stack.
  ram_ = align8(mcu_->freeStart());
  const uint64_t end = uint64_t{align8(static_cast<uint32_t>(std::min<uint64_t>(uint64_t{ram_} + fw.instance_bytes,
                                                                              0xFFFFFFF0u)))} +
                       h.config_.size();
  if (end > mcu_->stackLimit()) {
    why = "instance_bytes " + std::to_string(fw.instance_bytes) + " and the " + std::to_string(h.config_.size()) +
          "-byte configuration do not fit in the " + std::to_string(mcu_->stackLimit() - ram_) +
          " bytes of RAM between .bss and the stack";
    return false;
  }
  instanceBytes_ = fw.instance_bytes;
  config_ = align8(ram_ + fw.instance_bytes);
  mcu_->write(config_, h.config_.data(), h.config_.size());
  return true;
}

void TargetFirmware::reset(bool watchdog) {
  ++(watchdog ? resets_ : brownouts_);
  wdgRunning_ = false;
  resetPending_ = false;
  wdgTimeoutUs_ = 0;
  timerOn_ = false;
  timerPeriodUs_ = 0;
  canIe_ = false;
  pendAt_ns_.fill(UINT64_MAX);
  handlers_.clear();
  if (mcu_) mcu_->loadRam(true);  // the NVIC's reset state too; none: the ELF did not load (a brown-out before the first boot)
}

bool TargetFirmware::copyIn(uint32_t addr, void* out, size_t n, const char* what) {
  if (mcu_->read(addr, out, n)) return true;
  char why[200];
  std::snprintf(why, sizeof why, "%s at 0x%08x (%zu bytes) is not in the MCU's memory, PC 0x%08x", what, addr, n,
                mcu_->pc());
  mcu_->raiseFault(why);
  return false;
}

bool TargetFirmware::copyOut(uint32_t addr, const void* in, size_t n, const char* what) {
  if (mcu_->write(addr, in, n)) return true;
  char why[200];
  std::snprintf(why, sizeof why, "%s at 0x%08x (%zu bytes) is not in the MCU's RAM, PC 0x%08x", what, addr, n,
                mcu_->pc());
  mcu_->raiseFault(why);
  return false;
}

// A service: the arguments from the stub's registers and stack, buffers copied between
// the MCU's memory and the host's, the host's own service code in between.
uint32_t TargetFirmware::supervisorCall(TargetMcu& m, unsigned number) {
  FirmwareHost& h = host_;
  syncClock();
  uint32_t r = 0;
  switch (number) {
    case kSvcNowMs: r = h.nowMs(); break;
    case kSvcNowUs: r = h.nowUs(); break;
    case kSvcDelayUs: h.delayUs(m.arg(1)); break;
    case kSvcBusTransfer: {
      const uint8_t bus = static_cast<uint8_t>(m.arg(1));
      const uint32_t tx = m.arg(2), rx = m.arg(4);
      const uint16_t txLen = static_cast<uint16_t>(m.arg(3)), rxLen = static_cast<uint16_t>(m.arg(5));
      uint8_t txb[PSFW_BUS_MAX_FRAME], rxb[PSFW_BUS_MAX_FRAME];
      if (tx && txLen <= PSFW_BUS_MAX_FRAME && !copyIn(tx, txb, txLen, "bus_transfer's tx buffer")) return 0;
      const int32_t got = h.busTransfer(bus, tx ? txb : nullptr, txLen, rx ? rxb : nullptr, rxLen);
      if (rx && rxLen <= PSFW_BUS_MAX_FRAME && h.breakCause_[0] == '\0' &&
          !copyOut(rx, rxb, rxLen, "bus_transfer's rx buffer"))
        return 0;
      r = static_cast<uint32_t>(got);
      if (h.board_.pins) {  // the ALERT / FAULT line as the transfer left the chain
        bool line = false;
        for (const MonitorBus* b : h.board_.buses) line = line || b->chain->faultLine();
        monitorLine(line, h.clock_ns_);
      }
      break;
    }
    case kSvcAdcRead: r = static_cast<uint32_t>(h.adcRead(static_cast<uint8_t>(m.arg(1)))); break;
    case kSvcGpioRead: r = static_cast<uint32_t>(h.gpioRead(static_cast<uint8_t>(m.arg(1)))); break;
    case kSvcGpioWrite: h.gpioWrite(static_cast<uint8_t>(m.arg(1)), static_cast<int32_t>(m.arg(2))); break;
    case kSvcDacWrite: h.dacWrite(static_cast<uint8_t>(m.arg(1)), static_cast<int32_t>(m.arg(2))); break;
    case kSvcTelemetrySend: {
      const uint32_t bytes = m.arg(1);
      const uint16_t len = static_cast<uint16_t>(m.arg(2));
      uint8_t b[256];
      const size_t n = std::min<size_t>(len, sizeof b);  // the host keeps at most these
      if (bytes && !copyIn(bytes, b, n, "telemetry_send's buffer")) return 0;
      h.telemetrySend(bytes ? b : nullptr, static_cast<uint16_t>(bytes ? n : len));
      break;
    }
    case kSvcEvent: {
      const uint32_t text = m.arg(1);
      char t[122];
      if (text && !m.readString(text, t, sizeof t)) {
        copyIn(text, t, 1, "event's text");
        return 0;
      }
      h.firmwareEvent(text ? t : nullptr);
      break;
    }
    case kSvcSetTaskPeriod: r = static_cast<uint32_t>(h.setTaskPeriod(m.arg(1), m.arg(2), m.arg(3))); break;
    case kSvcCanSend: {
      const uint32_t data = m.arg(3);
      const uint8_t len = static_cast<uint8_t>(m.arg(4));
      uint8_t b[8] = {0};
      if (data && len <= 8 && !copyIn(data, b, len, "can_send's data")) return 0;
      r = static_cast<uint32_t>(h.canSend(static_cast<uint8_t>(m.arg(1)), m.arg(2), data ? b : nullptr, len));
      break;
    }
    case kSvcCanReceive: {
      const uint32_t id = m.arg(2), data = m.arg(3);
      uint32_t gotId = 0;
      uint8_t b[8] = {0};
      const int32_t n = h.canReceive(static_cast<uint8_t>(m.arg(1)), id ? &gotId : nullptr, data ? b : nullptr);
      if (n >= 0 && (!copyOut(id, &gotId, 4, "can_receive's id") || !copyOut(data, b, static_cast<size_t>(n), "can_receive's data")))
        return 0;
      r = static_cast<uint32_t>(n);
      break;
    }
    case kSvcNvmRead:
    case kSvcNvmWrite: {
      const uint32_t offset = m.arg(1), data = m.arg(2), len = m.arg(3);
      uint8_t b[PSFW_NVM_BYTES];
      const bool fits = uint64_t{offset} + len <= PSFW_NVM_BYTES;
      if (number == kSvcNvmRead) {
        const int32_t n = h.nvmRead(offset, data ? b : nullptr, fits ? len : 0xFFFFFFFFu);
        if (n > 0 && !copyOut(data, b, static_cast<size_t>(n), "nvm_read's buffer")) return 0;
        r = static_cast<uint32_t>(n);
      } else {
        if (data && fits && !copyIn(data, b, len, "nvm_write's buffer")) return 0;
        r = static_cast<uint32_t>(h.nvmWrite(offset, data ? b : nullptr, fits ? len : 0xFFFFFFFFu));
      }
      break;
    }
    default: {
      char why[120];
      std::snprintf(why, sizeof why, "supervisor call #%u, which the board does not offer (1-15), PC 0x%08x", number,
                    m.pc());
      m.raiseFault(why);
      return 0;
    }
  }
  if (h.breakCause_[0] != '\0')
    m.requestStop();
  else
    setDeadline();
  return r;
}

uint32_t TargetFirmware::watchdogRead(uint32_t offset) {
  switch (offset) {
    case 4: return wdgTimeoutUs_;
    case 8: return resets_;
    default: return 0;
  }
}

uint32_t TargetFirmware::peripheralRead(TargetMcu&, uint32_t offset) {
  syncClock();
  pendSources(host_.clock_ns_);
  switch (offset) {
    case kTimerCtrl: return timerOn_ ? 1u : 0u;
    case kTimerPeriodUs: return timerPeriodUs_;
    case kTimerCount: return static_cast<uint32_t>(timerCount_);
    case kCanIer: return canIe_ ? 1u : 0u;
    case kInstanceRam: return ram_;
    default: return 0;
  }
}

// The timer: PERIOD_US, then CTRL bit 0 starts it at the MCU clock's instant (its first
// update one period later) or stops it; COUNT counts its updates since the start.
void TargetFirmware::peripheralWrite(TargetMcu& m, uint32_t offset, uint32_t value) {
  syncClock();
  pendSources(host_.clock_ns_);
  if (offset == kTimerPeriodUs && !timerOn_) timerPeriodUs_ = value;
  if (offset == kCanIer) {
    canIe_ = (value & 1u) != 0;
    pendSources(host_.clock_ns_);  // a frame already waiting pends at once
  }
  if (offset == kTimerCtrl) {
    const bool on = (value & 1u) != 0 && timerPeriodUs_ > 0;
    if (on && !timerOn_) {
      timerNext_ns_ = host_.clock_ns_ + uint64_t{timerPeriodUs_} * 1000u;
      timerCount_ = 0;
    }
    timerOn_ = on;
  }
  setDeadline();
  m.checkInterrupts();
}

void TargetFirmware::watchdogWrite(TargetMcu&, uint32_t offset, uint32_t value) {
  syncClock();
  if (offset == 4 && !wdgRunning_) wdgTimeoutUs_ = value;
  if (offset != 0) return;
  if (value == 0xCCCCu && !wdgRunning_ && wdgTimeoutUs_ > 0) {
    wdgRunning_ = true;
    wdgTimeout_ns_ = uint64_t{wdgTimeoutUs_} * 1000u;
    wdgLastKick_ns_ = host_.clock_ns_;
  } else if (value == 0xAAAAu && wdgRunning_) {
    wdgLastKick_ns_ = host_.clock_ns_;
  }
  setDeadline();
}

}  // namespace packsim
