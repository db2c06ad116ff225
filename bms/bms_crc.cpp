#include "bms_crc.hpp"

namespace bms {

uint8_t crcCrc8(const uint8_t* data, size_t length) {
  uint8_t crc = 0;
  for (size_t i = 0; i < length; ++i) {
    crc = static_cast<uint8_t>(crc ^ data[i]);
    for (int b = 0; b < 8; ++b)
      crc = (crc & 0x80u) != 0 ? static_cast<uint8_t>((crc << 1) ^ 0x07u) : static_cast<uint8_t>(crc << 1);
  }
  return crc;
}

uint16_t crcCrc16(const uint8_t* data, size_t length) {
  uint16_t crc = 0;
  for (size_t i = 0; i < length; ++i) {
    crc = static_cast<uint16_t>(crc ^ data[i]);
    // 0xA001 is 0x8005 bit-reversed: the reflected form processes the LSB first.
    for (int b = 0; b < 8; ++b)
      crc = (crc & 1u) != 0 ? static_cast<uint16_t>((crc >> 1) ^ 0xA001u) : static_cast<uint16_t>(crc >> 1);
  }
  return crc;
}

}  // namespace bms
