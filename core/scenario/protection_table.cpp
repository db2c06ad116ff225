#include "core/scenario/protection_table.hpp"

#include "core/scenario/value_ranges.hpp"

#include <bms/bms_config.hpp>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>

namespace packsim {

namespace {

using F = bms::FaultId;
using T = bms::Telemetry;
constexpr double kMaxA = limits::kMaxCurrent_A;  // every threshold has a finite range
constexpr double kMilli = 1e3;  // V -> mV, A -> mA
constexpr double kDeci = 10.0;  // °C -> 0.1 °C

constexpr ProtectionSpec rule(F id, const char* unit, double scale, double min, double max, bool minOpen,
                              int32_t (*reading)(const T&), const char* detail) {
  return ProtectionSpec{id, ThresholdUse::Rule, unit, scale, min, max, minOpen, reading, detail};
}
constexpr ProtectionSpec flag(F id, const char* detail) {
  return ProtectionSpec{id, ThresholdUse::None, "", 1.0, 0.0, 0.0, false, nullptr, detail};
}

// clang-format off
constexpr std::array<ProtectionSpec, bms::kFaultCount> kSpecs = {{
  rule(F::CellOverVoltage,           "V", kMilli, 1.0,   5.0,   false, [](const T& t) -> int32_t { return t.maxCell_mV; },
       "max cell {value} V > {threshold} V"),
  rule(F::CellUnderVoltage,          "V", kMilli, 0.5,   4.5,   false, [](const T& t) -> int32_t { return t.minCell_mV; },
       "min cell {value} V < {threshold} V"),
  rule(F::OverCurrentDischarge,      "A", kMilli, 0.0,   kMaxA, true,  [](const T& t) -> int32_t { return t.packCurrent_mA; },
       "current {value} A > {threshold} A"),
  rule(F::OverCurrentCharge,         "A", kMilli, 0.0,   kMaxA, true,  [](const T& t) -> int32_t { return -t.packCurrent_mA; },
       "charge current {value} A > {threshold} A"),
  rule(F::OverTemperature,           "C", kDeci,  0.0,   150.0, false, [](const T& t) -> int32_t { return t.maxTemp_dC; },
       "max temperature {value} C > {threshold} C"),
  rule(F::OverTemperatureCharge,     "C", kDeci,  -60.0, 150.0, false, [](const T& t) -> int32_t { return t.maxTemp_dC; },
       "max temperature while charging {value} C > {threshold} C"),
  rule(F::UnderTemperatureDischarge, "C", kDeci,  -60.0, 150.0, false, [](const T& t) -> int32_t { return t.minTemp_dC; },
       "min temperature {value} C < {threshold} C"),
  rule(F::UnderTemperatureCharge,    "C", kDeci,  -60.0, 150.0, false, [](const T& t) -> int32_t { return t.minTemp_dC; },
       "min temperature while charging {value} C < {threshold} C"),
  rule(F::BoardOverTemperature,      "C", kDeci,  -60.0, 150.0, false, [](const T& t) -> int32_t { return t.maxDie_dC; },
       "monitor die {value} C > {threshold} C"),
  // The count comes from bms.comm_loss_count (bms::AfeConfig), not from this protection.
  flag(F::CommLoss,                  "{count} consecutive bad monitor replies"),
  rule(F::PlausibilityCellSum,       "V", kMilli, 0.001, 1.0,   false, nullptr,
       "sum of cells off the module channel by > {threshold_fw} mV per cell"),
  flag(F::ThermistorFault,           "thermistor reading at a rail (open or shorted)"),
  flag(F::CurrentSensorFault,        "current-sense code at a rail"),
  flag(F::EStop,                     "E-switch pulled"),
  flag(F::MonitorFault,              "monitor IC protection latched (FAULT line)"),
  ProtectionSpec{F::RelayWelded, ThresholdUse::WeldCurrent, "A", kMilli, 0.0, kMaxA, true,
                 [](const T& t) -> int32_t { return std::abs(t.packCurrent_mA); },
                 "relay commanded open but current {value} A still flows or its aux contact reads closed"},
  flag(F::PrechargeFailed,           "precharge did not finish in any attempt"),
  rule(F::TemperatureWarning,        "C", kDeci,  -60.0, 150.0, false, [](const T& t) -> int32_t { return t.maxTemp_dC; },
       "max temperature {value} C > {threshold} C"),
  rule(F::CellImbalance,             "V", kMilli, 0.001, 2.0,   false,
       [](const T& t) -> int32_t { return t.maxCell_mV - t.minCell_mV; },
       "cell spread {value_fw} mV > {threshold_fw} mV"),
  rule(F::FetOverTemperature,        "C", kDeci,  -60.0, 150.0, false, [](const T& t) -> int32_t { return t.maxFet_dC; },
       "FET temperature {value} C > {threshold} C"),
}};
// clang-format on

constexpr bool indexedById() {
  for (size_t i = 0; i < kSpecs.size(); ++i)
    if (static_cast<size_t>(kSpecs[i].id) != i) return false;
  return true;
}
static_assert(indexedById(), "simulator protection row i must have FaultId i");

}  // namespace

const std::array<ProtectionSpec, bms::kFaultCount>& protectionSpecs() { return kSpecs; }

ProtectionConfig defaultProtection(bms::FaultId id) {
  const bms::FaultRow& fw = bms::faultRow(id);
  const ProtectionSpec& sim = protectionSpec(id);
  ProtectionConfig p;
  p.enabled = fw.severity == bms::Severity::Fatal;
  p.delay_s = fw.delay_ms / 1e3;
  if (sim.use == ThresholdUse::Rule) {
    p.threshold = fw.threshold / sim.scale;
    p.hysteresis = fw.hysteresis / sim.scale;
  } else if (sim.use == ThresholdUse::WeldCurrent) {
    p.threshold = bms::kDefaultWeldCurrent_mA / sim.scale;
  }
  return p;
}

std::array<ProtectionConfig, bms::kFaultCount> defaultProtections() {
  std::array<ProtectionConfig, bms::kFaultCount> all;
  for (uint8_t i = 0; i < bms::kFaultCount; ++i) all[i] = defaultProtection(static_cast<bms::FaultId>(i));
  return all;
}

std::string protectionDetail(bms::FaultId id, int32_t threshold_fw, uint32_t delay_ms, const bms::Telemetry& tm) {
  const ProtectionSpec& s = protectionSpec(id);
  const double toSi = 1.0 / s.scale;
  const int32_t value_fw = s.reading ? s.reading(tm) : 0;
  std::ostringstream os;
  os.setf(std::ios::fixed);
  os.precision(3);
  for (const char* c = s.detail; *c;) {
    auto take = [&](const char* token) {
      const size_t n = std::strlen(token);
      if (std::strncmp(c, token, n) != 0) return false;
      c += n;
      return true;
    };
    if (take("{value}")) os << value_fw * toSi;
    else if (take("{threshold}")) os << threshold_fw * toSi;
    else if (take("{value_fw}")) os << value_fw;
    else if (take("{threshold_fw}")) os << threshold_fw;
    else if (take("{count}")) os << (threshold_fw + 1);
    else os << *c++;
  }
  // A protection without a debounce acts on the reading itself: "for 0 ms" read as if the
  // condition had lasted no time ("5 consecutive bad monitor replies for 0 ms").
  if (delay_ms > 0) os << " for " << delay_ms << " ms";
  return os.str();
}

const std::vector<std::string>& faultActionNames() {
  static const std::vector<std::string> names = {"isolate", "monitor", "monitor_while_driving"};
  return names;
}

}  // namespace packsim
