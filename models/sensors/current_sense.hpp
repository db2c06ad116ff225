// Current path: shunt + bidirectional sense amplifier + ADC.
//
//   v_out = v_mid + gain · (I·R_shunt) + amp_offset_V
//   code  = round(v_out / (v_ref / 2^bits))
//
// Positive current (discharge) raises the code above the mid-scale code.
#pragma once
#include "models/sensors/adc.hpp"

namespace packsim {

struct CurrentSense {
  double shunt_ohm = 0.005;
  double amp_gain = 20.0;        // V/V
  double amp_offset_V = 0.0;     // referred to the amplifier output
  double gain_error = 0.0;       // relative
  double noise_A_rms = 0.0;      // referred to the current
  double vref_V = 3.3;           // ADC reference; mid-scale = vref/2
  int bits = 16;

  double lsb_V() const { return vref_V / static_cast<double>(int64_t{1} << bits); }
  double zeroCode() const { return (vref_V / 2.0) / lsb_V(); }
  double lsb_A() const { return lsb_V() / (amp_gain * shunt_ohm); }
  // The converter, referred to the current: built once by a caller that converts every
  // tick (code() builds it each time).
  AdcChannel channel() const;
  int64_t code(double current_A, Rng& rng) const { return channel().convert(current_A, rng); }
};

}  // namespace packsim
