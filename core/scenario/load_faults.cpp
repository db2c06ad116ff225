// Reads `faults:` (scripted injections) and `expect:` (assertions) strictly.
#include <algorithm>
#include <cmath>
#include <bms/bms_faults.hpp>
#include <cstdio>
#include <sstream>

#include "core/scenario/overrides.hpp"
#include "core/scenario/provenance.hpp"
#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/value_ranges.hpp"

namespace packsim {

namespace {

// What follows a `when:` injection's description in its fault_injected detail.
const std::string kWhenPrefix = " (when ";

struct KindInfo {
  const char* name;
  FaultKind kind;
};

constexpr KindInfo kKinds[] = {
    {"overcurrent", FaultKind::Overcurrent},
    {"hot_cell", FaultKind::HotCell},
    {"internal_short", FaultKind::InternalShort},
    {"estop", FaultKind::EStop},
    {"device_silent", FaultKind::DeviceSilent},
    {"crc_errors", FaultKind::CrcErrors},
    {"device_stuck", FaultKind::DeviceStuck},
    {"broken_link", FaultKind::BrokenLink},
    {"channel_gain", FaultKind::ChannelGain},
    {"channel_offset", FaultKind::ChannelOffset},
    {"thermistor_open", FaultKind::ThermistorOpen},
    {"thermistor_short", FaultKind::ThermistorShort},
    {"welded_relay", FaultKind::WeldedRelay},
    {"current_sensor_drift", FaultKind::CurrentSensorDrift},
    {"charger_overvoltage", FaultKind::ChargerOvervoltage},
    {"host_dead", FaultKind::HostDead},
    {"reset_request", FaultKind::ResetRequest},
    {"key_off", FaultKind::KeyOff},
    {"supply_brownout", FaultKind::SupplyBrownout},
};

struct QuantityInfo {
  const char* name;
  Quantity q;
};

constexpr QuantityInfo kQuantities[] = {
    {"time_s", Quantity::Time_s},          {"cell_min_V", Quantity::CellMin_V},
    {"cell_max_V", Quantity::CellMax_V},   {"soc_min", Quantity::SocMin},
    {"soc_max", Quantity::SocMax},         {"soc", Quantity::SocMean},
    {"pack_current_A", Quantity::PackCurrent_A}, {"pack_voltage_V", Quantity::PackVoltage_V},
    {"temp_max_C", Quantity::TempMax_C},
};

// "<quantity> <op> <number>", op one of < <= > >=.
Condition parseCondition(YamlMap& m, const std::string& key) {
  const std::string text = m.string(key);
  std::istringstream is(text);
  std::string name, op, number;
  is >> name >> op >> number;
  std::string rest;
  is >> rest;
  std::vector<std::string> names;
  for (const auto& q : kQuantities) names.emplace_back(q.name);
  Condition c;
  c.text = text;
  bool found = false;
  for (const auto& q : kQuantities)
    if (name == q.name) {
      c.quantity = q.q;
      found = true;
    }
  if (!found) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    const std::string near = closestMatch(name, names);
    throw m.errorAt(key, "unknown quantity '" + name + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?") +
                             " (known: " + list + ")");
  }
  if (op != "<" && op != "<=" && op != ">" && op != ">=")
    throw m.errorAt(key, "expected a comparison like \"cell_min_V < 3.3\" (operators < <= > >=), got '" + text + "'");
  c.greater = op[0] == '>';
  c.inclusive = op.size() == 2;
  char* end = nullptr;
  c.value = std::strtod(number.c_str(), &end);
  if (number.empty() || *end != '\0' || !rest.empty())
    throw m.errorAt(key, "expected a number after '" + op + "', got '" + number + rest + "'");
  // Every quantity compared (volts, amperes, degrees, SOC, seconds) lies within +-1e7.
  if (!std::isfinite(c.value) || std::fabs(c.value) > 1e7)
    throw m.errorAt(key, "the number '" + number + "' is out of range; allowed [-1e+07, 1e+07]");
  return c;
}

FaultInjection readInjection(YamlMap f, int series, int parallel, int thermistors, const MonitorConfig& afe) {
  const int perBoard = afe.devices_per_board > 0 ? afe.devices_per_board : afe.devices;
  const int boards = (afe.devices + perBoard - 1) / perBoard;
  const int cells = series * parallel;
  FaultInjection inj;
  inj.line = f.raw().Mark().line + 1;
  // An injection an override wrote has no line of its own in the file (its node's mark
  // is the override text's): it is named by its place in the list instead.
  if (const Provenance* p = Provenance::active(); p && p->overridden(f.path()))
    inj.origin = f.path() + (p->topFile() == kDictScenarioName ? ", given in the dict" : ", set by an override");
  inj.parallel = parallel;
  std::vector<std::string> names;
  for (const auto& k : kKinds) names.emplace_back(k.name);
  inj.kind = [&] {
    const std::string kind = f.choice("kind", f.string("kind"), names);
    for (const auto& k : kKinds)
      if (kind == k.name) return k.kind;
    return FaultKind::Overcurrent;
  }();
  if (f.has("at_s") == f.has("when")) throw f.error("give exactly one of at_s or when");
  if (f.has("at_s")) {
    inj.at_s = f.number("at_s", Range::nonNegative(limits::kMaxTime_s));
  } else {
    inj.hasCondition = true;
    inj.when = parseCondition(f, "when");
  }
  inj.duration_s = f.number("duration_s", 0.0, Range::positive(limits::kMaxTime_s));
  auto cell = [&] { return static_cast<int>(f.integer("cell", 1, cells)) - 1; };
  // A cell input of the monitor measures a series group: channel faults count groups.
  auto group = [&] {
    if (f.has("cell"))
      throw f.errorAt("cell", "a channel fault acts on a series group's measurement channel: write group: N (1.." +
                                  std::to_string(series) + ")");
    return static_cast<int>(f.integer("group", 1, series)) - 1;
  };
  // The pack's own monitor devices: a device it does not have would be a fault on nothing
  // (it was taken up to 64 and ran as "injected" with no effect).
  auto device = [&](const char* key) {
    const long d = f.integer(key, -1000000, 1000000);
    if (d < 1 || d > afe.devices)
      throw f.errorAt(key, std::to_string(d) + " is not a device of this pack: it has " + std::to_string(afe.devices) + " monitor device" +
                               (afe.devices > 1 ? "s" : "") + " (hardware.afe: " + std::to_string(afe.cells_per_device) +
                               " series groups a device); allowed [1, " + std::to_string(afe.devices) + "]");
    return static_cast<int>(d) - 1;
  };
  switch (inj.kind) {
    case FaultKind::Overcurrent: inj.value = f.number("current_A", Range::symmetric(limits::kMaxCurrent_A)); break;
    case FaultKind::HotCell:
      inj.index = cell();
      inj.value = f.number("heat_W", Range::closed(0.0, 10000.0));
      break;
    case FaultKind::InternalShort:
      inj.index = cell();
      inj.value = f.number("resistance_ohm", Range::positive(1.0e6));  // 1 MOhm: a leak, no longer a short
      break;
    case FaultKind::EStop: inj.external = f.choice("switch", f.string("switch"), {"internal", "external"}) == "external"; break;
    case FaultKind::DeviceSilent: inj.index = device("device"); break;
    case FaultKind::CrcErrors:
      inj.index = device("device");
      inj.value = f.number("rate", Range::closed(0.0, 1.0));
      break;
    case FaultKind::DeviceStuck: {
      inj.index = device("device");
      const long b = f.integer("byte", 0, 255);
      if (b != 0 && b != 255) throw f.errorAt("byte", "a stuck device reads 0 (0x00) or 255 (0xFF)");
      inj.value = static_cast<double>(b);
      break;
    }
    case FaultKind::BrokenLink: {
      inj.index = device("above_device");
      // It cuts off the devices above it on its own board: the top device of a board has none.
      const int bottom = inj.index / perBoard * perBoard + 1, top = std::min(afe.devices, bottom + perBoard - 1);
      if (inj.index + 1 == top)
        throw f.errorAt("above_device", "device " + std::to_string(top) + " is the top device of its " +
                                            (boards > 1 ? "board" : "stack") + " (devices " + std::to_string(bottom) + "-" +
                                            std::to_string(top) + "): a broken link above it cuts off nothing");
      // A broken link silences the devices above it; a bad joint whose line floats
      // reads 0xFF (or 0x00) from them instead.
      inj.value = -1.0;
      if (f.has("byte")) {
        const long b = f.integer("byte", 0, 255);
        if (b != 0 && b != 255) throw f.errorAt("byte", "the devices above a bad joint read 0 (0x00) or 255 (0xFF)");
        inj.value = static_cast<double>(b);
      }
      break;
    }
    case FaultKind::ChannelGain:
      inj.index = group();
      inj.value = f.number("gain_error", Range::closed(-0.5, 0.5));
      break;
    case FaultKind::ChannelOffset:
      inj.index = group();
      inj.value = f.number("offset_mV", Range::closed(-2000.0, 2000.0)) * 1e-3;
      break;
    case FaultKind::ThermistorOpen:
    case FaultKind::ThermistorShort:
      if (thermistors == 0) throw f.error("the scenario has no thermistors");
      inj.index = static_cast<int>(f.integer("thermistor", 1, thermistors)) - 1;
      break;
    case FaultKind::WeldedRelay: break;
    case FaultKind::CurrentSensorDrift:
      if (!f.has("offset_A") && !f.has("drift_A_per_h")) throw f.error("give offset_A and/or drift_A_per_h");
      inj.value = f.number("offset_A", 0.0, Range::symmetric(limits::kMaxCurrent_A));
      inj.rate_per_s = f.number("drift_A_per_h", 0.0, Range::closed(-1000.0, 1000.0)) / 3600.0;
      break;
    case FaultKind::ChargerOvervoltage: inj.value = f.number("overvoltage_V", Range::closed(0.0, 100.0)); break;
    case FaultKind::HostDead:  // board 1's MCU is the pack host; others, a monitor board's
      inj.index = static_cast<int>(f.integer("board", 1, 1, boards)) - 1;
      break;
    case FaultKind::ResetRequest: break;
    case FaultKind::KeyOff: break;
    case FaultKind::SupplyBrownout:  // the rail's level during the dip; 0: the supply is lost
      inj.value = f.number("supply_V", 0.0, Range::closed(0.0, 100.0));
      break;
  }
  f.finish();
  return inj;
}

std::vector<std::string> bmsFaultNames() {
  std::vector<std::string> n;
  for (uint8_t i = 0; i < bms::kFaultCount; ++i) n.emplace_back(bms::faultName(static_cast<bms::FaultId>(i)));
  return n;
}

std::string checkFaultName(YamlMap& m, const std::string& key) {
  const std::string name = m.string(key);
  const std::vector<std::string> names = bmsFaultNames();
  for (const auto& n : names)
    if (n == name) return name;
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  const std::string near = closestMatch(name, names);
  throw m.errorAt(key, "unknown BMS fault '" + name + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?") +
                           " (known: " + list + ")");
}

std::pair<double, double> window(YamlMap& m, const std::string& key) {
  const std::vector<double> w = m.numbers(key, Range::nonNegative(limits::kMaxTime_s), 2);
  if (w.size() != 2 || !(w[1] >= w[0])) throw m.errorAt(key, "expected [from_s, to_s] with from_s <= to_s");
  return {w[0], w[1]};
}

}  // namespace

