// The frame checksums against the catalogue check values (CRC of "123456789") and a
// bit-serial reference written from the polynomial, on every frame length.
#include <bms/bms_crc.hpp>
#include <bms/bms_telemetry.hpp>
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

namespace {

const uint8_t kCheck[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};

TEST(Crc, CatalogueCheckValues) {
  EXPECT_EQ(bms::crcCrc8(kCheck, 9), 0xF4);     // CRC-8/SMBUS: poly 0x07, init 0
  EXPECT_EQ(bms::crcCrc16(kCheck, 9), 0xBB3D);  // CRC-16/ARC: poly 0x8005 reflected, init 0
  EXPECT_EQ(bms::crcCrc8(kCheck, 0), 0);
}

uint8_t serial8(const uint8_t* d, size_t n) {
  uint8_t c = 0;
  for (size_t i = 0; i < n; ++i) {
    c ^= d[i];
    for (int b = 0; b < 8; ++b) c = static_cast<uint8_t>((c & 0x80) ? (c << 1) ^ 0x07 : c << 1);
  }
  return c;
}

uint16_t serial16(const uint8_t* d, size_t n) {
  uint16_t c = 0;
  for (size_t i = 0; i < n; ++i) {
    c ^= d[i];
    for (int b = 0; b < 8; ++b) c = static_cast<uint16_t>((c & 1) ? (c >> 1) ^ 0xA001 : c >> 1);
  }
  return c;
}

TEST(Crc, TableEqualsBitSerialOnEveryLength) {
  std::mt19937_64 rng(7);
  std::vector<uint8_t> buf(64);
  for (int trial = 0; trial < 2000; ++trial) {
    for (uint8_t& b : buf) b = static_cast<uint8_t>(rng());
    const size_t n = static_cast<size_t>(trial % 65);
    ASSERT_EQ(bms::crcCrc8(buf.data(), n), serial8(buf.data(), n)) << "length " << n;
    ASSERT_EQ(bms::crcCrc8Fixed<32>(buf.data()), serial8(buf.data(), 32));  // the telemetry frame's
    ASSERT_EQ(bms::crcCrc8Fixed<7>(buf.data()), serial8(buf.data(), 7));    // a BQ76PL536A read-out's
    ASSERT_EQ(bms::crcCrc8Fixed<22>(buf.data()), serial8(buf.data(), 22));  // two exchanges
    ASSERT_EQ(bms::crcCrc16(buf.data(), n), serial16(buf.data(), n)) << "length " << n;
  }
}

// The telemetry frame's lost-device count (byte 31) is the number of set bits of
// devicesLost, and its last byte the CRC-8 of the 32 before it.
TEST(Crc, TelemetryFrameCountsLostDevicesAndEndsWithItsCrc) {
  std::mt19937_64 rng(3);
  bms::Outputs out{};
  for (int trial = 0; trial < 500; ++trial) {
    uint64_t lost = rng();
    if (trial % 4 == 1) lost = 0;
    if (trial % 4 == 2) lost = ~uint64_t{0};
    if (trial % 4 == 3) lost &= rng() & rng();
    out.telemetry.devicesLost = lost;
    out.telemetry.packCurrent_mA = static_cast<int32_t>(rng());
    uint8_t f[bms::kTelemetryFrameBytes];
    ASSERT_EQ(bms::telemetryEncode(out, f), bms::kTelemetryFrameBytes);
    int bits = 0;
    for (int d = 0; d < 64; ++d) bits += static_cast<int>((lost >> d) & 1u);
    ASSERT_EQ(f[31], bits);
    ASSERT_EQ(f[bms::kTelemetryFrameBytes - 1], serial8(f, bms::kTelemetryFrameBytes - 1));
  }
}

}  // namespace
