// Test-side monitor stack: what the drivers (bms_monitor.hpp) would hand the core after
// a read-out, with chosen cell voltages, temperatures and comm faults, so the core can
// be driven tick by tick without the bus. A silent device's read times out; a stuck one
// answers bytes that fail the driver's header check.
#pragma once
#include <bms/bms_config.hpp>
#include <bms/bms_core.hpp>

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
  int stackError_mV = 0;            // added to every device's module (stack) reading
  int16_t die_dC = 300;
  bool deviceFault = false;         // every device reports its own protection latched
  std::vector<int> silent;          // devices that do not answer
  std::vector<int> stuck;           // devices that answer a stuck line (bad header)

  FakeStack(uint16_t cells, uint8_t therms, uint16_t mv = 3700) : cell_mV(cells, mv), thermCode(therms, 2048) {}

  static bool in(const std::vector<int>& v, int d) {
    for (int x : v)
      if (x == d) return true;
    return false;
  }

  // One full read-out into the core's acquisition.
  void fill(const bms::Config& c, bms::CoreState& s) const {
    bms::FrameResult res[bms::kMaxDevices];
    for (int d = 0; d < c.afe.deviceCount; ++d) {
      res[d] = in(silent, d) ? bms::FrameResult::Timeout
               : in(stuck, d) ? bms::FrameResult::BadHeader
                              : bms::FrameResult::Ok;
      if (res[d] != bms::FrameResult::Ok) continue;
      bms::DeviceReading& r = s.acq.device[d];
      r = bms::DeviceReading{};
      uint32_t sum = 0;
      for (int k = 0; k < c.afe.cellsPerDevice; ++k) {
        const int cell = d * c.afe.cellsPerDevice + k;
        r.cell_mV[k] = cell < c.cellCount ? cell_mV[static_cast<size_t>(cell)] : 0;
        sum += r.cell_mV[k];
      }
      r.stack_mV = static_cast<uint32_t>(static_cast<int>(sum) + stackError_mV);
      for (int k = 0; k < c.afe.thermistorsPerDevice; ++k) {
        const size_t ch = static_cast<size_t>(d * c.afe.thermistorsPerDevice + k);
        r.thermCode[k] = ch < thermCode.size() ? thermCode[ch] : 2048;
      }
      r.die_dC = die_dC;
      r.fault = deviceFault;
    }
    bms::acquireResults(c, s.acq, res, true);
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

// Runs the core from t0 to t1 (exclusive) every period, a read-out before each tick.
template <typename Each>
uint32_t run(const bms::Config& c, bms::CoreState& s, bms::Inputs& in, bms::Outputs& out, const FakeStack& st,
             uint32_t t0, uint32_t t1, Each each) {
  uint32_t t = t0;
  for (; t < t1; t += c.tickPeriod_ms) {
    st.fill(c, s);
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
