// Test-side BQ76PL536A-like replies built byte by byte from the register layout of
// the datasheets (independent of the simulator's monitor model), so the firmware can be
// driven tick by tick with chosen cell voltages, temperatures and comm faults.
#pragma once
#include <bms/bms_config.hpp>
#include <bms/bms_core.hpp>
#include <bms/bms_crc.hpp>

#include <cstring>
#include <vector>

namespace bms_test {

// 1 mV per cell code, thermistor codes 12-bit on a 10k/10k divider, 1 mA per current code.
inline bms::Config config(uint16_t cells, uint8_t thermistors) {
  bms::Config c = bms::defaultConfig(cells, thermistors);
  c.scaling.cellLsb_uV = 1000.0f;
  c.scaling.currentZeroCode = 32768.0f;
  c.scaling.currentLsb_mA = 1.0f;
  c.scaling.currentCodeMax = 65535;
  c.scaling.busLsb_mV = 1.0f;
  c.soc.capacity_mAh = 2000.0f;
  return c;
}

struct FakeStack {
  std::vector<uint16_t> cell_mV;
  std::vector<uint16_t> thermCode;  // per AFE thermistor channel
  int stackError_mV = 0;            // added to every device's module (GPAI) reading
  int16_t die_dC = 300;
  uint8_t statusBits = 0;           // OR-ed into every device's STATUS byte
  std::vector<int> silent;          // devices that do not answer
  std::vector<int> stuck;           // devices that answer 0x00 …
  uint8_t stuckByte = 0x00;

  FakeStack(uint16_t cells, uint8_t therms, uint16_t mv = 3700) : cell_mV(cells, mv), thermCode(therms, 2048) {}

  static void be(uint8_t* p, uint16_t v) {
    p[0] = static_cast<uint8_t>(v >> 8);
    p[1] = static_cast<uint8_t>(v & 0xFF);
  }

  void fill(const bms::Config& c, bms::Inputs& in) const {
    for (int d = 0; d < bms::kMaxDevices; ++d) in.afe[d].length = 0;
    for (int d = 0; d < c.afe.deviceCount; ++d) {
      bms::AfeFrame& f = in.afe[d];
      bool isSilent = false, isStuck = false;
      for (int s : silent) isSilent = isSilent || s == d;
      for (int s : stuck) isStuck = isStuck || s == d;
      if (isSilent) continue;
      f.length = 29;  // 3 header + 25 data + CRC
      std::memset(f.bytes, 0, sizeof f.bytes);
      f.bytes[0] = static_cast<uint8_t>((d + 1) * 2);
      f.bytes[1] = 0;
      f.bytes[2] = 25;
      uint8_t* p = f.bytes + 3;
      p[0] = static_cast<uint8_t>(0x01 | statusBits);
      uint32_t sum = 0;
      for (int k = 0; k < 6; ++k) {
        const int cell = d * c.afe.cellsPerDevice + k;
        const uint16_t mv = (k < c.afe.cellsPerDevice && cell < c.cellCount) ? cell_mV[static_cast<size_t>(cell)] : 0;
        be(p + 3 + 2 * k, mv);
        sum += mv;
      }
      // GPAI LSB = 6 cell LSBs = 6 mV here.
      be(p + 1, static_cast<uint16_t>((static_cast<int>(sum) + stackError_mV + 3) / 6));
      for (int k = 0; k < 2; ++k) {
        const size_t ch = static_cast<size_t>(d * c.afe.thermistorsPerDevice + k);
        be(p + 15 + 2 * k, ch < thermCode.size() ? thermCode[ch] : 2048);
      }
      be(p + 23, static_cast<uint16_t>(die_dC));
      f.bytes[28] = bms::crcCrc8(f.bytes, 28);
      if (isStuck) std::memset(f.bytes, stuckByte, f.length);
    }
  }
};

// A core ready to step: initialised state, zeroed pins, drive requested, no current.
struct Rig {
  bms::CoreState s;
  bms::Inputs in{};
  bms::Outputs out{};
  Rig() {
    bms::init(s);
    in.runRequest = true;
    in.currentCode = 32768;
  }
};

// Runs the core from t0 to t1 (exclusive) every period, refilling the frames each tick.
template <typename Each>
uint32_t run(const bms::Config& c, bms::CoreState& s, bms::Inputs& in, bms::Outputs& out, const FakeStack& st,
             uint32_t t0, uint32_t t1, Each each) {
  uint32_t t = t0;
  for (; t < t1; t += c.tickPeriod_ms) {
    st.fill(c, in);
    in.now_ms = t;
    bms::step(c, s, in, out);
    each(t);
  }
  return t;
}

inline uint32_t run(const bms::Config& c, bms::CoreState& s, bms::Inputs& in, bms::Outputs& out, const FakeStack& st,
                    uint32_t t0, uint32_t t1) {
  return run(c, s, in, out, st, t0, t1, [](uint32_t) {});
}

}  // namespace bms_test
