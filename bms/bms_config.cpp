#include "bms_config.hpp"

#include "bms_afe_driver.hpp"
#include "bms_settings.hpp"

namespace bms {

Config defaultConfig(uint16_t cellCount, uint8_t thermistorCount) {
  Config c{};
  c.cellCount = cellCount;
  c.thermistorCount = thermistorCount;
  c.tickPeriod_ms = 10;
  c.scaling = SensorScaling{6250000.0f / 16383.0f, 0.0f, 1.0f, 4095.0f, 10000.0f, 10000.0f, 3435.0f, 65535, 1.0f};
  const uint8_t perDevice = cellCount < 6 ? static_cast<uint8_t>(cellCount) : 6;
  const uint16_t devices = static_cast<uint16_t>(perDevice == 0 ? 0 : (cellCount + perDevice - 1) / perDevice);
  c.afe.deviceCount = static_cast<uint8_t>(devices);
  c.afe.cellsPerDevice = perDevice;
  c.afe.thermistorsPerDevice = 2;
  afeSelect(c, 0);  // the registry's first part with its drivers' defaults
  c.readout = ReadoutConfig{c.tickPeriod_ms, 0};
  c.pack = PackConfig{0, 1};
  c.soc.capacity_mAh = 1000.0f;
  c.soc.ocvPoints = 2;
  c.soc.ocv_mV[0] = 3000;
  c.soc.ocv_mV[1] = 4200;
  // EKF: no model until configured (r0 = r1 = 0, tau1 30 s), the initial SOC from the
  // first reading; R0 independent of temperature until configured (reference 25 °C, no
  // thermistors). Its noise settings are rows of bms_settings.def.
  c.soc.ekf = EkfConfig{};
  c.soc.ekf.tau1_s = 30.0f;
  c.soc.ekf.initialSoc = -1.0f;
  c.soc.ekf.r0RefTemp_C = 25.0f;
  // reference system C: < 3.3 V one bar, one more per 0.1 V up to 3.9 V, above 4.0 V eight.
  const uint16_t bars[kDisplayBars - 1] = {3300, 3400, 3500, 3600, 3700, 3800, 4001};
  for (uint8_t i = 0; i + 1 < kDisplayBars; ++i) c.soc.displayBars_mV[i] = bars[i];
  c.weldCurrent_mA = kDefaultWeldCurrent_mA;
  // Every channel a cell temperature, none nearer any group than another, one balancing
  // board without thermistors: until the hardware says otherwise.
  c.therm.cell = thermistorCount >= 64 ? ~uint64_t{0} : (uint64_t{1} << thermistorCount) - 1;
  for (uint16_t g = 0; g < kMaxCells; ++g) c.therm.nearest[g] = kMaxThermistors;
  c.balance.boardCount = 1;
  c.chargeRequest_mA = 0;
  // Balancing (after open firmware and reference system C), precharge, the SOC rest,
  // weld detection and the other scalar settings: their rows.
  settingDefaults(c);

  // The protection table as bms_faults.hpp defines it, every rule enabled.
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const FaultRow& f = faultRow(static_cast<FaultId>(i));
    c.rules[i] = ProtectionRule{f.quantity, f.tripAbove, f.threshold, f.hysteresis, f.delay_ms,
                                f.severity,  f.latch,     f.opens,     true,        FaultAction::Isolate};
  }
  return c;
}

}  // namespace bms
