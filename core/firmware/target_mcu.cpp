#include "core/firmware/target_mcu.hpp"

#include "core/firmware/emulator_libraries.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "core/firmware/target_memory_map.hpp"

namespace packsim {

namespace {

constexpr uint32_t kExcpSwi = 2;  // QEMU's EXCP_SWI: the SVC instruction
constexpr uint32_t kExcpExceptionExit = 8;  // QEMU's EXCP_EXCEPTION_EXIT: a branch to an EXC_RETURN value

void check(uc_err e, const char* what) {
  if (e != UC_ERR_OK) throw std::runtime_error(std::string("Unicorn: ") + what + ": " + unicorn().strerror(e));
}

const char* exceptionName(uint32_t intno) {
  switch (intno) {
    case 1: return "undefined instruction (UsageFault)";
    case 3: return "prefetch abort (instruction fetch fault)";
    case 4: return "data abort (bus fault)";
    case 7: return "breakpoint (BKPT)";
    case 8: return "exception return";
    case 15: return "invalid state (UsageFault: INVSTATE, e.g. a call to an address without the Thumb bit)";
    case 17: return "no coprocessor (UsageFault: NOCP, the FPU used while disabled)";
    case 18: return "invalid exception return (UsageFault: INVPC)";
    case 20: return "semihosting call";
    default: return "exception";
  }
}

const char* accessName(int type) {
  switch (type) {
    case UC_MEM_READ_UNMAPPED: return "read of unmapped memory";
    case UC_MEM_WRITE_UNMAPPED: return "write to unmapped memory";
    case UC_MEM_FETCH_UNMAPPED: return "instruction fetch from unmapped memory";
    case UC_MEM_WRITE_PROT: return "write to flash (read-only)";
    case UC_MEM_READ_PROT: return "read of protected memory";
    case UC_MEM_FETCH_PROT: return "instruction fetch from non-executable memory";
    default: return "invalid memory access";
  }
}

}  // namespace

TargetMcu::TargetMcu(const ElfImage& elf) : elf_(elf) {
  check(unicorn().open(UC_ARCH_ARM, static_cast<uc_mode>(UC_MODE_THUMB | UC_MODE_MCLASS), &uc_), "open a Cortex-M");
  check(unicorn().ctl(uc_, UC_CTL_WRITE(UC_CTL_CPU_MODEL, 1), UC_CPU_ARM_CORTEX_M4), "select the Cortex-M4 model");
  check(unicorn().mem_map(uc_, target::kFlashBase, target::kFlashBytes, UC_PROT_READ | UC_PROT_EXEC), "map flash");
  check(unicorn().mem_map(uc_, target::kRamBase, target::kRamBytes, UC_PROT_ALL), "map RAM");
  check(unicorn().mem_map(uc_, target::kReturnPage, target::kReturnBytes, UC_PROT_READ | UC_PROT_EXEC), "map the return page");
  check(unicorn().mmio_map(uc_, target::kWatchdogBase, target::kWatchdogBytes, &TargetMcu::onWatchdogRead, this,
                    &TargetMcu::onWatchdogWrite, this),
        "map the watchdog");
  check(unicorn().mmio_map(uc_, target::kPeripheralBase, target::kPeripheralBytes, &TargetMcu::onPeripheralRead, this,
                    &TargetMcu::onPeripheralWrite, this),
        "map the peripherals");
  check(unicorn().mmio_map(uc_, target::kScsBase, target::kScsBytes, &TargetMcu::onScsRead, this, &TargetMcu::onScsWrite, this),
        "map the NVIC");
  for (const ElfSegment& s : elf.segments)
    if (s.vaddr >= target::kFlashBase && s.vaddr < target::kFlashBase + target::kFlashBytes && !s.bytes.empty())
      check(unicorn().mem_write(uc_, s.vaddr, s.bytes.data(), s.bytes.size()), "load flash");
  const uint16_t bkpt[2] = {0xBE00, 0xBE00};  // never executed: reaching the page ends the call
  check(unicorn().mem_write(uc_, target::kReturnPage, bkpt, sizeof bkpt), "fill the return page");
  uc_hook h;
  check(unicorn().hook_add(uc_, &h, UC_HOOK_BLOCK, reinterpret_cast<void*>(&TargetMcu::onBlock), this, 1, 0), "hook blocks");
  check(unicorn().hook_add(uc_, &h, UC_HOOK_INTR, reinterpret_cast<void*>(&TargetMcu::onInterrupt), this, 1, 0),
        "hook exceptions");
  check(unicorn().hook_add(uc_, &h, UC_HOOK_MEM_INVALID, reinterpret_cast<void*>(&TargetMcu::onBadMemory), this, 1, 0),
        "hook memory faults");
  stackTop_ = elf.symbol("__psbsp_stack_top");
  stackLimit_ = elf.symbol("__psbsp_stack_limit");
  freeStart_ = elf.symbol("__psbsp_free_start");
  noinitStart_ = elf.symbol("__psbsp_noinit_start");
  noinitEnd_ = elf.symbol("__psbsp_noinit_end");
  paintedFrom_ = stackTop_;
  // VTOR at reset: the board's vector table at the start of flash (an ELF built before
  // the board had one: no vectors, an interrupt taken is a fault).
  const auto vec = elf.symbols.find("psbsp_vectors");
  const auto dflt = elf.symbols.find("psbsp_default_handler");
  nvic_ = TargetNvic(vec != elf.symbols.end() ? vec->second : 0);
  defaultHandler_ = dflt != elf.symbols.end() ? (dflt->second & ~1u) : 0;
}

TargetMcu::~TargetMcu() {
  if (uc_) unicorn().close(uc_);
}

void TargetMcu::loadRam(bool keepNoInit) {
  std::vector<uint8_t> ram(target::kRamBytes, 0);
  for (const ElfSegment& s : elf_.segments)
    if (s.vaddr >= target::kRamBase && s.vaddr < target::kRamBase + target::kRamBytes && !s.bytes.empty())
      std::memcpy(ram.data() + (s.vaddr - target::kRamBase), s.bytes.data(), s.bytes.size());
  if (keepNoInit && noinitEnd_ > noinitStart_)
    check(unicorn().mem_read(uc_, noinitStart_, ram.data() + (noinitStart_ - target::kRamBase), noinitEnd_ - noinitStart_),
          "keep .noinit");
  check(unicorn().mem_write(uc_, target::kRamBase, ram.data(), ram.size()), "load RAM");
  paintedFrom_ = stackTop_;
  paintStack();
  // The core's reset state: thread mode, no interrupt pending or enabled, masks clear.
  nvic_.reset();
  irqCheck_ = false;
  irqDue_ = UINT64_MAX;
  setReg(UC_ARM_REG_IPSR, 0);
  setReg(UC_ARM_REG_PRIMASK, 0);
  setReg(UC_ARM_REG_BASEPRI, 0);
  setReg(UC_ARM_REG_FAULTMASK, 0);
  setReg(UC_ARM_REG_CONTROL, 0);
}

uint32_t TargetMcu::reg(int id) {
  uint32_t v = 0;
  unicorn().reg_read(uc_, id, &v);
  return v;
}

void TargetMcu::setReg(int id, uint32_t v) { unicorn().reg_write(uc_, id, &v); }

bool TargetMcu::atReturnPage() { return pc() == target::kReturnPage; }

void TargetMcu::paintStack() {
  if (paintedFrom_ >= stackTop_) paintedFrom_ = stackLimit_;
  std::vector<uint32_t> paint((stackTop_ - paintedFrom_) / 4, target::kStackPaint);
  if (!paint.empty()) check(unicorn().mem_write(uc_, paintedFrom_, paint.data(), paint.size() * 4), "paint the stack");
  paintedFrom_ = stackTop_;
}

uint32_t TargetMcu::stackUsed_bytes() {
  const uint32_t n = (stackTop_ - stackLimit_) / 4;
  std::vector<uint32_t> words(n);
  check(unicorn().mem_read(uc_, stackLimit_, words.data(), n * 4), "scan the stack");
  uint32_t i = 0;
  while (i < n && words[i] == target::kStackPaint) ++i;
  const uint32_t lowest = stackLimit_ + i * 4;
  paintedFrom_ = std::min(paintedFrom_, lowest);
  return stackTop_ - lowest;
}

TargetCallResult TargetMcu::call(uint32_t fn, const std::vector<uint32_t>& args, TargetPeripherals& p) {
  lastBlockEnd_ = 0;
  uint32_t sp = stackTop_;
  if (args.size() > 4) {
    sp -= static_cast<uint32_t>((args.size() - 4) * 4);
    sp &= ~7u;  // AAPCS: 8-byte aligned at a call
    check(unicorn().mem_write(uc_, sp, args.data() + 4, (args.size() - 4) * 4), "push arguments");
  }
  const int argRegs[4] = {UC_ARM_REG_R0, UC_ARM_REG_R1, UC_ARM_REG_R2, UC_ARM_REG_R3};
  for (size_t i = 0; i < 4; ++i) {
    uint32_t v = i < args.size() ? args[i] : 0;
    unicorn().reg_write(uc_, argRegs[i], &v);
  }
  uint32_t lr = target::kReturnPage | 1u;
  unicorn().reg_write(uc_, UC_ARM_REG_SP, &sp);
  unicorn().reg_write(uc_, UC_ARM_REG_LR, &lr);
  return run(fn, p);
}

TargetCallResult TargetMcu::resume(TargetPeripherals& p) { return run(pc(), p); }

TargetCallResult TargetMcu::run(uint32_t start, TargetPeripherals& p) {
  peripherals_ = &p;
  stop_ = TargetStop::Returned;
  stopping_ = false;
  fault_.clear();
  uc_err e = unicorn().emu_start(uc_, start | 1u, target::kReturnPage, 0, 0);
  if (stopping_ && stop_ == TargetStop::Split) {
    // The interrupt falls inside the block the emulator was entering (it has not run):
    // re-translate it with a hook on its instructions from the boundary on, and run it
    // again; the hook stops the emulator before the first of them.
    uc_hook h = 0;
    check(unicorn().hook_add(uc_, &h, UC_HOOK_CODE, reinterpret_cast<void*>(&TargetMcu::onSplit), this, splitAt_, splitEnd_ - 1),
          "hook the interrupt's boundary");
    splitHook_ = h;
    check(unicorn().ctl(uc_, UC_CTL_WRITE(UC_CTL_TB_REMOVE_CACHE, 2), splitStart_, splitEnd_), "re-translate a block");
    splitArmed_ = true;
    stop_ = TargetStop::Returned;
    stopping_ = false;
    e = unicorn().emu_start(uc_, pc() | 1u, target::kReturnPage, 0, 0);
  }
  if (splitArmed_) {
    splitArmed_ = false;
    unicorn().hook_del(uc_, splitHook_);
    check(unicorn().ctl(uc_, UC_CTL_WRITE(UC_CTL_TB_REMOVE_CACHE, 2), splitStart_, splitEnd_), "re-translate a block");
    const uint32_t at = pc();
    if (stopping_ && stop_ == TargetStop::Interrupt && at >= splitStart_ && at < splitEnd_) {
      // The block was counted whole when it started: its instructions from the
      // boundary on have not run (they run, and count, after the handler).
      std::vector<uint8_t> code(splitEnd_ - at);
      if (unicorn().mem_read(uc_, at, code.data(), code.size()) == UC_ERR_OK) {
        const BlockCost rest = model_.cost(code.data(), code.size(), at);
        instructions_ -= rest.instructions;
        cycles_ -= rest.cycles;
        cyclesMin_ -= rest.cyclesMin;
        cyclesMax_ -= rest.cyclesMax;
      }
      lastBlockEnd_ = 0;
    }
  }
  peripherals_ = nullptr;
  TargetCallResult r;
  unicorn().reg_read(uc_, UC_ARM_REG_R0, &r.r0);
  if (stopping_) {
    r.stop = stop_;
    r.fault = fault_;
    return r;
  }
  if (e != UC_ERR_OK) {
    char why[200];
    std::snprintf(why, sizeof why, "%s at PC 0x%08x",
                  e == UC_ERR_INSN_INVALID ? "undefined instruction (UsageFault: UNDEFINSTR)" : unicorn().strerror(e), pc());
    r.stop = TargetStop::Fault;
    r.fault = why;
    return r;
  }
  if (pc() != target::kReturnPage) {  // uc_emu_start ended without reaching the return page
    char why[120];
    std::snprintf(why, sizeof why, "the emulator stopped at PC 0x%08x before the call returned", pc());
    r.stop = TargetStop::Fault;
    r.fault = why;
  }
  return r;
}

void TargetMcu::stopWith(TargetStop s, const std::string& why) {
  if (stopping_) return;
  stopping_ = true;
  stop_ = s;
  fault_ = why;
  unicorn().emu_stop(uc_);
}

void TargetMcu::requestStop() { stopWith(TargetStop::Requested, ""); }

void TargetMcu::raiseFault(const std::string& why) { stopWith(TargetStop::Fault, why); }

uint32_t TargetMcu::pc() {
  uint32_t v = 0;
  unicorn().reg_read(uc_, UC_ARM_REG_PC, &v);
  return v;
}

uint32_t TargetMcu::arg(int i) {
  uint32_t v = 0;
  if (i < 4) {
    const int regs[4] = {UC_ARM_REG_R0, UC_ARM_REG_R1, UC_ARM_REG_R2, UC_ARM_REG_R3};
    unicorn().reg_read(uc_, regs[i], &v);
    return v;
  }
  uint32_t sp = 0;
  unicorn().reg_read(uc_, UC_ARM_REG_SP, &sp);
  if (unicorn().mem_read(uc_, sp + 4u * static_cast<uint32_t>(i - 4), &v, 4) != UC_ERR_OK) return 0;
  return v;
}

bool TargetMcu::read(uint32_t addr, void* out, size_t n) {
  if (n == 0) return true;
  return unicorn().mem_read(uc_, addr, out, n) == UC_ERR_OK;
}

bool TargetMcu::write(uint32_t addr, const void* in, size_t n) {
  if (n == 0) return true;
  // Firmware buffers live in RAM: a write elsewhere (flash, unmapped) is a fault.
  if (addr < target::kRamBase || uint64_t{addr} + n > uint64_t{target::kRamBase} + target::kRamBytes) return false;
  return unicorn().mem_write(uc_, addr, in, n) == UC_ERR_OK;
}

bool TargetMcu::readString(uint32_t addr, char* out, size_t max) {
  for (size_t i = 0; i < max; ++i) {
    if (unicorn().mem_read(uc_, addr + i, out + i, 1) != UC_ERR_OK) return false;
    if (out[i] == '\0') return true;
  }
  out[max - 1] = '\0';
  return true;
}

void TargetMcu::onBlock(uc_struct* uc, uint64_t address, uint32_t size, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  uint32_t penalty[3] = {0, 0, 0};
  if (m.lastBlockEnd_ != 0 && address != m.lastBlockEnd_) {
    penalty[0] = kTakenBranchCycles;
    penalty[1] = kTakenBranchCyclesMin;
    penalty[2] = kTakenBranchCyclesMax;
  }
  const uint64_t key = address | (uint64_t{size} << 32);
  auto it = m.costs_.find(key);
  if (it == m.costs_.end()) {
    std::vector<uint8_t> code(size);
    BlockCost c;
    if (size > 0 && unicorn().mem_read(uc, address, code.data(), size) == UC_ERR_OK) c = m.model_.cost(code.data(), size, address);
    it = m.costs_.emplace(key, c).first;
  }
  const bool splitting = m.splitArmed_;  // the split block again: counted whole, its hook stops it
  if (!splitting && (m.irqCheck_ || m.irqDue_ != UINT64_MAX || m.nvic_.anyPendingEnabled()) &&
      m.interruptBoundary(address, size, it->second, penalty))
    return;
  m.cycles_ += penalty[0];
  m.cyclesMin_ += penalty[1];
  m.cyclesMax_ += penalty[2];
  m.lastBlockEnd_ = address + size;
  m.instructions_ += it->second.instructions;
  m.cycles_ += it->second.cycles;
  m.cyclesMin_ += it->second.cyclesMin;
  m.cyclesMax_ += it->second.cyclesMax;
  if (!splitting && m.cycles_ >= m.deadline_) m.stopWith(TargetStop::Deadline, "");
}

// The emulator is about to run a block: stop before it when an interrupt is to be
// looked at (an NVIC write, a service, a mask that may have lifted) or falls due at its
// start; when it falls due inside it, split it at the instruction boundary.
bool TargetMcu::interruptBoundary(uint64_t address, uint32_t size, const BlockCost& c, uint32_t penalty[3]) {
  const uint64_t c0 = cycles_ + penalty[0];
  bool stopHere = irqCheck_ || irqDue_ <= c0;
  if (!stopHere && nvic_.anyPendingEnabled()) stopHere = nvic_.next(executionPriority()) >= 0;  // a mask lifted
  const auto stopBefore = [&](TargetStop why) {
    cycles_ = c0;  // the branch into the block has run; the block has not
    cyclesMin_ += penalty[1];
    cyclesMax_ += penalty[2];
    lastBlockEnd_ = 0;
    stopWith(why, "");
  };
  if (stopHere) {
    stopBefore(TargetStop::Interrupt);
    return true;
  }
  if (irqDue_ >= c0 + c.cycles) return false;
  std::vector<uint8_t> code(size);
  if (unicorn().mem_read(uc_, address, code.data(), size) != UC_ERR_OK) return false;
  const size_t at = model_.boundary(code.data(), size, address, irqDue_ - c0);
  if (at >= size) return false;  // at the block's end: the next block stops
  splitStart_ = address;
  splitEnd_ = address + size;
  splitAt_ = address + at;
  stopBefore(TargetStop::Split);
  return true;
}

void TargetMcu::onSplit(uc_struct*, uint64_t, uint32_t, void* self) {
  static_cast<TargetMcu*>(self)->stopWith(TargetStop::Interrupt, "");
}

int TargetMcu::executionPriority() {
  return nvic_.executionPriority(reg(UC_ARM_REG_PRIMASK), reg(UC_ARM_REG_FAULTMASK), reg(UC_ARM_REG_BASEPRI));
}

namespace {
constexpr uint32_t kFpca = 1u << 2;           // CONTROL.FPCA: the running code has an FP context
constexpr uint32_t kExcReturnBasic = 1u << 4;  // EXC_RETURN bit 4: a basic (no FP) frame
constexpr uint32_t kExcReturnThread = 1u << 3; // bit 3: back to thread mode
constexpr uint32_t kEntryCycles = 12, kReturnCycles = 10;  // Cortex-M4 TRM, zero wait states
}  // namespace

int TargetMcu::takeInterrupt(std::string& fault) {
  irqCheck_ = false;
  const int irq = nvic_.next(executionPriority());
  if (irq < 0) return -1;
  uint32_t vector = 0;
  const uint32_t exc = 16u + static_cast<uint32_t>(irq);
  char why[240];
  if (nvic_.vtor() == 0 || !read(nvic_.vtor() + 4 * exc, &vector, 4)) {
    std::snprintf(why, sizeof why,
                  "interrupt %d taken, but the firmware has no vector table (VTOR 0x%08x; psbsp_board.c's psbsp_vectors "
                  "is missing: an ELF built before the board had interrupts?), PC 0x%08x",
                  irq, nvic_.vtor(), pc());
    fault = why;
    return -2;
  }
  if ((vector & ~1u) == defaultHandler_) {
    std::snprintf(why, sizeof why,
                  "interrupt %d (%s) enabled and taken, but the firmware defines no handler for it (its vector is "
                  "psbsp_default_handler), PC 0x%08x",
                  irq, irq == kTargetIrqAlert ? "PSBSP_ALERT_IRQHandler" : irq == kTargetIrqCanRx ? "PSBSP_CAN_RX_IRQHandler" : "PSBSP_TIMER_IRQHandler", pc());
    fault = why;
    return -2;
  }
  if (!(vector & 1u)) {
    std::snprintf(why, sizeof why, "interrupt %d's vector 0x%08x has no Thumb bit (UsageFault: INVSTATE)", irq, vector);
    fault = why;
    return -2;
  }
  // PushStack (ARMv7-M ARM B1.5.6): the frame on the main stack, 8-byte aligned.
  const uint32_t control = reg(UC_ARM_REG_CONTROL);
  const bool fp = (control & kFpca) != 0;
  const uint32_t frameBytes = fp ? 0x68u : 0x20u;
  const uint32_t sp = reg(UC_ARM_REG_SP);
  const uint32_t align = (sp >> 2) & 1u;
  const uint32_t frame = (sp - frameBytes) & ~(align << 2);
  uint32_t words[26] = {reg(UC_ARM_REG_R0), reg(UC_ARM_REG_R1), reg(UC_ARM_REG_R2),   reg(UC_ARM_REG_R3),
                        reg(UC_ARM_REG_R12), reg(UC_ARM_REG_LR), pc() & ~1u,          (reg(UC_ARM_REG_XPSR) & ~(1u << 9)) | (align << 9)};
  if (fp) {  // written at once (the chip's lazy stacking writes the same values at the handler's first FP instruction)
    for (int i = 0; i < 16; ++i) words[8 + i] = reg(UC_ARM_REG_S0 + i);
    words[24] = reg(UC_ARM_REG_FPSCR);
    words[25] = 0;
  }
  if (!write(frame, words, frameBytes)) {
    std::snprintf(why, sizeof why, "interrupt %d: its exception frame at 0x%08x is outside RAM (stack overflow), PC 0x%08x", irq,
                  frame, pc());
    fault = why;
    return -2;
  }
  const bool fromThread = (reg(UC_ARM_REG_IPSR) & 0x1FFu) == 0;
  const uint32_t excReturn = 0xFFFFFFE1u | (fp ? 0u : kExcReturnBasic) | (fromThread ? kExcReturnThread : 0u);
  setReg(UC_ARM_REG_SP, frame);
  setReg(UC_ARM_REG_LR, excReturn);
  setReg(UC_ARM_REG_CONTROL, control & ~kFpca);
  setReg(UC_ARM_REG_XPSR_NZCVQG, (1u << 24) | exc);  // Thumb, the exception number, no IT state
  setReg(UC_ARM_REG_PC, vector);
  nvic_.activate(irq);
  cycles_ += kEntryCycles;
  cyclesMin_ += kEntryCycles;
  cyclesMax_ += kEntryCycles;
  lastBlockEnd_ = 0;  // the entry's cycles hold the pipeline's refill
  return irq;
}

int TargetMcu::enterFromIdle(std::string& fault) {
  lastBlockEnd_ = 0;
  setReg(UC_ARM_REG_SP, stackTop_);
  setReg(UC_ARM_REG_LR, target::kReturnPage | 1u);
  setReg(UC_ARM_REG_XPSR_NZCVQG, 1u << 24);
  setReg(UC_ARM_REG_PC, target::kReturnPage | 1u);
  return takeInterrupt(fault);
}

int TargetMcu::exceptionReturn(std::string& fault) {
  const uint32_t excReturn = pc() | 1u;
  const uint32_t ipsr = reg(UC_ARM_REG_IPSR) & 0x1FFu;
  const int irq = static_cast<int>(ipsr) - 16;
  char why[200];
  const bool known = excReturn == 0xFFFFFFE1u || excReturn == 0xFFFFFFE9u || excReturn == 0xFFFFFFF1u ||
                     excReturn == 0xFFFFFFF9u;
  if (irq < 0 || irq >= kTargetIrqLines || !nvic_.active(irq) || !known) {
    std::snprintf(why, sizeof why,
                  "invalid exception return (UsageFault: INVPC): EXC_RETURN 0x%08x in %s%s", excReturn,
                  irq >= 0 ? "interrupt " : "thread mode", irq >= 0 ? std::to_string(irq).c_str() : "");
    if (excReturn == 0xFFFFFFFDu || excReturn == 0xFFFFFFEDu)
      std::strncat(why, " (the process stack, PSP, is not modelled: thread mode runs on the main stack)", sizeof why - std::strlen(why) - 1);
    fault = why;
    return -2;
  }
  nvic_.deactivate(irq);
  // PopStack: the frame back into the registers; SP past it (and its aligner).
  const bool fp = (excReturn & kExcReturnBasic) == 0;
  const uint32_t frameBytes = fp ? 0x68u : 0x20u;
  const uint32_t frame = reg(UC_ARM_REG_SP);
  uint32_t w[26] = {0};
  if (!read(frame, w, frameBytes)) {
    std::snprintf(why, sizeof why, "exception return: its frame at 0x%08x is not in memory", frame);
    fault = why;
    return -2;
  }
  const int regs[6] = {UC_ARM_REG_R0, UC_ARM_REG_R1, UC_ARM_REG_R2, UC_ARM_REG_R3, UC_ARM_REG_R12, UC_ARM_REG_LR};
  for (int i = 0; i < 6; ++i) setReg(regs[i], w[i]);
  if (fp) {
    for (int i = 0; i < 16; ++i) setReg(UC_ARM_REG_S0 + i, w[8 + i]);
    setReg(UC_ARM_REG_FPSCR, w[24]);
  }
  setReg(UC_ARM_REG_SP, frame + frameBytes + (((w[7] >> 9) & 1u) << 2));
  const uint32_t control = reg(UC_ARM_REG_CONTROL);
  setReg(UC_ARM_REG_CONTROL, fp ? (control | kFpca) : (control & ~kFpca));
  const uint32_t back = (excReturn & kExcReturnThread) ? 0u : (w[7] & 0x1FFu);
  setReg(UC_ARM_REG_XPSR_NZCVQG, (w[7] & ~0x3FFu) | back);
  setReg(UC_ARM_REG_PC, w[6] | 1u);
  cycles_ += kReturnCycles;
  cyclesMin_ += kReturnCycles;
  cyclesMax_ += kReturnCycles;
  lastBlockEnd_ = 0;
  if (nvic_.anyPendingEnabled()) irqCheck_ = true;  // one waiting for this handler's priority to drop
  return irq;
}

uint64_t TargetMcu::onScsRead(uc_struct*, uint64_t offset, unsigned size, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  const uint32_t aligned = static_cast<uint32_t>(offset) & ~3u;
  const uint32_t v = m.nvic_.read(aligned, m.reg(UC_ARM_REG_IPSR));
  const uint32_t shift = 8u * (static_cast<uint32_t>(offset) & 3u);
  return size >= 4 ? v : (v >> shift) & ((1u << (8 * size)) - 1u);
}

void TargetMcu::onScsWrite(uc_struct*, uint64_t offset, unsigned size, uint64_t value, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  m.nvic_.write(static_cast<uint32_t>(offset), static_cast<uint32_t>(value), size);
  m.irqCheck_ = true;  // an interrupt may be takeable now: at the next block
}

uint64_t TargetMcu::onPeripheralRead(uc_struct*, uint64_t offset, unsigned, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  return m.peripherals_ ? m.peripherals_->peripheralRead(m, static_cast<uint32_t>(offset)) : 0;
}

void TargetMcu::onPeripheralWrite(uc_struct*, uint64_t offset, unsigned, uint64_t value, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  if (m.peripherals_) m.peripherals_->peripheralWrite(m, static_cast<uint32_t>(offset), static_cast<uint32_t>(value));
}

void TargetMcu::onInterrupt(uc_struct* uc, uint32_t intno, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  const uint32_t pc = m.pc();
  if (intno == kExcpSwi && m.peripherals_) {
    uint16_t insn = 0;  // the SVC instruction before the return address: its immediate is the service
    unicorn().mem_read(uc, pc - 2, &insn, 2);
    const uint32_t r0 = m.peripherals_->supervisorCall(m, insn & 0xFFu);
    unicorn().reg_write(uc, UC_ARM_REG_R0, &r0);
    if (m.nvic_.anyPendingEnabled()) m.irqCheck_ = true;  // a service pended one (an edge seen on the bus)
    return;
  }
  if (intno == kExcpExceptionExit) {  // a branch to EXC_RETURN: the host unstacks
    m.stopWith(TargetStop::ExceptionReturn, "");
    return;
  }
  char why[200];
  std::snprintf(why, sizeof why, "%s (exception %u) at PC 0x%08x", exceptionName(intno), intno, pc);
  m.stopWith(TargetStop::Fault, why);
}

bool TargetMcu::onBadMemory(uc_struct*, int type, uint64_t address, int size, int64_t, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  char why[200];
  std::snprintf(why, sizeof why, "%s: %d bytes at 0x%08llx, PC 0x%08x", accessName(type), size,
                static_cast<unsigned long long>(address), m.pc());
  m.stopWith(TargetStop::Fault, why);
  return false;
}

uint64_t TargetMcu::onWatchdogRead(uc_struct*, uint64_t offset, unsigned, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  return m.peripherals_ ? m.peripherals_->watchdogRead(static_cast<uint32_t>(offset)) : 0;
}

void TargetMcu::onWatchdogWrite(uc_struct*, uint64_t offset, unsigned, uint64_t value, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  if (m.peripherals_) m.peripherals_->watchdogWrite(m, static_cast<uint32_t>(offset), static_cast<uint32_t>(value));
}

}  // namespace packsim