const char* faultKindName(FaultKind k) {
  for (const auto& i : kKinds)
    if (i.kind == k) return i.name;
  return "unknown";
}

std::string FaultInjection::cellText() const {
  std::string t = "cell " + std::to_string(index + 1);
  if (parallel > 1) t += " (group " + std::to_string(index / parallel + 1) + ")";
  return t;
}

// The values as written, to six significant digits and with their own sign: "%.3g" with a
// "+" in front printed a charging over-current as "overcurrent +-30 A", 1000 A/h as
// "+1e+03 A/h" and 12.345 A as "+12.3 A".
std::string FaultInjection::injectedDetail() const {
  return describe() + (hasCondition ? kWhenPrefix + when.text + ")" : "");
}

bool injectionDetailIs(const std::string& injectedDetail, const std::string& described) {
  const std::string& d = injectedDetail;
  return d.compare(0, described.size(), described) == 0 &&
         (d.size() == described.size() || d.compare(described.size(), kWhenPrefix.size(), kWhenPrefix) == 0);
}

std::string FaultInjection::describe() const {
  char buf[160];
  switch (kind) {
    case FaultKind::Overcurrent: std::snprintf(buf, sizeof buf, "overcurrent %+.6g A", value); break;
    case FaultKind::HotCell: std::snprintf(buf, sizeof buf, "hot_cell %s, %.6g W", cellText().c_str(), value); break;
    case FaultKind::InternalShort:
      std::snprintf(buf, sizeof buf, "internal_short %s, %.6g ohm", cellText().c_str(), value);
      break;
    case FaultKind::EStop: std::snprintf(buf, sizeof buf, "estop %s pulled", external ? "external" : "internal"); break;
    case FaultKind::DeviceSilent: std::snprintf(buf, sizeof buf, "device_silent device %d", index + 1); break;
    case FaultKind::CrcErrors: std::snprintf(buf, sizeof buf, "crc_errors device %d, rate %.6g", index + 1, value); break;
    case FaultKind::DeviceStuck: std::snprintf(buf, sizeof buf, "device_stuck device %d, 0x%02X", index + 1, static_cast<int>(value)); break;
    case FaultKind::BrokenLink:
      if (value >= 0.0)
        std::snprintf(buf, sizeof buf, "broken_link above device %d, 0x%02X", index + 1, static_cast<int>(value));
      else
        std::snprintf(buf, sizeof buf, "broken_link above device %d", index + 1);
      break;
    case FaultKind::ChannelGain: std::snprintf(buf, sizeof buf, "channel_gain group %d, %+.2f %%", index + 1, value * 100.0); break;
    case FaultKind::ChannelOffset: std::snprintf(buf, sizeof buf, "channel_offset group %d, %+.1f mV", index + 1, value * 1e3); break;
    case FaultKind::ThermistorOpen: std::snprintf(buf, sizeof buf, "thermistor_open thermistor %d", index + 1); break;
    case FaultKind::ThermistorShort: std::snprintf(buf, sizeof buf, "thermistor_short thermistor %d", index + 1); break;
    case FaultKind::WeldedRelay: std::snprintf(buf, sizeof buf, "welded_relay"); break;
    case FaultKind::CurrentSensorDrift:
      if (rate_per_s != 0.0)
        std::snprintf(buf, sizeof buf, "current_sensor_drift %+.6g A %+.6g A/h", value, rate_per_s * 3600.0);
      else
        std::snprintf(buf, sizeof buf, "current_sensor_drift %+.6g A", value);
      break;
    case FaultKind::ChargerOvervoltage: std::snprintf(buf, sizeof buf, "charger_overvoltage +%.6g V", value); break;
    case FaultKind::HostDead:
      if (index > 0)
        std::snprintf(buf, sizeof buf, "host_dead board %d", index + 1);
      else
        std::snprintf(buf, sizeof buf, "host_dead");
      break;
    case FaultKind::ResetRequest: std::snprintf(buf, sizeof buf, "reset_request"); break;
    case FaultKind::KeyOff: std::snprintf(buf, sizeof buf, "key_off"); break;
    case FaultKind::SupplyBrownout: std::snprintf(buf, sizeof buf, "supply_brownout to %.6g V", value); break;
  }
  return buf;
}

