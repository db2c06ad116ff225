// The virtual Cortex-M4 (bms.firmware.target: cortex-m4): the firmware ELF's object code
// run by the Unicorn engine (Debian's libunicorn-dev; QEMU's Thumb-2 and FPv4 translator,
// an instruction-set emulator that is maintained, rather than one written here).
//
// Memory (target_memory_map.hpp): flash (read and execute) and RAM loaded from the ELF's
// segments, .bss zeroed, the stack painted; the watchdog's registers as MMIO; a return
// page, the link register of every call packsim makes. call() runs one function to its
// return and counts what ran: instructions and cycles (cycle_model.hpp), block by block.
// It stops early at a cycle deadline (budget, watchdog, runaway), on a fault (unmapped
// or protected memory, an undefined instruction, an exception other than SVC), or when
// a supervisor call's handler asks (a contract break).
//
// Interrupts (target_nvic.hpp): the NVIC at its architectural addresses; an interrupt is
// taken at an instruction boundary -- where the cycle count reaches the instant a
// source pends it (the block that holds that count is re-translated with a hook on its
// remaining instructions, so the emulator stops between two of them), or at the next
// basic block after an NVIC write, a service that pended one, or an unmasking. Entry
// and return are the architecture's: the 8-word frame (26 with the FP context when
// CONTROL.FPCA is set; 4 more bytes to align it to 8), LR = EXC_RETURN, IPSR, the vector
// from VTOR; 12 cycles in, 10 out (the Cortex-M4 TRM's zero-wait figures).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/firmware/cycle_model.hpp"
#include "core/firmware/elf_image.hpp"
#include "core/firmware/target_nvic.hpp"

struct uc_struct;

namespace packsim {

class TargetMcu;

// What the firmware reaches through the MCU: supervisor calls and the watchdog's registers.
class TargetPeripherals {
 public:
  virtual ~TargetPeripherals() = default;
  // `svc #number` with the caller's registers in the MCU; returns r0.
  virtual uint32_t supervisorCall(TargetMcu& mcu, unsigned number) = 0;
  virtual uint32_t watchdogRead(uint32_t offset) = 0;
  virtual void watchdogWrite(TargetMcu& mcu, uint32_t offset, uint32_t value) = 0;
  // The board's peripheral page (target_memory_map.hpp: the timer, the CAN controller).
  virtual uint32_t peripheralRead(TargetMcu& mcu, uint32_t offset) = 0;
  virtual void peripheralWrite(TargetMcu& mcu, uint32_t offset, uint32_t value) = 0;
};

// Interrupt: the call stopped at an instruction boundary to take an interrupt (the
// host pends what is due and calls takeInterrupt()); ExceptionReturn: a handler
// branched to EXC_RETURN (the host calls exceptionReturn()).
enum class TargetStop { Returned, Deadline, Fault, Requested, Interrupt, ExceptionReturn, Split };

struct TargetCallResult {
  TargetStop stop = TargetStop::Returned;
  uint32_t r0 = 0;
  std::string fault;  // Fault: the reason and the PC
};

class TargetMcu {
 public:
  explicit TargetMcu(const ElfImage& elf);
  ~TargetMcu();
  TargetMcu(const TargetMcu&) = delete;
  TargetMcu& operator=(const TargetMcu&) = delete;

  // RAM as the ELF loads it, .bss zeroed, the stack painted; `keepNoInit`: the .noinit
  // region keeps its bytes (a watchdog reset), else it is zeroed (power-up).
  void loadRam(bool keepNoInit);
  // Runs fn(args...) (the first four in r0-r3, the rest on the stack) from the top of
  // the stack until it returns; stops early when cycles() reaches the deadline.
  TargetCallResult call(uint32_t fn, const std::vector<uint32_t>& args, TargetPeripherals& p);
  // Continues a call that stopped at its cycle deadline, from where it stopped.
  TargetCallResult resume(TargetPeripherals& p);

  TargetNvic& nvic() { return nvic_; }
  // Stop at the next basic block to look for an interrupt to take.
  void checkInterrupts() { irqCheck_ = true; }
  // The cycle count at which a source pends an interrupt (UINT64_MAX: none).
  void setInterruptDueCycles(uint64_t cycles) { irqDue_ = cycles; }
  // The execution priority now (active interrupts, PRIMASK, FAULTMASK, BASEPRI).
  int executionPriority();
  // Exception entry for the interrupt the NVIC selects, if one pre-empts the execution
  // priority: returns its IRQ (-1: none). A vector without a handler (the board's
  // default) or without the Thumb bit, a frame outside RAM: -2 and the fault's reason.
  int takeInterrupt(std::string& fault);
  // The MCU leaves its idle loop for an interrupt: a thread context at the top of the
  // stack whose return address is the return page (the call ends when the handler
  // returns), then takeInterrupt().
  int enterFromIdle(std::string& fault);
  // Exception return to the frame's context (the handler branched to EXC_RETURN):
  // returns the IRQ that returned; -2 and the reason for an invalid EXC_RETURN.
  int exceptionReturn(std::string& fault);
  // Whether the PC is the return page: the call (or an idle interrupt) has ended.
  bool atReturnPage();
  void setCycleDeadline(uint64_t cycles) { deadline_ = cycles; }
  // From a handler: the call ends as a fault with this reason.
  void raiseFault(const std::string& why);
  // From a supervisor call's handler: end the call when the handler returns.
  void requestStop();

