// The cycle cost model of the virtual Cortex-M4 (docs/firmware.md, "Target mode"): an
// estimate from the instructions a basic block holds, decoded once per block with
// Capstone (a maintained disassembler, rather than a hand-written Thumb-2 decoder).
//
//   every instruction                    1 cycle
//   a single load or store (LDR*, STR*,  +1   (the TRM's 2; neighbouring loads and stores
//     VLDR, VSTR, LDREX, ...)                   pipeline to 1 on the chip: an over-estimate)
//   LDRD / STRD                          +2   (TRM: 3)
//   LDM, STM, PUSH, POP, VLDM, VSTM,     +N   registers moved (TRM: 1 + N)
//     VPUSH, VPOP
//   SDIV, UDIV                           +6   (TRM: 2-12 by operand size; 7 is the middle)
//   VDIV.F32, VSQRT.F32                  +13  (TRM: 14)
//   a taken branch (the next block does  +2   (TRM: 1 + P, P = 1-3 pipeline refill)
//     not start where this one ends)
//
// The TRM's ranges (the bounds in BlockCost) give the model's error: each estimate is
// reported with the cycles the same instructions take at the range's ends.
//
// Zero flash wait states (code and data in zero-wait memory, or an accelerator that
// always hits); multiplies, MAC and single-precision VFP arithmetic take 1 cycle, as on
// the M4.
#pragma once
#include <cstddef>
#include <cstdint>

namespace packsim {

struct BlockCost {
  uint32_t instructions = 0;
  uint32_t cycles = 0;  // without the taken-branch penalty (known only when the next block starts)
  // The Cortex-M4 TRM's range for the same instructions: loads and stores pipelined to
  // 1 cycle .. not; SDIV/UDIV 2 .. 12 (the model's error bounds, with the branch's below)
  uint32_t cyclesMin = 0, cyclesMax = 0;
};

constexpr uint32_t kTakenBranchCycles = 2, kTakenBranchCyclesMin = 1, kTakenBranchCyclesMax = 3;

class CycleModel {
 public:
  CycleModel();
  ~CycleModel();
  CycleModel(const CycleModel&) = delete;
  CycleModel& operator=(const CycleModel&) = delete;
  // The cost of the Thumb-2 code at `address` (`n` bytes). An undecodable instruction
  // counts as one instruction of one cycle (the emulator faults on it anyway).
  BlockCost cost(const uint8_t* code, size_t n, uint64_t address) const;
  // The byte offset of the first instruction boundary in the block at which at least
  // `cycles` of its cost have run, not inside an IT block (an interrupt taken there
  // waits for the IT block's end); n when that is the block's end.
  size_t boundary(const uint8_t* code, size_t n, uint64_t address, uint64_t cycles) const;

 private:
  size_t handle_ = 0;  // Capstone's csh
};

}  // namespace packsim
