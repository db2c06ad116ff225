#include "bms_faults.hpp"

namespace bms {

namespace {

// Which actuator a fault opens follows reference system A: the monitor side (relay)
// isolates on voltage, current, temperature, E-switch and comm; the MCU opens the
// discharge MOSFET on over-current, over-temperature and the E-switch. Warnings and
// infos open nothing and do not latch.
using F = FaultId;
using Q = Quantity;
using U = FaultUnit;
constexpr Severity kFatal = Severity::Fatal;
constexpr uint8_t R = kActRelay, D = kActDischargeFet, C = kActChargeFet;
// clang-format off
constexpr FaultRow kRows[] = {
  // id                          name                       quantity                above  thr    hyst  delay  unit        severity           latch  opens
  {F::CellOverVoltage,           "cell_overvoltage",        Q::MaxCell_mV,          true,  4250,  50,   500,  U::mV,      kFatal,            true,  R | C},
  {F::CellUnderVoltage,          "cell_undervoltage",       Q::MinCell_mV,          false, 3000,  100,  500,  U::mV,      kFatal,            true,  R},
  {F::OverCurrentDischarge,      "overcurrent_discharge",   Q::DischargeCurrent_mA, true,  30000, 1000, 100,  U::mA,      kFatal,            true,  R | D},
  {F::OverCurrentCharge,         "overcurrent_charge",      Q::ChargeCurrent_mA,    true,  5000,  500,  100,  U::mA,      kFatal,            true,  R | C},
  {F::OverTemperature,           "overtemperature",         Q::MaxTemp_dC,          true,  600,   50,   1000, U::dC,      kFatal,            true,  R | D | C},
  {F::OverTemperatureCharge,     "overtemperature_charge",  Q::MaxTempCharging_dC,  true,  450,   50,   1000, U::dC,      kFatal,            true,  R | C},
  {F::UnderTemperatureDischarge, "undertemperature",        Q::MinTemp_dC,          false, -200,  50,   1000, U::dC,      kFatal,            true,  R | D},
  {F::UnderTemperatureCharge,    "undertemperature_charge", Q::MinTempCharging_dC,  false, 0,     50,   1000, U::dC,      kFatal,            true,  R | C},
  {F::BoardOverTemperature,      "board_overtemperature",   Q::MaxDie_dC,           true,  1050,  100,  1000, U::dC,      kFatal,            true,  R | D | C},
  {F::CommLoss,                  "comm_loss",               Q::CommBadFrames,       true,  4,     0,    0,    U::Replies, kFatal,            true,  R},
  {F::PlausibilityCellSum,       "cell_sum_plausibility",   Q::CellSumError_mV,     true,  50,    10,   1000, U::mV,      kFatal,            true,  R},
  {F::ThermistorFault,           "thermistor_fault",        Q::InvalidThermistors,  true,  0,     0,    1000, U::Flag,    kFatal,            true,  R | D | C},
  {F::CurrentSensorFault,        "current_sensor_fault",    Q::CurrentCodeAtRail,   true,  0,     0,    500,  U::Flag,    kFatal,            true,  R | D | C},
  {F::EStop,                     "estop",                   Q::EStopPulled,         true,  0,     0,    0,    U::Flag,    kFatal,            true,  R | D | C},
  {F::MonitorFault,              "monitor_fault",           Q::MonitorFaultLine,    true,  0,     0,    0,    U::Flag,    kFatal,            true,  R},
  {F::RelayWelded,               "relay_welded",            Q::RelayStuckClosed,    true,  0,     0,    200,  U::Flag,    kFatal,            true,  D | C},
  {F::PrechargeFailed,           "precharge_failed",        Q::PrechargeFailed,     true,  0,     0,    0,    U::Flag,    kFatal,            true,  R},
  {F::TemperatureWarning,        "temperature_warning",     Q::MaxTemp_dC,          true,  517,   20,   1000, U::dC,      Severity::Warning, false, 0},
  {F::CellImbalance,             "cell_imbalance",          Q::CellSpread_mV,       true,  50,    10,   1000, U::mV,      Severity::Info,    false, 0},
  {F::FetOverTemperature,        "fet_overtemperature",     Q::MaxFet_dC,           true,  850,   100,  2000, U::dC,      kFatal,            true,  R | D | C},
};
// clang-format on

constexpr bool indexedById() {
  for (uint8_t i = 0; i < kFaultCount; ++i)
    if (static_cast<uint8_t>(kRows[i].id) != i) return false;
  return true;
}
static_assert(sizeof(kRows) / sizeof(kRows[0]) == kFaultCount, "one protection row per FaultId");
static_assert(indexedById(), "protection row i must have FaultId i");

}  // namespace

const FaultRow& faultRow(FaultId id) { return kRows[static_cast<uint8_t>(id)]; }

const char* faultName(FaultId id) {
  return static_cast<uint8_t>(id) < kFaultCount ? kRows[static_cast<uint8_t>(id)].name : "unknown";
}

}  // namespace bms
