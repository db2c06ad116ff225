#include "bms_config.hpp"

namespace bms {

namespace {

constexpr ProtectionRule rule(FaultId id, Quantity q, bool above, int32_t thr, int32_t hyst, uint32_t delay_ms,
                              Severity sev, bool latch, uint8_t opens) {
  return ProtectionRule{id, q, above, thr, hyst, delay_ms, sev, latch, opens, true};
}

}  // namespace

Config defaultConfig(uint16_t cellCount, uint8_t thermistorCount) {
  Config c{};
  c.cellCount = cellCount;
  c.thermistorCount = thermistorCount;
  c.tickPeriod_ms = 10;
  c.scaling = SensorScaling{6250000.0f / 16383.0f, 0.0f, 1.0f, 4095.0f, 10000.0f, 10000.0f, 3435.0f, 65535, 1.0f};
  const uint8_t perDevice = cellCount < 6 ? static_cast<uint8_t>(cellCount) : 6;
  const uint16_t devices = static_cast<uint16_t>(perDevice == 0 ? 0 : (cellCount + perDevice - 1) / perDevice);
  c.afe = AfeConfig{AfeModel::Bq76pl536a, static_cast<uint8_t>(devices), perDevice, 2, true, 5};
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
  c.soc.ekf = EkfConfig{{}, 0.0f, 30.0f, 10.0f, 1.7e-4f, 2.0f, -1.0f, 0.05f, 0.0f, 25.0f, 0, 0, {}};
  c.soc.sohMinDeltaSoc = 0.3f;
  // reference system C: < 3.3 V one bar, one more per 0.1 V up to 3.9 V, above 4.0 V eight.
  const uint16_t bars[kDisplayBars - 1] = {3300, 3400, 3500, 3600, 3700, 3800, 4001};
  for (uint8_t i = 0; i + 1 < kDisplayBars; ++i) c.soc.displayBars_mV[i] = bars[i];
  c.weldSettle_ms = 50;
  c.weldCurrent_mA = 500;
  c.relayAuxFeedback = true;
  c.balanceTime_s = 60;
  // Balancing defaults after open firmware (the parts' datasheets) and reference system C: start at
  // 50 mV spread, stop at 10 mV, never below 3.3 V, pause above 70 °C board temperature.
  c.balance = BalanceConfig{false, BalanceWhen::ChargingOrRest, 50, 10, 3300, 700, 600, false, 200,
                            10u * 60u * 1000u, 1000, 0, 0, 1, 1, 0};
  c.chargeRequest_mA = 0;
  c.chargeFullCell_mV = 0;

  // The table. Which actuator a fault opens follows reference system A: the monitor
  // side (relay) isolates on voltage, current, temperature, E-switch and comm; the MCU
  // opens the discharge MOSFET on over-current, over-temperature and the E-switch.
  using Q = Quantity;
  using S = Severity;
  constexpr uint8_t R = kActRelay, D = kActDischargeFet, C = kActChargeFet;
  ProtectionRule* r = c.rules;
  //                id                                   quantity               above  thr    hyst  delay  severity  latch opens
  r[0] = rule(FaultId::CellOverVoltage,           Q::MaxCell_mV,          true,  4250,  50,   500,  S::Fatal, true, R | C);
  r[1] = rule(FaultId::CellUnderVoltage,          Q::MinCell_mV,          false, 3000,  100,  500,  S::Fatal, true, R);
  r[2] = rule(FaultId::OverCurrentDischarge,      Q::DischargeCurrent_mA, true,  30000, 1000, 100,  S::Fatal, true, R | D);
  r[3] = rule(FaultId::OverCurrentCharge,         Q::ChargeCurrent_mA,    true,  5000,  500,  100,  S::Fatal, true, R | C);
  r[4] = rule(FaultId::OverTemperature,           Q::MaxTemp_dC,          true,  600,   50,   1000, S::Fatal, true, R | D | C);
  r[5] = rule(FaultId::OverTemperatureCharge,     Q::MaxTempCharging_dC,  true,  450,   50,   1000, S::Fatal, true, R | C);
  r[6] = rule(FaultId::UnderTemperatureDischarge, Q::MinTemp_dC,          false, -200,  50,   1000, S::Fatal, true, R | D);
  r[7] = rule(FaultId::UnderTemperatureCharge,    Q::MinTempCharging_dC,  false, 0,     50,   1000, S::Fatal, true, R | C);
  r[8] = rule(FaultId::BoardOverTemperature,      Q::MaxDie_dC,           true,  1050,  100,  1000, S::Fatal, true, R | D | C);
  r[9] = rule(FaultId::CommLoss,                  Q::CommBadFrames,       true,  4,     0,    0,    S::Fatal, true, R);
  r[10] = rule(FaultId::PlausibilityCellSum,      Q::CellSumError_mV,     true,  50,    10,   1000, S::Fatal, true, R);
  r[11] = rule(FaultId::ThermistorFault,          Q::InvalidThermistors,  true,  0,     0,    1000, S::Fatal, true, R | D | C);
  r[12] = rule(FaultId::CurrentSensorFault,       Q::CurrentCodeAtRail,   true,  0,     0,    500,  S::Fatal, true, R | D | C);
  r[13] = rule(FaultId::EStop,                    Q::EStopPulled,         true,  0,     0,    0,    S::Fatal, true, R | D | C);
  r[14] = rule(FaultId::MonitorFault,             Q::MonitorFaultLine,    true,  0,     0,    0,    S::Fatal, true, R);
  r[15] = rule(FaultId::RelayWelded,              Q::RelayStuckClosed,    true,  0,     0,    200,  S::Fatal, true, D | C);
  r[16] = rule(FaultId::PrechargeFailed,          Q::PrechargeFailed,     true,  0,     0,    0,    S::Fatal, true, R);
  r[17] = rule(FaultId::TemperatureWarning,       Q::MaxTemp_dC,          true,  517,   20,   1000, S::Warning, false, 0);
  r[18] = rule(FaultId::CellImbalance,            Q::CellSpread_mV,       true,  50,    10,   1000, S::Info, false, 0);
  return c;
}

uint8_t afeThermistorChannels(const Config& c) {
  const uint32_t inputs = static_cast<uint32_t>(c.afe.deviceCount) * c.afe.thermistorsPerDevice;
  return static_cast<uint8_t>(inputs < c.thermistorCount ? inputs : c.thermistorCount);
}

}  // namespace bms
