#include <bms/bms_limits.hpp>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/scenario/scenario_sections.hpp"

namespace packsim {

HardwareConfig readHardware(std::optional<YamlMap> hw, const PackConfig& pack) {
  HardwareConfig h;
  // Defaults: a BQ76PL536A-class 14-bit cell ADC, 4 thermistors spread over the
  // string, a 5 mΩ shunt into a gain-10 amplifier on a 16-bit converter.
  h.cell_adc.lsb = 6.25 / 16383.0;
  h.cell_adc.code_max = (1 << 14) - 1;
  h.cell_adc.noise_rms = 0.5e-3;
  h.current_sense.amp_gain = 10.0;
  h.current_sense.noise_A_rms = 0.02;
  const int cells = pack.series;
  for (int k = 0; k < std::min(4, cells); ++k) h.thermistor_cells.push_back(k * cells / std::min(4, cells));
  if (!hw) return h;

  if (auto a = hw->optionalMap("cell_adc")) {
    h.cell_adc.lsb = a->number("lsb_uV", h.cell_adc.lsb * 1e6, Range::positive()) * 1e-6;
    const long bits = a->integer("bits", 14, 8, 24);
    h.cell_adc.code_max = (int64_t{1} << bits) - 1;
    h.cell_adc.gain_error = a->number("gain_error", 0.0, Range::closed(-0.5, 0.5));
    h.cell_adc.offset = a->number("offset_mV", 0.0, Range::closed(-500.0, 500.0)) * 1e-3;
    h.cell_adc.noise_rms = a->number("noise_mV_rms", h.cell_adc.noise_rms * 1e3, Range::closed(0.0, 500.0)) * 1e-3;
    if (h.cell_adc.code_max > 65535) throw a->errorAt("bits", "the BMS reads 16-bit cell codes; allowed 8..16");
    a->finish();
  }
  if (auto t = hw->optionalMap("thermistors")) {
    if (t->has("at_cells")) {
      h.thermistor_cells.clear();
      for (long c : t->integers("at_cells", 1, cells)) h.thermistor_cells.push_back(static_cast<int>(c - 1));
      if (h.thermistor_cells.size() > bms::kMaxThermistors)
        throw t->errorAt("at_cells", "at most " + std::to_string(bms::kMaxThermistors) + " thermistors");
    }
    h.thermistor.r25_ohm = t->number("r25_ohm", h.thermistor.r25_ohm, Range::positive());
    h.thermistor.beta_K = t->number("beta_K", h.thermistor.beta_K, Range::closed(1000.0, 10000.0));
    h.thermistor.pullup_ohm = t->number("pullup_ohm", h.thermistor.pullup_ohm, Range::positive());
    h.thermistor.bits = static_cast<int>(t->integer("bits", 12, 8, 16));
    h.thermistor.noise_codes_rms = t->number("noise_codes_rms", 0.0, Range::closed(0.0, 100.0));
    t->finish();
  }
  if (auto c = hw->optionalMap("current_sense")) {
    CurrentSense& s = h.current_sense;
    s.shunt_ohm = c->number("shunt_ohm", s.shunt_ohm, Range::positive());
    s.amp_gain = c->number("amp_gain", s.amp_gain, Range::positive());
    s.amp_offset_V = c->number("amp_offset_mV", 0.0, Range::closed(-1000.0, 1000.0)) * 1e-3;
    s.gain_error = c->number("gain_error", 0.0, Range::closed(-0.5, 0.5));
    s.noise_A_rms = c->number("noise_A_rms", s.noise_A_rms, Range::nonNegative());
    s.vref_V = c->number("vref_V", s.vref_V, Range::closed(0.5, 10.0));
    s.bits = static_cast<int>(c->integer("bits", 16, 8, 24));
    c->finish();
  }
  hw->finish();
  return h;
}

}  // namespace packsim
