#include "models/sensors/current_sense.hpp"

namespace packsim {

AdcChannel CurrentSense::channel() const {
  // Work in amps referred to the input so noise is specified where engineers quote it.
  AdcChannel adc;
  adc.lsb = lsb_A();
  adc.gain_error = gain_error;
  adc.offset = (vref_V / 2.0 + amp_offset_V) / (amp_gain * shunt_ohm);
  adc.noise_rms = noise_A_rms;
  adc.code_min = 0;
  adc.code_max = (int64_t{1} << bits) - 1;
  return adc;
}

}  // namespace packsim
