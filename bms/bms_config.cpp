#include "bms_config.hpp"

namespace bms {

Config defaultConfig(uint16_t cellCount, uint8_t thermistorCount) {
  Config c{};
  c.cellCount = cellCount;
  c.thermistorCount = thermistorCount;
  c.tickPeriod_ms = 10;
  c.scaling = SensorScaling{6250000.0f / 16383.0f, 0.0f, 1.0f, 4095.0f, 10000.0f, 10000.0f, 3435.0f};
  //                id                            quantity                       above  thr    hyst  delay  severity         latch opens                         enabled
  c.rules[0] = {FaultId::CellOverVoltage,      Quantity::MaxCell_mV,          true,  4250,  50,   500, Severity::Fatal, true, kActRelay | kActChargeFet,    true};
  c.rules[1] = {FaultId::CellUnderVoltage,     Quantity::MinCell_mV,          false, 3000,  100,  500, Severity::Fatal, true, kActRelay | kActDischargeFet, true};
  c.rules[2] = {FaultId::OverCurrentDischarge, Quantity::DischargeCurrent_mA, true,  30000, 1000, 100, Severity::Fatal, true, kActRelay | kActDischargeFet, true};
  c.rules[3] = {FaultId::OverCurrentCharge,    Quantity::ChargeCurrent_mA,    true,  5000,  500,  100, Severity::Fatal, true, kActRelay | kActChargeFet,    true};
  c.rules[4] = {FaultId::OverTemperature,      Quantity::MaxTemp_dC,          true,  600,   50,  1000, Severity::Fatal, true, kActRelay | kActDischargeFet | kActChargeFet, true};
  return c;
}

}  // namespace bms
