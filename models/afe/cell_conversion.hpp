// The conversion every monitor-IC model shares: its cell inputs' own gain and offset
// errors (drawn once per run), a cell reading, the module/stack sum and a thermistor
// input. The parts differ in which channels a command converts, in what order and
// into which register; what one channel reads is this.
//
//   channel errors:  gain[c] = channel_gain_sd · N(0,1), offset[c] = channel_offset_sd_V ·
//                    N(0,1), drawn in cell order (gain then offset of each cell, a draw
//                    only where its sd > 0) from deriveSeed(seed, MonitorChannelErrors):
//                    the same stream for every part, so a seed gives the same errors
//   cell reading:    AdcChannel(part's cell_adc, gain_error += gain[c] + injected gain,
//                    offset += offset[c] + injected offset)(V at the input), its noise
//                    from the part's conversion stream
//   module reading:  sum of the device's cells (bottom up) + module_noise_V · N(0,1)
//   thermistor:      open: full scale, short: 0, else the divider's code (its noise)
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "models/afe/device_faults.hpp"
#include "models/afe/monitor_part.hpp"
#include "models/sensors/adc.hpp"
#include "models/sensors/thermistor.hpp"
#include "models/sensors/thermistor_range.hpp"

namespace packsim {

class CellChannelErrors {
 public:
  CellChannelErrors(int cells, double gain_sd, double offset_sd_V, uint64_t seed);

  double gain(int cell) const { return gain_[static_cast<size_t>(cell)]; }
  double offset_V(int cell) const { return offset_[static_cast<size_t>(cell)]; }

  // The code of stack cell `cell`, input `k` of the device whose pins `pins` are, for
  // v_V across the input, rounded by Round (round_even.hpp). Inline: one call per cell
  // and conversion, for a few additions around the ADC's own (inline) conversion.
  template <class Round = RoundHalfEven>
  [[gnu::always_inline]] int64_t convert(const AdcChannel& adc, size_t cell, const DeviceAnalog& pins, size_t k,
                                         double v_V, Rng& noise) const {
    return adc.convertWith<Round>(adc.gain_error + (gain_[cell] + pins.cell_gain_error[k]),
                           adc.offset + (offset_[cell] + pins.cell_offset_V[k]), v_V, noise);
  }

 private:
  std::vector<double> gain_, offset_;
};

// The device's module (stack) voltage as its own channel reads it, from its cells as
// the conversion sees them (DeviceAnalog::cellsSeen).
double moduleVoltage(const std::vector<double>& cell_V, double noise_V, Rng& noise);

// A thermistor input's noiseless code (Thermistor::idealCode, an exp) for the last
// temperature asked: the inputs change once per tick, while a chain looks at them at
// every transfer (its comparators) and conversion. The same value as computing it anew.
//
// And its conversion without noise (noise_codes_rms 0, the usual thermistor): a code
// spans some 0.025 K at 25 °C, while a node's temperature moves by a small part of that
// in a tick, yet moves every tick (an exp a tick and input). So the temperatures that
// convert to the code last made are kept as a range [lo, hi] (thermistor_range.hpp): a
// temperature within it converts to that code, no exp.
class ThermistorCodeCache {
 public:
  double ideal(const Thermistor& ntc, double temp_C) {
    if (!(temp_C == temp_C_)) code_ = ntc.idealCode(temp_C), temp_C_ = temp_C;
    return code_;
  }

  // ideal(ntc, temp_C) < x, the comparator's question: where the kept range holds temp_C
  // and x lies outside its code's window (code - 0.5, code + 0.5), the range answers it
  // (ThermistorCodeRange::bounded), no exp; else the ideal code is compared.
  bool idealBelow(const Thermistor& ntc, double temp_C, double x) {
    if (range_.bounded && range_.holds(temp_C)) {
      const double c = static_cast<double>(range_.code);
      if (x >= c + 0.5) return true;
      if (x <= c - 0.5) return false;
    }
    return ideal(ntc, temp_C) < x;
  }

  // Thermistor::codeOf(ideal(ntc, temp_C), noise): the conversion, noise and all.
  int64_t code(const Thermistor& ntc, double temp_C, Rng& noise) {
    if (ntc.noise_codes_rms == 0.0 && range_.holds(temp_C)) return range_.code;
    return convert(ntc, temp_C, noise);
  }

 private:
  // Out of line: the conversion and the new range, seldom; code() and its callers inline.
  int64_t convert(const Thermistor& ntc, double temp_C, Rng& noise);

  double temp_C_ = std::numeric_limits<double>::quiet_NaN();  // NaN: nothing kept
  double code_ = 0.0;
  ThermistorCodeRange range_;
};

// A thermistor input's code: open reads full scale, shorted reads 0.
int64_t thermistorCode(const Thermistor& ntc, ThermistorFault fault, double temp_C, Rng& noise);
// The same, its noiseless code kept in `kept` (one cache per input and thermistor type).
// Inline, as the conversion it ends in (Thermistor::codeOf).
inline int64_t thermistorCode(const Thermistor& ntc, ThermistorFault fault, double temp_C, ThermistorCodeCache& kept,
                              Rng& noise) {
  if (fault == ThermistorFault::Open) return ntc.fullScaleCode();
  if (fault == ThermistorFault::Short) return 0;
  return kept.code(ntc, temp_C, noise);
}

}  // namespace packsim
