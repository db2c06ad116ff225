#include "bms_crc.hpp"

namespace bms {

namespace {

// Tables built by the compiler. T0 is the classic one-byte table, Tk[x] the CRC of byte x
// followed by k zero bytes, so k + 1 bytes cost k + 1 independent lookups instead of a
// chain of dependent ones (the CRC is linear over GF(2): the state after k + 1 bytes is
// the XOR of each byte's contribution). Both are sliced by eight (2 KiB of flash for CRC-8,
// 4 KiB for CRC-16). Every frame of every monitor IC is CRC'd twice at each read-out (built
// by the part, checked by the firmware) and the telemetry frame once a tick: a 10 ms tick
// makes that a visible share of a small pack's run.
struct Crc8Tables {
  uint8_t t[8][256];
  constexpr Crc8Tables() : t{} {
    for (int i = 0; i < 256; ++i) {
      uint8_t c = static_cast<uint8_t>(i);
      for (int b = 0; b < 8; ++b) c = (c & 0x80u) != 0 ? static_cast<uint8_t>((c << 1) ^ 0x07u) : static_cast<uint8_t>(c << 1);
      t[0][i] = c;
    }
    for (int k = 1; k < 8; ++k)
      for (int i = 0; i < 256; ++i) t[k][i] = t[0][t[k - 1][i]];  // one more zero byte
  }
};

// 0xA001 is 0x8005 bit-reversed: the reflected form processes the LSB first.
struct Crc16Tables {
  uint16_t t[8][256];
  constexpr Crc16Tables() : t{} {
    for (int i = 0; i < 256; ++i) {
      uint16_t c = static_cast<uint16_t>(i);
      for (int b = 0; b < 8; ++b) c = (c & 1u) != 0 ? static_cast<uint16_t>((c >> 1) ^ 0xA001u) : static_cast<uint16_t>(c >> 1);
      t[0][i] = c;
    }
    for (int k = 1; k < 8; ++k)
      for (int i = 0; i < 256; ++i)
        t[k][i] = static_cast<uint16_t>((t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFFu]);  // one more zero byte
  }
};

constexpr Crc8Tables kCrc8{};
constexpr Crc16Tables kCrc16{};

// Eight bytes from d into the state.
uint8_t crc8Step8(uint8_t crc, const uint8_t* d) {
  const auto& t = kCrc8.t;
  return static_cast<uint8_t>(t[7][crc ^ d[0]] ^ t[6][d[1]] ^ t[5][d[2]] ^ t[4][d[3]] ^ t[3][d[4]] ^ t[2][d[5]] ^
                              t[1][d[6]] ^ t[0][d[7]]);
}

// The last n < 8 bytes: at most one step of four and one of the last one to three bytes
// (the frames here are short, 3 to 32 bytes, so the tail is no bytewise chain). Inline:
// called out of line by crcCrc8 it cost some 20 instructions a tick more.
inline uint8_t crc8Tail(uint8_t crc, const uint8_t* d, size_t n) {
  const auto& t = kCrc8.t;
  if (n >= 4) {
    crc = static_cast<uint8_t>(t[3][crc ^ d[0]] ^ t[2][d[1]] ^ t[1][d[2]] ^ t[0][d[3]]);
    d += 4;
    n -= 4;
  }
  switch (n) {
    case 3: return static_cast<uint8_t>(t[2][crc ^ d[0]] ^ t[1][d[1]] ^ t[0][d[2]]);
    case 2: return static_cast<uint8_t>(t[1][crc ^ d[0]] ^ t[0][d[1]]);
    case 1: return t[0][crc ^ d[0]];
    default: return crc;
  }
}

}  // namespace

// Eight bytes a step, then the tail.
uint8_t crcCrc8(const uint8_t* data, size_t length) {
  uint8_t crc = 0;
  size_t i = 0;
  for (; i + 8 <= length; i += 8) crc = crc8Step8(crc, data + i);
  return crc8Tail(crc, data + i, length - i);
}

// The same steps for a length known at build time: unrolled, no loop or tail tests (the
// telemetry frame's 32 bytes: 113 -> about 75 instructions on a host).
template <size_t N>
uint8_t crcCrc8Fixed(const uint8_t* data) {
  uint8_t crc = 0;
#pragma GCC unroll 8
  for (size_t i = 0; i + 8 <= N; i += 8) crc = crc8Step8(crc, data + i);
  return crc8Tail(crc, data + N / 8 * 8, N % 8);
}
template uint8_t crcCrc8Fixed<32>(const uint8_t* data);  // the telemetry frame
// A BQ76PL536A read-out's two exchanges (request and registers: the flags' 3 + 4 bytes and
// the results' 3 + 19), checked at every read-out.
template uint8_t crcCrc8Fixed<7>(const uint8_t* data);
template uint8_t crcCrc8Fixed<22>(const uint8_t* data);

// The same steps; the state's low byte meets the next byte, its high byte the one after.
uint16_t crcCrc16(const uint8_t* data, size_t length) {
  const auto& t = kCrc16.t;
  uint16_t crc = 0;
  size_t i = 0;
  for (; i + 8 <= length; i += 8) {
    const uint16_t x = static_cast<uint16_t>(crc ^ (data[i] | (data[i + 1] << 8)));
    crc = static_cast<uint16_t>(t[7][x & 0xFFu] ^ t[6][x >> 8] ^ t[5][data[i + 2]] ^ t[4][data[i + 3]] ^
                                t[3][data[i + 4]] ^ t[2][data[i + 5]] ^ t[1][data[i + 6]] ^ t[0][data[i + 7]]);
  }
  if (i + 4 <= length) {
    const uint16_t x = static_cast<uint16_t>(crc ^ (data[i] | (data[i + 1] << 8)));
    crc = static_cast<uint16_t>(t[3][x & 0xFFu] ^ t[2][x >> 8] ^ t[1][data[i + 2]] ^ t[0][data[i + 3]]);
    i += 4;
  }
  switch (length - i) {
    case 3: {
      const uint16_t x = static_cast<uint16_t>(crc ^ (data[i] | (data[i + 1] << 8)));
      crc = static_cast<uint16_t>(t[2][x & 0xFFu] ^ t[1][x >> 8] ^ t[0][data[i + 2]]);
      break;
    }
    case 2: {
      const uint16_t x = static_cast<uint16_t>(crc ^ (data[i] | (data[i + 1] << 8)));
      crc = static_cast<uint16_t>(t[1][x & 0xFFu] ^ t[0][x >> 8]);
      break;
    }
    case 1: crc = static_cast<uint16_t>((crc >> 8) ^ t[0][(crc ^ data[i]) & 0xFFu]); break;
    default: break;
  }
  return crc;
}

}  // namespace bms