std::vector<FaultInjection> readFaults(YamlMap& root, int series, int parallel, int thermistors, const MonitorConfig& afe) {
  std::vector<FaultInjection> out;
  if (!root.has("faults")) return out;
  for (YamlMap f : root.mapList("faults")) out.push_back(readInjection(f, series, parallel, thermistors, afe));
  return out;
}

Expectations readExpect(std::optional<YamlMap> m) {
  Expectations e;
  if (!m) return e;
  e.present = true;
  if (m->has("no_trip")) e.no_trip = m->boolean("no_trip", false);
  if (m->has("trip_reason")) e.trip_reason = checkFaultName(*m, "trip_reason");
  if (m->has("trip_within_s")) e.trip_within_s = window(*m, "trip_within_s");
  if (m->has("relay_open_by_s")) e.relay_open_by_s = m->number("relay_open_by_s", Range::nonNegative(limits::kMaxTime_s));
  if (m->has("detected")) {
    for (YamlMap d : m->mapList("detected")) {
      DetectionExpectation x;
      x.fault = checkFaultName(d, "fault");
      const auto w = window(d, "within_s");
      x.from_s = w.first;
      x.to_s = w.second;
      d.finish();
      e.detected.push_back(x);
    }
  }
  if (m->has("min_cell_V_above")) e.min_cell_V_above = m->number("min_cell_V_above", Range::closed(0.0, 10.0));
  if (m->has("max_temp_C_below")) e.max_temp_C_below = m->number("max_temp_C_below", Range::closed(-60.0, 300.0));
  if (m->has("final_soc_spread_above"))
    e.final_soc_spread_above = m->number("final_soc_spread_above", Range::closed(0.0, 1.0));
  if (m->has("final_soc_spread_below"))
    e.final_soc_spread_below = m->number("final_soc_spread_below", Range::closed(0.0, 1.0));
  if (m->has("energy_delivered_Wh_above"))
    e.energy_delivered_Wh_above = m->number("energy_delivered_Wh_above", Range::symmetric(limits::kMaxEnergy_Wh));
  // Distances up to 1e6 km (25 times round the earth).
  if (m->has("vehicle_distance_km_above"))
    e.vehicle_distance_km_above = m->number("vehicle_distance_km_above", Range::nonNegative(1.0e6));
  if (m->has("vehicle_distance_km_below"))
    e.vehicle_distance_km_below = m->number("vehicle_distance_km_below", Range::nonNegative(1.0e6));
  if (m->has("vehicle_finished")) e.vehicle_finished = m->boolean("vehicle_finished", true);
  readSocExpectations(*m, e);  // load_estimation.cpp
  if (m->has("energy_lost_vs_compare_Wh_above"))
    e.energy_lost_vs_compare_Wh_above = m->number("energy_lost_vs_compare_Wh_above", Range::symmetric(limits::kMaxEnergy_Wh));
  if (m->has("min_cell_V_below_compare")) e.min_cell_V_below_compare = m->boolean("min_cell_V_below_compare", true);
  e.firmware_fault = m->boolean("firmware_fault", false);
  if (m->has("mcu_resets")) e.mcu_resets = static_cast<int>(m->integer("mcu_resets", 0, 100000));
  if (e.no_trip && *e.no_trip && (e.trip_reason || e.trip_within_s))
    throw m->error("no_trip: true contradicts trip_reason / trip_within_s");
  m->finish();
  return e;
}

}  // namespace packsim
