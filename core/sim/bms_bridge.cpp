#include "core/sim/bms_bridge.hpp"

#include <cmath>

namespace packsim {

namespace {

int32_t toInt(double v) { return static_cast<int32_t>(std::lround(v)); }

void setRule(bms::ProtectionRule& r, const ProtectionConfig& p, double scale) {
  r.enabled = p.enabled;
  r.threshold = toInt(p.threshold * scale);
  r.hysteresis = toInt(p.hysteresis * scale);
  r.delay_ms = static_cast<uint32_t>(std::lround(p.delay_s * 1e3));
}

}  // namespace

bms::Config makeBmsConfig(const Scenario& s) {
  const HardwareConfig& hw = s.hardware;
  bms::Config c = bms::defaultConfig(static_cast<uint16_t>(s.pack.series),
                                     static_cast<uint8_t>(hw.thermistor_cells.size()));
  c.tickPeriod_ms = static_cast<uint32_t>(std::lround(s.bms.tick_s * 1e3));
  // The firmware knows the datasheet scaling, not the part's actual error.
  c.scaling.cellLsb_uV = static_cast<float>(hw.cell_adc.lsb * 1e6);
  c.scaling.currentZeroCode = static_cast<float>(hw.current_sense.zeroCode());
  c.scaling.currentLsb_mA = static_cast<float>(hw.current_sense.lsb_A() * 1e3);
  c.scaling.thermFullScaleCode = static_cast<float>(hw.thermistor.fullScaleCode());
  c.scaling.thermPullup_ohm = static_cast<float>(hw.thermistor.pullup_ohm);
  c.scaling.thermR25_ohm = static_cast<float>(hw.thermistor.r25_ohm);
  c.scaling.thermBeta_K = static_cast<float>(hw.thermistor.beta_K);
  setRule(c.rules[static_cast<int>(bms::FaultId::CellOverVoltage)], s.bms.cell_overvoltage, 1e3);
  setRule(c.rules[static_cast<int>(bms::FaultId::CellUnderVoltage)], s.bms.cell_undervoltage, 1e3);
  setRule(c.rules[static_cast<int>(bms::FaultId::OverCurrentDischarge)], s.bms.overcurrent_discharge, 1e3);
  setRule(c.rules[static_cast<int>(bms::FaultId::OverCurrentCharge)], s.bms.overcurrent_charge, 1e3);
  setRule(c.rules[static_cast<int>(bms::FaultId::OverTemperature)], s.bms.overtemperature, 10.0);
  return c;
}

void sampleSensors(const Scenario& s, const Plant& plant, const PlantSignals& sig, Rng& rng, bms::Inputs& in) {
  const HardwareConfig& hw = s.hardware;
  for (int g = 0; g < s.pack.series; ++g)
    in.cellCode[g] = static_cast<uint16_t>(hw.cell_adc.convert(sig.group_voltage_V[static_cast<size_t>(g)], rng));
  for (size_t k = 0; k < hw.thermistor_cells.size(); ++k) {
    const int cell = hw.thermistor_cells[k] * plant.pack().parallel;  // first cell of the group
    in.thermistorCode[k] = static_cast<uint16_t>(hw.thermistor.code(sig.node_temp_C[static_cast<size_t>(cell)], rng));
  }
  in.currentCode = static_cast<int32_t>(hw.current_sense.code(sig.pack_current_A, rng));
}

}  // namespace packsim
