#include "bms_measure.hpp"

#include <math.h>

#include "bms_afe_driver.hpp"

namespace bms {

uint16_t cellCodeToMillivolts(const SensorScaling& s, uint16_t code) { return afeCellCodeToMv(code, s.cellLsb_uV); }

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

void acquisitionReset(AcquisitionState& a) {
  for (uint8_t d = 0; d < kMaxDevices; ++d) {
    a.seen[d] = false;
    a.bad[d] = 0;
    a.last[d] = FrameResult::Timeout;
    a.device[d].thermConverted = 0;  // no conversion is held yet
  }
  a.newCells = 0;
  a.fresh = false;
  a.readOut = false;
}

void acquireResults(const Config& cfg, AcquisitionState& a, const FrameResult* result, bool full) {
  bool arrived = false;  // a device's new cells came with this read-out
  for (uint8_t d = 0; d < cfg.afe.deviceCount; ++d) {
    if (result[d] == FrameResult::NotRead) continue;  // as it was: nothing new, nothing failed
    if (full) a.readOut = true;
    a.last[d] = result[d];
    if (result[d] == FrameResult::Ok) {
      a.bad[d] = 0;
      // A device's first cells are new to the estimators whichever loop they are from.
      const bool first = !a.seen[d];
      if (full) a.seen[d] = true;
      if (full && (first || !a.device[d].sameLoop)) {
        a.newCells |= uint64_t{1} << d;
        arrived = true;
      }
    } else if (a.bad[d] < 255) {
      ++a.bad[d];
    }
  }
  const uint8_t n = cfg.afe.deviceCount;
  const uint64_t every = n >= 64 ? ~uint64_t{0} : (uint64_t{1} << n) - 1;
  if (arrived && (a.newCells & every) == every) {
    a.fresh = true;
    a.newCells = 0;
  }
}

bool loopCurrent(const Config& cfg, const AcquisitionState& a, int32_t& mA) {
  const uint8_t n = cfg.afe.deviceCount;
  if (n == 0) return false;
  int64_t sum = 0;
  for (uint8_t d = 0; d < n; ++d) {
    if (!a.device[d].loopCurrent) return false;
    sum += a.device[d].current_mA;
  }
  mA = static_cast<int32_t>(sum / n);
  return true;
}

bool measure(const Config& cfg, const Inputs& in, AcquisitionState& a, Telemetry& tm,
             int32_t quantity[kQuantityCount]) {
  // 1. Comm status of every device; the device's own protection counts from a read that
  //    just succeeded (a device that stopped answering is the comm-loss rule's).
  // 2. Cells, from each device's last good reading (0 until it has answered), in the
  //    same pass: each reading is read once.
  uint8_t worstBad = 0;
  uint32_t worstSumError_mV = 0;
  int16_t maxDie = INT16_MIN;
  bool deviceFault = false;
  uint16_t minMv = UINT16_MAX;
  uint16_t maxMv = 0;
  uint32_t sumMv = 0;
  uint16_t counted = 0;
  tm.devicesLost = 0;
  for (uint8_t d = 0; d < cfg.afe.deviceCount; ++d) {
    tm.lastResult[d] = static_cast<uint8_t>(a.last[d]);
    tm.commBad[d] = a.bad[d];
    if (a.bad[d] > worstBad) worstBad = a.bad[d];
    if (a.bad[d] >= cfg.afe.commLossCount && d < 64) tm.devicesLost |= uint64_t{1} << d;
    const uint8_t cells = afeCellsOf(cfg.afe, cfg.cellCount, d);
    uint16_t* const cell_mV = tm.cellVoltage_mV + static_cast<uint16_t>(d * cfg.afe.cellsPerDevice);
    if (!a.seen[d]) {
      for (uint8_t c = 0; c < cells; ++c) cell_mV[c] = 0;
      continue;
    }
    const DeviceReading& r = a.device[d];
    deviceFault = deviceFault || (a.bad[d] == 0 && r.fault);
    uint32_t sum_mV = 0;
    for (uint8_t c = 0; c < cells; ++c) {
      const uint16_t mv = r.cell_mV[c];
      cell_mV[c] = mv;
      sum_mV += mv;
      if (mv < minMv) minMv = mv;
      if (mv > maxMv) maxMv = mv;
    }
    sumMv += sum_mV;
    counted = static_cast<uint16_t>(counted + cells);
    const uint32_t diff = sum_mV > r.stack_mV ? sum_mV - r.stack_mV : r.stack_mV - sum_mV;
    const uint32_t perCell = cells > 0 ? diff / cells : 0;
    if (perCell > worstSumError_mV) worstSumError_mV = perCell;
    if (r.die_dC > maxDie) maxDie = r.die_dC;
  }

  // 3. Temperatures: the first channels sit on the monitor ICs, the rest on the MCU.
  const uint8_t afeTherm = afeThermistorChannels(cfg);
  const AfeDriver* part = afeDriver(cfg.afe.part);  // converts its thermistor inputs
  // A ratiometric part's driver marks the inputs whose code changed: the others keep the
  // temperature this Telemetry holds (a logf and five divisions a channel a tick saved).
  const bool keepsConversions = part != nullptr && part->api->temperature_dC == afeRatiometricTemp_dC;
  int16_t maxT = INT16_MIN;
  int16_t minT = INT16_MAX;
  int16_t maxFet = INT16_MIN;
  uint8_t invalid = 0;
  bool moved = false;  // a channel reads differently from the previous tick
  uint8_t nextDevice = 0, nextInput = 0;  // AFE channel k is input k % perDevice of device k / perDevice
  for (uint8_t k = 0; k < cfg.thermistorCount; ++k) {
    int16_t dC = kTempInvalid_dC;
    if (k < afeTherm) {
      const uint8_t d = nextDevice, i = nextInput;  // counted, not divided: two divisions a channel a tick
      if (++nextInput == cfg.afe.thermistorsPerDevice) {
        nextInput = 0;
        ++nextDevice;
      }
      if (!a.seen[d]) {
        moved = moved || tm.temperature_dC[k] != kTempInvalid_dC;
        tm.temperature_dC[k] = kTempInvalid_dC;
        continue;  // no data yet is a comm problem, not a sensor fault
      }
      DeviceReading& r = a.device[d];
      const uint8_t bit = static_cast<uint8_t>(1u << i);
      if (keepsConversions && (r.thermConverted & bit) != 0) {
        dC = tm.temperature_dC[k];  // converted from this same code on an earlier tick
      } else {
        dC = part != nullptr ? part->api->temperature_dC(cfg, r, i) : kTempInvalid_dC;
        if (keepsConversions) r.thermConverted = static_cast<uint8_t>(r.thermConverted | bit);
      }
    } else {
      dC = thermistorCodeToDeciCelsius(cfg.scaling, in.mcuThermistorCode[k - afeTherm]);
    }
    moved = moved || tm.temperature_dC[k] != dC;
    tm.temperature_dC[k] = dC;
    if (dC == kTempInvalid_dC) {
      ++invalid;
      continue;
    }
    // Balancing-board thermistors are not cell temperatures (bms_balance reads them),
    // nor are the FETs' (their own limit).
    if (thermOn(cfg.therm.board, k)) continue;
    if (thermOn(cfg.therm.fet, k)) {
      if (dC > maxFet) maxFet = dC;
      continue;
    }
    if (dC > maxT) maxT = dC;
    if (dC < minT) minT = dC;
  }

  // 4. Current, bus voltage.
  tm.packCurrent_mA = currentCodeToMilliamps(cfg.scaling, in.currentCode);
  const bool currentAtRail = in.currentCode <= 0 || in.currentCode >= cfg.scaling.currentCodeMax;
  const float bus = static_cast<float>(in.busVoltageCode) * cfg.scaling.busLsb_mV;
  tm.busVoltage_mV = static_cast<uint32_t>(bus + 0.5f);
  tm.packVoltage_mV = sumMv;
  tm.minCell_mV = counted > 0 ? minMv : 0;
  tm.maxCell_mV = maxMv;
  tm.maxTemp_dC = maxT;
  tm.minTemp_dC = minT;
  tm.maxDie_dC = maxDie;
  tm.maxFet_dC = maxFet;
  tm.monitorFault = deviceFault || in.monitorFaultPin;

  // Charge temperature limits apply while the charger is connected (regen braking in
  // drive is judged by the discharge limits).
  const bool charging = in.chargerPresent;
  auto set = [&](Quantity q, int32_t v) { quantity[static_cast<uint8_t>(q)] = v; };
  // With no cell data yet the voltage rules see neutral values (comm loss covers it).
  set(Quantity::MaxCell_mV, counted > 0 ? maxMv : 0);
  set(Quantity::MinCell_mV, counted > 0 ? minMv : INT32_MAX);
  set(Quantity::DischargeCurrent_mA, tm.packCurrent_mA);
  set(Quantity::ChargeCurrent_mA, -tm.packCurrent_mA);
  set(Quantity::MaxTemp_dC, maxT);
  set(Quantity::MaxTempCharging_dC, charging ? maxT : INT32_MIN);
  set(Quantity::MinTemp_dC, minT);
  set(Quantity::MinTempCharging_dC, charging ? minT : INT32_MAX);
  set(Quantity::MaxDie_dC, maxDie);
  set(Quantity::MaxFet_dC, maxFet);
  set(Quantity::CommBadFrames, worstBad);
  set(Quantity::CellSumError_mV, static_cast<int32_t>(worstSumError_mV));
  set(Quantity::InvalidThermistors, invalid);
  set(Quantity::CurrentCodeAtRail, currentAtRail ? 1 : 0);
  set(Quantity::EStopPulled, (in.eSwitchInternal || in.eSwitchExternal) ? 1 : 0);
  set(Quantity::MonitorFaultLine, tm.monitorFault ? 1 : 0);
  set(Quantity::CellSpread_mV, counted > 0 ? static_cast<int32_t>(maxMv - minMv) : 0);
  return moved;
}

}  // namespace bms
