#include "bms_config.hpp"

#include "bms_afe_driver.hpp"

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
  c.afe.commLossCount = 5;
  afeSelect(c, 0);  // the registry's first part with its drivers' defaults
  c.readout = ReadoutConfig{c.tickPeriod_ms, 0};
  c.pack = PackConfig{0, 1};
  c.precharge = PrechargeConfig{false, 1000, 50, 2000, 1000, 30, 3};
  c.soc.capacity_mAh = 1000.0f;
  c.soc.ocvPoints = 2;
  c.soc.ocv_mV[0] = 3000;
  c.soc.ocv_mV[1] = 4200;
  c.soc.restCurrent_mA = 200;
  c.soc.rest_ms = 30u * 60u * 1000u;
  c.soc.estimator = SocEstimator::CoulombCounting;
  // EKF: no model until configured (r0 = r1 = 0); 10 mV reading/model error, a slow SOC
  // random walk (about 1 % per hour) and a 2 mV/sqrt(s) v1 walk.
  // R0 independent of temperature until configured (reference 25 °C, no thermistors).
  c.soc.ekf = EkfConfig{{}, 0.0f, 30.0f, 10.0f, 1.7e-4f, 2.0f, -1.0f, 0.05f, 0.0f, 25.0f, 0, {}};
  c.soc.sohMinDeltaSoc = 0.3f;
  // reference system C: < 3.3 V one bar, one more per 0.1 V up to 3.9 V, above 4.0 V eight.
  const uint16_t bars[kDisplayBars - 1] = {3300, 3400, 3500, 3600, 3700, 3800, 4001};
  for (uint8_t i = 0; i + 1 < kDisplayBars; ++i) c.soc.displayBars_mV[i] = bars[i];
  c.weldSettle_ms = 50;
  c.weldCurrent_mA = kDefaultWeldCurrent_mA;
  c.relayAuxFeedback = true;
  c.balanceTime_s = 60;
  // Balancing defaults after open firmware (the parts' datasheets) and reference system C: start at
  // 50 mV spread, stop at 10 mV, never below 3.3 V, pause above 70 °C board temperature.
  c.balance = BalanceConfig{false, BalanceWhen::ChargingOrRest, 50, 10, 3300, 700, 600, false, 200,
                            10u * 60u * 1000u, 1000, 0, 0, 1, 1, 0};
  c.chargeRequest_mA = 0;
  c.chargeFullCell_mV = 0;

  // The protection table as bms_faults.hpp defines it, every rule enabled.
  for (uint8_t i = 0; i < kFaultCount; ++i) {
    const FaultRow& f = faultRow(static_cast<FaultId>(i));
    c.rules[i] = ProtectionRule{f.quantity, f.tripAbove, f.threshold, f.hysteresis, f.delay_ms,
                                f.severity,  f.latch,     f.opens,     true,        FaultAction::Isolate};
  }
  return c;
}

uint8_t afeThermistorChannels(const Config& c) {
  const uint32_t inputs = static_cast<uint32_t>(c.afe.deviceCount) * c.afe.thermistorsPerDevice;
  return static_cast<uint8_t>(inputs < c.thermistorCount ? inputs : c.thermistorCount);
}

}  // namespace bms
