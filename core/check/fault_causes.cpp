#include "core/check/fault_causes.hpp"

#include <algorithm>
#include <cmath>

namespace packsim {

namespace {

using V = std::vector<std::string>;

// Voltage faults follow from a wrong cell reading or a cell pulled low; temperature faults
// from heat or a wrong thermistor; the monitor IC's own FAULT line (monitor_fault) from
// what its comparators see (voltage, temperature, current).
const V kNone{};
const V kOvercurrent{"overcurrent_discharge", "overcurrent_charge", "current_sensor_fault", "cell_undervoltage",
                     "monitor_fault", "overtemperature", "temperature_warning", "fet_overtemperature"};
const V kHotCell{"overtemperature", "overtemperature_charge", "temperature_warning", "monitor_fault"};
const V kInternalShort{"cell_undervoltage", "cell_imbalance", "cell_sum_plausibility", "overtemperature",
                       "overtemperature_charge", "temperature_warning", "monitor_fault"};
const V kEStop{"estop"};
const V kComm{"comm_loss", "cell_sum_plausibility", "thermistor_fault", "cell_overvoltage", "cell_undervoltage",
              "monitor_fault"};
const V kChannel{"cell_overvoltage", "cell_undervoltage", "cell_sum_plausibility", "cell_imbalance", "monitor_fault"};
const V kThermistor{"thermistor_fault", "overtemperature", "overtemperature_charge", "undertemperature",
                    "undertemperature_charge", "temperature_warning", "fet_overtemperature"};
const V kWelded{"relay_welded"};
const V kDrift{"current_sensor_fault", "overcurrent_discharge", "overcurrent_charge"};
const V kCharger{"cell_overvoltage", "overcurrent_charge", "overtemperature_charge", "monitor_fault"};
const V kHostDead{"comm_loss", "monitor_fault"};

}  // namespace

const std::vector<std::string>& faultsCausedBy(FaultKind kind) {
  switch (kind) {
    case FaultKind::Overcurrent: return kOvercurrent;
    case FaultKind::HotCell: return kHotCell;
    case FaultKind::InternalShort: return kInternalShort;
    case FaultKind::EStop: return kEStop;
    case FaultKind::DeviceSilent:
    case FaultKind::CrcErrors:
    case FaultKind::DeviceStuck:
    case FaultKind::BrokenLink: return kComm;
    case FaultKind::ChannelGain:
    case FaultKind::ChannelOffset: return kChannel;
    case FaultKind::ThermistorOpen:
    case FaultKind::ThermistorShort: return kThermistor;
    case FaultKind::WeldedRelay: return kWelded;
    case FaultKind::CurrentSensorDrift: return kDrift;
    case FaultKind::ChargerOvervoltage: return kCharger;
    case FaultKind::HostDead: return kHostDead;
    case FaultKind::ResetRequest:
    case FaultKind::KeyOff:
    case FaultKind::SupplyBrownout: return kNone;  // the MCU resets; its reboot is no BMS fault
  }
  return kNone;
}

bool faultKindOfDetail(const std::string& detail, FaultKind& kind) {
  const std::string word = detail.substr(0, detail.find(' '));
  for (int k = 0; k <= static_cast<int>(FaultKind::SupplyBrownout); ++k)
    if (word == faultKindName(static_cast<FaultKind>(k))) {
      kind = static_cast<FaultKind>(k);
      return true;
    }
  return false;
}

std::vector<InjectionSpan> injectionSpans(const std::vector<Event>& events) {
  std::vector<InjectionSpan> spans;
  for (const Event& e : events) {
    if (e.kind == "fault_injected") {
      InjectionSpan sp;
      sp.injected = &e;
      sp.start_s = e.time_s;
      sp.end_s = INFINITY;
      sp.known = faultKindOfDetail(e.detail, sp.kind);
      spans.push_back(sp);
    } else if (e.kind == "fault_removed") {
      // The earliest injection of this detail still in place (a `when:` injection's
      // detail carries its condition, its removal does not).
      for (InjectionSpan& sp : spans)
        if (std::isinf(sp.end_s) && injectionDetailIs(sp.injected->detail, e.detail)) {
          sp.end_s = e.time_s;
          break;
        }
    }
  }
  return spans;
}

const InjectionSpan* laterCause(const std::vector<InjectionSpan>& spans, const InjectionSpan& own,
                                const std::string& name, double t_s) {
  if (std::isinf(own.end_s)) return nullptr;
  for (const InjectionSpan& sp : spans) {
    if (&sp == &own || !sp.known || sp.start_s < own.end_s - 1e-9 || sp.start_s > t_s + 1e-9) continue;
    const std::vector<std::string>& causes = faultsCausedBy(sp.kind);
    if (std::find(causes.begin(), causes.end(), name) != causes.end()) return &sp;
  }
  return nullptr;
}

}  // namespace packsim