  uint64_t cycles() const { return cycles_; }
  // The same instructions' cycles at the ends of the Cortex-M4 TRM's ranges (cycle_model.hpp).
  uint64_t cyclesMin() const { return cyclesMin_; }
  uint64_t cyclesMax() const { return cyclesMax_; }
  uint64_t instructions() const { return instructions_; }
  // Argument i of the function the supervisor call stub was called as (AAPCS).
  uint32_t arg(int i);
  uint32_t pc();
  bool read(uint32_t addr, void* out, size_t n);
  bool write(uint32_t addr, const void* in, size_t n);
  // A NUL-terminated string of at most max bytes; false if it runs into unmapped memory.
  bool readString(uint32_t addr, char* out, size_t max);
  // Stack bytes the calls since the last paint touched (the deepest point below the top).
  uint32_t stackUsed_bytes();
  void paintStack();
  uint32_t stackBytes() const { return stackTop_ - stackLimit_; }
  uint32_t freeStart() const { return freeStart_; }
  uint32_t stackLimit() const { return stackLimit_; }

 private:
  static void onBlock(uc_struct* uc, uint64_t address, uint32_t size, void* self);
  static void onSplit(uc_struct* uc, uint64_t address, uint32_t size, void* self);
  static uint64_t onScsRead(uc_struct* uc, uint64_t offset, unsigned size, void* self);
  static void onScsWrite(uc_struct* uc, uint64_t offset, unsigned size, uint64_t value, void* self);
  static uint64_t onPeripheralRead(uc_struct* uc, uint64_t offset, unsigned size, void* self);
  static void onPeripheralWrite(uc_struct* uc, uint64_t offset, unsigned size, uint64_t value, void* self);
  // At a block's start with an interrupt possibly due: true when the call stops there.
  bool interruptBoundary(uint64_t address, uint32_t size, const BlockCost& c, uint32_t penalty[3]);
  uint32_t reg(int id);
  void setReg(int id, uint32_t v);
  static void onInterrupt(uc_struct* uc, uint32_t intno, void* self);
  static bool onBadMemory(uc_struct* uc, int type, uint64_t address, int size, int64_t value, void* self);
  static uint64_t onWatchdogRead(uc_struct* uc, uint64_t offset, unsigned size, void* self);
  static void onWatchdogWrite(uc_struct* uc, uint64_t offset, unsigned size, uint64_t value, void* self);
  void stopWith(TargetStop s, const std::string& why);
  TargetCallResult run(uint32_t pc, TargetPeripherals& p);

  uc_struct* uc_ = nullptr;
  const ElfImage& elf_;
  CycleModel model_;
  std::unordered_map<uint64_t, BlockCost> costs_;  // per block start (and size, in the key's top bits)
  uint64_t cycles_ = 0, instructions_ = 0, deadline_ = UINT64_MAX;
  uint64_t cyclesMin_ = 0, cyclesMax_ = 0;
  uint64_t lastBlockEnd_ = 0;
  TargetPeripherals* peripherals_ = nullptr;
  TargetStop stop_ = TargetStop::Returned;
  bool stopping_ = false;
  std::string fault_;
  uint32_t stackTop_ = 0, stackLimit_ = 0, freeStart_ = 0, noinitStart_ = 0, noinitEnd_ = 0;
  uint32_t paintedFrom_ = 0;  // lowest address painted since the last scan

  TargetNvic nvic_;
  uint32_t defaultHandler_ = 0;   // the board's handler for an interrupt the firmware has none for
  bool irqCheck_ = false;         // stop at the next block to look for an interrupt
  uint64_t irqDue_ = UINT64_MAX;  // a source pends one at this cycle count
  // A block being split at the interrupt's instruction boundary: its range, the first
  // instruction that must not run before the interrupt, the code hook on the rest.
  bool splitArmed_ = false;
  uint64_t splitStart_ = 0, splitEnd_ = 0, splitAt_ = 0;
  size_t splitHook_ = 0;
};

}  // namespace packsim
