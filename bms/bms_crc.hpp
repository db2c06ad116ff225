// Frame checksums of the monitor-IC links.
//   crc8:  polynomial x^8+x^2+x+1 (0x07), initial 0, MSB first, no final XOR
//          (BQ76PL536A SPI frames; optional on BQ76952 I2C/SPI)
//   crc16: polynomial x^16+x^15+x^2+1 (0x8005), initial 0, bit-reflected (LSB first),
//          no final XOR -- "CRC-16/ARC", sent low byte first (BQ76PL455A UART frames)
#pragma once
#include <cstddef>
#include <cstdint>

namespace bms {

uint8_t crcCrc8(const uint8_t* data, size_t length);
// The same over N bytes, N known at build time (instantiated for N = 32, the telemetry
// frame, and N = 7 and 22, a BQ76PL536A read-out's exchanges: bms_crc.cpp).
template <size_t N>
uint8_t crcCrc8Fixed(const uint8_t* data);
uint16_t crcCrc16(const uint8_t* data, size_t length);

}  // namespace bms
