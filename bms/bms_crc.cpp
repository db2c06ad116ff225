#include "bms_crc.hpp"

namespace bms {

namespace {

// Tables built by the compiler, sliced by four (3 KiB of flash in all): T0 is the classic
// one-byte table, Tk[x] the CRC of byte x followed by k zero bytes, so four bytes cost four
// independent lookups instead of a chain of four dependent ones (the CRC is linear over
// GF(2): the state after four bytes is the XOR of each byte's contribution). Every frame
// of every monitor IC is CRC'd twice at each read-out (built by the part, checked by the
// firmware); a 10 ms tick over a stack makes that a visible share of a small pack's run.
struct Crc8Tables {
  uint8_t t[4][256];
  constexpr Crc8Tables() : t{} {
    for (int i = 0; i < 256; ++i) {
      uint8_t c = static_cast<uint8_t>(i);
      for (int b = 0; b < 8; ++b) c = (c & 0x80u) != 0 ? static_cast<uint8_t>((c << 1) ^ 0x07u) : static_cast<uint8_t>(c << 1);
      t[0][i] = c;
    }
    for (int k = 1; k < 4; ++k)
      for (int i = 0; i < 256; ++i) t[k][i] = t[0][t[k - 1][i]];  // one more zero byte
  }
};

// 0xA001 is 0x8005 bit-reversed: the reflected form processes the LSB first.
struct Crc16Tables {
  uint16_t t[4][256];
  constexpr Crc16Tables() : t{} {
    for (int i = 0; i < 256; ++i) {
      uint16_t c = static_cast<uint16_t>(i);
      for (int b = 0; b < 8; ++b) c = (c & 1u) != 0 ? static_cast<uint16_t>((c >> 1) ^ 0xA001u) : static_cast<uint16_t>(c >> 1);
      t[0][i] = c;
    }
    for (int k = 1; k < 4; ++k)
      for (int i = 0; i < 256; ++i)
        t[k][i] = static_cast<uint16_t>((t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFFu]);  // one more zero byte
  }
};

constexpr Crc8Tables kCrc8{};
constexpr Crc16Tables kCrc16{};

}  // namespace

uint8_t crcCrc8(const uint8_t* data, size_t length) {
  uint8_t crc = 0;
  size_t i = 0;
  for (; i + 4 <= length; i += 4)
    crc = static_cast<uint8_t>(kCrc8.t[3][crc ^ data[i]] ^ kCrc8.t[2][data[i + 1]] ^ kCrc8.t[1][data[i + 2]] ^
                               kCrc8.t[0][data[i + 3]]);
  for (; i < length; ++i) crc = kCrc8.t[0][crc ^ data[i]];
  return crc;
}

uint16_t crcCrc16(const uint8_t* data, size_t length) {
  uint16_t crc = 0;
  size_t i = 0;
  for (; i + 4 <= length; i += 4) {
    const uint16_t x = static_cast<uint16_t>(crc ^ (data[i] | (data[i + 1] << 8)));
    crc = static_cast<uint16_t>(kCrc16.t[3][x & 0xFFu] ^ kCrc16.t[2][x >> 8] ^ kCrc16.t[1][data[i + 2]] ^
                                kCrc16.t[0][data[i + 3]]);
  }
  for (; i < length; ++i) crc = static_cast<uint16_t>((crc >> 8) ^ kCrc16.t[0][(crc ^ data[i]) & 0xFFu]);
  return crc;
}

}  // namespace bms
