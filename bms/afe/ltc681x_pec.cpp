#include "ltc681x_pec.hpp"

#include "ltc681x_regs.h"

namespace bms {

namespace {

// One lookup per byte (0.5 KiB of flash) instead of eight shift-and-XOR steps: the
// remainder is kept in the upper 15 bits of a 16-bit word, so the table is the usual
// MSB-first CRC table of the polynomial shifted left by one.
struct Pec15Table {
  uint16_t v[256];
  constexpr Pec15Table() : v{} {
    for (int i = 0; i < 256; ++i) {
      uint16_t r = static_cast<uint16_t>(i << 7);  // byte at the top of the 15-bit register
      for (int b = 0; b < 8; ++b)
        r = (r & 0x4000u) != 0 ? static_cast<uint16_t>(((r << 1) ^ LTC681X_PEC_POLY) & 0x7FFFu)
                               : static_cast<uint16_t>((r << 1) & 0x7FFFu);
      v[i] = r;
    }
  }
};

constexpr Pec15Table kPec{};

}  // namespace

uint16_t ltcPec15(const uint8_t* data, size_t length) {
  uint16_t rem = LTC681X_PEC_SEED;
  for (size_t i = 0; i < length; ++i) {
    const uint8_t idx = static_cast<uint8_t>(((rem >> 7) ^ data[i]) & 0xFFu);
    rem = static_cast<uint16_t>(((rem << 8) ^ kPec.v[idx]) & 0x7FFFu);
  }
  return static_cast<uint16_t>(rem << 1);
}

bool ltcPecOk(const uint8_t* data, size_t length) {
  const uint16_t pec = ltcPec15(data, length);
  return data[length] == static_cast<uint8_t>(pec >> 8) && data[length + 1] == static_cast<uint8_t>(pec & 0xFFu);
}

void ltcPutPec(uint8_t* data, size_t length) {
  const uint16_t pec = ltcPec15(data, length);
  data[length] = static_cast<uint8_t>(pec >> 8);
  data[length + 1] = static_cast<uint8_t>(pec & 0xFFu);
}

}  // namespace bms
