#include "core/firmware/target_mcu.hpp"

#include <unicorn/unicorn.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "core/firmware/target_memory_map.hpp"

namespace packsim {

namespace {

constexpr uint32_t kExcpSwi = 2;  // QEMU's EXCP_SWI: the SVC instruction

void check(uc_err e, const char* what) {
  if (e != UC_ERR_OK) throw std::runtime_error(std::string("Unicorn: ") + what + ": " + uc_strerror(e));
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
  check(uc_open(UC_ARCH_ARM, static_cast<uc_mode>(UC_MODE_THUMB | UC_MODE_MCLASS), &uc_), "open a Cortex-M");
  check(uc_ctl_set_cpu_model(uc_, UC_CPU_ARM_CORTEX_M4), "select the Cortex-M4 model");
  check(uc_mem_map(uc_, target::kFlashBase, target::kFlashBytes, UC_PROT_READ | UC_PROT_EXEC), "map flash");
  check(uc_mem_map(uc_, target::kRamBase, target::kRamBytes, UC_PROT_ALL), "map RAM");
  check(uc_mem_map(uc_, target::kReturnPage, target::kReturnBytes, UC_PROT_READ | UC_PROT_EXEC), "map the return page");
  check(uc_mmio_map(uc_, target::kWatchdogBase, target::kWatchdogBytes, &TargetMcu::onWatchdogRead, this,
                    &TargetMcu::onWatchdogWrite, this),
        "map the watchdog");
  for (const ElfSegment& s : elf.segments)
    if (s.vaddr >= target::kFlashBase && s.vaddr < target::kFlashBase + target::kFlashBytes && !s.bytes.empty())
      check(uc_mem_write(uc_, s.vaddr, s.bytes.data(), s.bytes.size()), "load flash");
  const uint16_t bkpt[2] = {0xBE00, 0xBE00};  // never executed: reaching the page ends the call
  check(uc_mem_write(uc_, target::kReturnPage, bkpt, sizeof bkpt), "fill the return page");
  uc_hook h;
  check(uc_hook_add(uc_, &h, UC_HOOK_BLOCK, reinterpret_cast<void*>(&TargetMcu::onBlock), this, 1, 0), "hook blocks");
  check(uc_hook_add(uc_, &h, UC_HOOK_INTR, reinterpret_cast<void*>(&TargetMcu::onInterrupt), this, 1, 0),
        "hook exceptions");
  check(uc_hook_add(uc_, &h, UC_HOOK_MEM_INVALID, reinterpret_cast<void*>(&TargetMcu::onBadMemory), this, 1, 0),
        "hook memory faults");
  stackTop_ = elf.symbol("__psbsp_stack_top");
  stackLimit_ = elf.symbol("__psbsp_stack_limit");
  freeStart_ = elf.symbol("__psbsp_free_start");
  noinitStart_ = elf.symbol("__psbsp_noinit_start");
  noinitEnd_ = elf.symbol("__psbsp_noinit_end");
  paintedFrom_ = stackTop_;
}

TargetMcu::~TargetMcu() {
  if (uc_) uc_close(uc_);
}

void TargetMcu::loadRam(bool keepNoInit) {
  std::vector<uint8_t> ram(target::kRamBytes, 0);
  for (const ElfSegment& s : elf_.segments)
    if (s.vaddr >= target::kRamBase && s.vaddr < target::kRamBase + target::kRamBytes && !s.bytes.empty())
      std::memcpy(ram.data() + (s.vaddr - target::kRamBase), s.bytes.data(), s.bytes.size());
  if (keepNoInit && noinitEnd_ > noinitStart_)
    check(uc_mem_read(uc_, noinitStart_, ram.data() + (noinitStart_ - target::kRamBase), noinitEnd_ - noinitStart_),
          "keep .noinit");
  check(uc_mem_write(uc_, target::kRamBase, ram.data(), ram.size()), "load RAM");
  paintedFrom_ = stackTop_;
  paintStack();
}

void TargetMcu::paintStack() {
  if (paintedFrom_ >= stackTop_) paintedFrom_ = stackLimit_;
  std::vector<uint32_t> paint((stackTop_ - paintedFrom_) / 4, target::kStackPaint);
  if (!paint.empty()) check(uc_mem_write(uc_, paintedFrom_, paint.data(), paint.size() * 4), "paint the stack");
  paintedFrom_ = stackTop_;
}

uint32_t TargetMcu::stackUsed_bytes() {
  const uint32_t n = (stackTop_ - stackLimit_) / 4;
  std::vector<uint32_t> words(n);
  check(uc_mem_read(uc_, stackLimit_, words.data(), n * 4), "scan the stack");
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
    check(uc_mem_write(uc_, sp, args.data() + 4, (args.size() - 4) * 4), "push arguments");
  }
  const int argRegs[4] = {UC_ARM_REG_R0, UC_ARM_REG_R1, UC_ARM_REG_R2, UC_ARM_REG_R3};
  for (size_t i = 0; i < 4; ++i) {
    uint32_t v = i < args.size() ? args[i] : 0;
    uc_reg_write(uc_, argRegs[i], &v);
  }
  uint32_t lr = target::kReturnPage | 1u;
  uc_reg_write(uc_, UC_ARM_REG_SP, &sp);
  uc_reg_write(uc_, UC_ARM_REG_LR, &lr);
  return run(fn, p);
}

TargetCallResult TargetMcu::resume(TargetPeripherals& p) { return run(pc(), p); }

TargetCallResult TargetMcu::run(uint32_t start, TargetPeripherals& p) {
  peripherals_ = &p;
  stop_ = TargetStop::Returned;
  stopping_ = false;
  fault_.clear();
  const uc_err e = uc_emu_start(uc_, start | 1u, target::kReturnPage, 0, 0);
  peripherals_ = nullptr;
  TargetCallResult r;
  uc_reg_read(uc_, UC_ARM_REG_R0, &r.r0);
  if (stopping_) {
    r.stop = stop_;
    r.fault = fault_;
    return r;
  }
  if (e != UC_ERR_OK) {
    char why[200];
    std::snprintf(why, sizeof why, "%s at PC 0x%08x",
                  e == UC_ERR_INSN_INVALID ? "undefined instruction (UsageFault: UNDEFINSTR)" : uc_strerror(e), pc());
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
  uc_emu_stop(uc_);
}

void TargetMcu::requestStop() { stopWith(TargetStop::Requested, ""); }

void TargetMcu::raiseFault(const std::string& why) { stopWith(TargetStop::Fault, why); }

uint32_t TargetMcu::pc() {
  uint32_t v = 0;
  uc_reg_read(uc_, UC_ARM_REG_PC, &v);
  return v;
}

uint32_t TargetMcu::arg(int i) {
  uint32_t v = 0;
  if (i < 4) {
    const int regs[4] = {UC_ARM_REG_R0, UC_ARM_REG_R1, UC_ARM_REG_R2, UC_ARM_REG_R3};
    uc_reg_read(uc_, regs[i], &v);
    return v;
  }
  uint32_t sp = 0;
  uc_reg_read(uc_, UC_ARM_REG_SP, &sp);
  if (uc_mem_read(uc_, sp + 4u * static_cast<uint32_t>(i - 4), &v, 4) != UC_ERR_OK) return 0;
  return v;
}

bool TargetMcu::read(uint32_t addr, void* out, size_t n) {
  if (n == 0) return true;
  return uc_mem_read(uc_, addr, out, n) == UC_ERR_OK;
}

bool TargetMcu::write(uint32_t addr, const void* in, size_t n) {
  if (n == 0) return true;
  // Firmware buffers live in RAM: a write elsewhere (flash, unmapped) is a fault.
  if (addr < target::kRamBase || uint64_t{addr} + n > uint64_t{target::kRamBase} + target::kRamBytes) return false;
  return uc_mem_write(uc_, addr, in, n) == UC_ERR_OK;
}

bool TargetMcu::readString(uint32_t addr, char* out, size_t max) {
  for (size_t i = 0; i < max; ++i) {
    if (uc_mem_read(uc_, addr + i, out + i, 1) != UC_ERR_OK) return false;
    if (out[i] == '\0') return true;
  }
  out[max - 1] = '\0';
  return true;
}

void TargetMcu::onBlock(uc_struct* uc, uint64_t address, uint32_t size, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  if (m.lastBlockEnd_ != 0 && address != m.lastBlockEnd_) {
    m.cycles_ += kTakenBranchCycles;
    m.cyclesMin_ += kTakenBranchCyclesMin;
    m.cyclesMax_ += kTakenBranchCyclesMax;
  }
  m.lastBlockEnd_ = address + size;
  const uint64_t key = address | (uint64_t{size} << 32);
  auto it = m.costs_.find(key);
  if (it == m.costs_.end()) {
    std::vector<uint8_t> code(size);
    BlockCost c;
    if (size > 0 && uc_mem_read(uc, address, code.data(), size) == UC_ERR_OK) c = m.model_.cost(code.data(), size, address);
    it = m.costs_.emplace(key, c).first;
  }
  m.instructions_ += it->second.instructions;
  m.cycles_ += it->second.cycles;
  m.cyclesMin_ += it->second.cyclesMin;
  m.cyclesMax_ += it->second.cyclesMax;
  if (m.cycles_ >= m.deadline_) m.stopWith(TargetStop::Deadline, "");
}

void TargetMcu::onInterrupt(uc_struct* uc, uint32_t intno, void* self) {
  auto& m = *static_cast<TargetMcu*>(self);
  const uint32_t pc = m.pc();
  if (intno == kExcpSwi && m.peripherals_) {
    uint16_t insn = 0;  // the SVC instruction before the return address: its immediate is the service
    uc_mem_read(uc, pc - 2, &insn, 2);
    const uint32_t r0 = m.peripherals_->supervisorCall(m, insn & 0xFFu);
    uc_reg_write(uc, UC_ARM_REG_R0, &r0);
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
