#include "bms_crc.hpp"

namespace bms {

namespace {

// 256-entry tables built by the compiler (0.75 KiB of flash): one lookup per byte
// instead of eight shift-and-XOR steps, which matters at a 10 ms tick over a stack.
struct Crc8Table {
  uint8_t v[256];
  constexpr Crc8Table() : v{} {
    for (int i = 0; i < 256; ++i) {
      uint8_t c = static_cast<uint8_t>(i);
      for (int b = 0; b < 8; ++b) c = (c & 0x80u) != 0 ? static_cast<uint8_t>((c << 1) ^ 0x07u) : static_cast<uint8_t>(c << 1);
      v[i] = c;
    }
  }
};

// 0xA001 is 0x8005 bit-reversed: the reflected form processes the LSB first.
struct Crc16Table {
  uint16_t v[256];
  constexpr Crc16Table() : v{} {
    for (int i = 0; i < 256; ++i) {
      uint16_t c = static_cast<uint16_t>(i);
      for (int b = 0; b < 8; ++b) c = (c & 1u) != 0 ? static_cast<uint16_t>((c >> 1) ^ 0xA001u) : static_cast<uint16_t>(c >> 1);
      v[i] = c;
    }
  }
};

constexpr Crc8Table kCrc8{};
constexpr Crc16Table kCrc16{};

}  // namespace

uint8_t crcCrc8(const uint8_t* data, size_t length) {
  uint8_t crc = 0;
  for (size_t i = 0; i < length; ++i) crc = kCrc8.v[crc ^ data[i]];
  return crc;
}

uint16_t crcCrc16(const uint8_t* data, size_t length) {
  uint16_t crc = 0;
  for (size_t i = 0; i < length; ++i) crc = static_cast<uint16_t>((crc >> 8) ^ kCrc16.v[(crc ^ data[i]) & 0xFFu]);
  return crc;
}

}  // namespace bms
