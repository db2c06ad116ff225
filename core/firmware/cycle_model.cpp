#include "core/firmware/cycle_model.hpp"

#include "core/firmware/emulator_libraries.hpp"

#include <cstring>
#include <stdexcept>

namespace packsim {

namespace {

// Registers a multiple load or store moves: its register-list operands (LDM/STM carry
// the base register first).
uint32_t listedRegisters(const cs_insn& in, bool hasBase) {
  const int ops = in.detail ? in.detail->arm.op_count : 0;
  return static_cast<uint32_t>(hasBase && ops > 0 ? ops - 1 : ops);
}

struct Extra {
  uint32_t model, min, max;
};

Extra extraCycles(const cs_insn& in) {
  switch (in.id) {
    case ARM_INS_LDR: case ARM_INS_LDRB: case ARM_INS_LDRH: case ARM_INS_LDRSB: case ARM_INS_LDRSH:
    case ARM_INS_LDRT: case ARM_INS_LDRBT: case ARM_INS_LDRHT: case ARM_INS_LDRSBT: case ARM_INS_LDRSHT:
    case ARM_INS_LDREX: case ARM_INS_LDREXB: case ARM_INS_LDREXH:
    case ARM_INS_STR: case ARM_INS_STRB: case ARM_INS_STRH: case ARM_INS_STRT: case ARM_INS_STRBT:
    case ARM_INS_STRHT: case ARM_INS_STREX: case ARM_INS_STREXB: case ARM_INS_STREXH:
    case ARM_INS_VLDR: case ARM_INS_VSTR:
      return {1, 0, 1};
    case ARM_INS_LDRD: case ARM_INS_STRD:
      return {2, 1, 2};
    case ARM_INS_PUSH: case ARM_INS_POP: case ARM_INS_VPUSH: case ARM_INS_VPOP: {
      const uint32_t n = listedRegisters(in, false);
      return {n, n, n};
    }
    case ARM_INS_LDM: case ARM_INS_LDMDB: case ARM_INS_STM: case ARM_INS_STMDB:
    case ARM_INS_VLDMIA: case ARM_INS_VLDMDB: case ARM_INS_VSTMIA: case ARM_INS_VSTMDB: {
      const uint32_t n = listedRegisters(in, true);
      return {n, n, n};
    }
    case ARM_INS_SDIV: case ARM_INS_UDIV:
      return {6, 1, 11};
    case ARM_INS_VDIV: case ARM_INS_VSQRT:
      return {13, 13, 13};
    default:
      return {0, 0, 0};
  }
}

}  // namespace

CycleModel::CycleModel() {
  csh h = 0;
  if (capstone().open(CS_ARCH_ARM, static_cast<cs_mode>(CS_MODE_THUMB | CS_MODE_MCLASS), &h) != CS_ERR_OK)
    throw std::runtime_error("Capstone: cannot open a Thumb-2 (M-class) disassembler");
  capstone().option(h, CS_OPT_DETAIL, CS_OPT_ON);
  handle_ = h;
}

CycleModel::~CycleModel() {
  csh h = handle_;
  capstone().close(&h);
}

BlockCost CycleModel::cost(const uint8_t* code, size_t n, uint64_t address) const {
  BlockCost c;
  cs_insn* insn = nullptr;
  size_t pos = 0;
  while (pos < n) {
    const size_t got = capstone().disasm(handle_, code + pos, n - pos, address + pos, 0, &insn);
    size_t used = 0;
    for (size_t i = 0; i < got; ++i) {
      ++c.instructions;
      const Extra e = extraCycles(insn[i]);
      c.cycles += 1 + e.model;
      c.cyclesMin += 1 + e.min;
      c.cyclesMax += 1 + e.max;
      used += insn[i].size;
    }
    if (got) capstone().free(insn, got);
    pos += used;
    if (pos < n) {  // an undecodable halfword: one instruction, skip it
      ++c.instructions;
      ++c.cycles;
      ++c.cyclesMin;
      ++c.cyclesMax;
      pos += 2;
    }
  }
  return c;
}

size_t CycleModel::boundary(const uint8_t* code, size_t n, uint64_t address, uint64_t cycles) const {
  cs_insn* insn = nullptr;
  const size_t got = capstone().disasm(handle_, code, n, address, 0, &insn);
  uint64_t spent = 0;
  size_t pos = 0, itLeft = 0;
  size_t result = n;
  for (size_t i = 0; i < got; ++i) {
    if (spent >= cycles && itLeft == 0) {
      result = pos;
      break;
    }
    if (itLeft > 0) --itLeft;
    if (insn[i].id == ARM_INS_IT) itLeft = std::strlen(insn[i].mnemonic) - 1;  // it, itt, ite, ittt...: 1-4 instructions
    spent += 1 + extraCycles(insn[i]).model;
    pos += insn[i].size;
  }
  if (got) capstone().free(insn, got);
  return result;
}

}  // namespace packsim
