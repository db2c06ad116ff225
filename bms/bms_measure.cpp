#include "bms_measure.hpp"

#include <math.h>

namespace bms {

uint16_t cellCodeToMillivolts(const SensorScaling& s, uint16_t code) {
  const float mv = static_cast<float>(code) * s.cellLsb_uV * 0.001f;
  if (mv <= 0.0f) return 0;
  if (mv >= 65535.0f) return 65535;
  return static_cast<uint16_t>(mv + 0.5f);
}

int32_t currentCodeToMilliamps(const SensorScaling& s, int32_t code) {
  const float ma = (static_cast<float>(code) - s.currentZeroCode) * s.currentLsb_mA;
  return static_cast<int32_t>(ma >= 0.0f ? ma + 0.5f : ma - 0.5f);
}

int16_t thermistorCodeToDeciCelsius(const SensorScaling& s, uint16_t code) {
  // A reading at either rail means the sensor is open (ratio 1) or shorted (ratio 0).
  if (code == 0 || static_cast<float>(code) >= s.thermFullScaleCode) return kTempInvalid_dC;
  const float ratio = static_cast<float>(code) / s.thermFullScaleCode;
  const float r_ohm = s.thermPullup_ohm * ratio / (1.0f - ratio);
  const float invT = 1.0f / 298.15f + logf(r_ohm / s.thermR25_ohm) / s.thermBeta_K;
  const float tC = 1.0f / invT - 273.15f;
  if (tC < -100.0f || tC > 300.0f) return kTempInvalid_dC;
  const float dC = tC * 10.0f;
  return static_cast<int16_t>(dC >= 0.0f ? dC + 0.5f : dC - 0.5f);
}

void measure(const Config& cfg, const Inputs& in, Telemetry& tm, int32_t quantity[kQuantityCount]) {
  uint16_t minMv = UINT16_MAX;
  uint16_t maxMv = 0;
  for (uint16_t c = 0; c < cfg.cellCount; ++c) {
    const uint16_t mv = cellCodeToMillivolts(cfg.scaling, in.cellCode[c]);
    tm.cellVoltage_mV[c] = mv;
    if (mv < minMv) minMv = mv;
    if (mv > maxMv) maxMv = mv;
  }
  int16_t maxT = INT16_MIN;
  for (uint8_t k = 0; k < cfg.thermistorCount; ++k) {
    const int16_t dC = thermistorCodeToDeciCelsius(cfg.scaling, in.thermistorCode[k]);
    tm.temperature_dC[k] = dC;
    if (dC != kTempInvalid_dC && dC > maxT) maxT = dC;
  }
  tm.packCurrent_mA = currentCodeToMilliamps(cfg.scaling, in.currentCode);
  tm.minCell_mV = cfg.cellCount > 0 ? minMv : 0;
  tm.maxCell_mV = maxMv;
  tm.maxTemp_dC = maxT;

  quantity[static_cast<uint8_t>(Quantity::MaxCell_mV)] = tm.maxCell_mV;
  quantity[static_cast<uint8_t>(Quantity::MinCell_mV)] = tm.minCell_mV;
  quantity[static_cast<uint8_t>(Quantity::DischargeCurrent_mA)] = tm.packCurrent_mA;
  quantity[static_cast<uint8_t>(Quantity::ChargeCurrent_mA)] = -tm.packCurrent_mA;
  quantity[static_cast<uint8_t>(Quantity::MaxTemp_dC)] = tm.maxTemp_dC;
}

}  // namespace bms
