// The LTC681x packet error code (PEC15): x^15+x^14+x^10+x^8+x^7+x^4+x^3+1 (0x4599), seed
// 16, MSB first; returned as the 16-bit word on the wire (the 15-bit remainder shifted
// left by one), sent high byte first (bms/afe/ltc681x_regs.h).
#pragma once
#include <cstddef>
#include <cstdint>

namespace bms {

uint16_t ltcPec15(const uint8_t* data, size_t length);
// True when the two bytes after `length` data bytes are their PEC.
bool ltcPecOk(const uint8_t* data, size_t length);
// Appends the PEC of data[0..length) at data[length], data[length + 1].
void ltcPutPec(uint8_t* data, size_t length);

}  // namespace bms
