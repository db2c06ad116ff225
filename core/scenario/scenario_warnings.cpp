#include "core/scenario/scenario_warnings.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/parts/monitor_parts.hpp"
#include "core/scenario/derived_defaults.hpp"
#include "core/scenario/number_ranges.hpp"
#include "core/scenario/provenance.hpp"
#include "core/scenario/rest_noise_warning.hpp"
#include "core/scenario/start_voltage_warning.hpp"

namespace packsim {

namespace {

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(4);
  os << v;
  return os.str();
}

// Where a whole section (e.g. `load`) came from: its first recorded key's origin.
std::string sectionOrigin(const Provenance& p, const std::string& section) {
  for (const ProvenanceEntry& e : p.entries())
    if (keyUnder(e.key, section)) {
      const std::string o = e.origin;
      return o.rfind("default", 0) == 0 ? "default" : o;
    }
  return "default";
}

double sensorRange_A(const Scenario& s) {
  const CurrentSense& c = s.hardware.current_sense;
  return c.zeroCode() * c.lsb_A();
}

std::string sensorText(const Scenario& s, const Provenance& p) {
  return "the current sensor's +/-" + fmt(sensorRange_A(s)) + " A (hardware.current_sense: shunt_ohm " +
         p.originOf("hardware.current_sense.shunt_ohm") + ", amp_gain " + p.originOf("hardware.current_sense.amp_gain") + ")";
}

// An over-current limit close to (or the load beyond) what the current sensor can read.
void checkSensorRange(const Scenario& s, const Provenance& p, std::vector<std::string>& out) {
  const double range_A = sensorRange_A(s);
  const struct {
    bms::FaultId id;
    const char* key;
  } limits[] = {{bms::FaultId::OverCurrentDischarge, "bms.protections.overcurrent_discharge.threshold_A"},
                {bms::FaultId::OverCurrentCharge, "bms.protections.overcurrent_charge.threshold_A"}};
  for (const auto& l : limits) {
    const ProtectionConfig& pc = s.bms.protection(l.id);
    if (pc.enabled && pc.threshold > kLimitNearSensorRange * range_A && pc.threshold < range_A)
      out.push_back(p.describe(l.key, numberText(pc.threshold)) + " is within " +
                    fmt(100.0 * (1.0 - kLimitNearSensorRange)) + " % of " + sensorText(s, p) +
                    ": a current just past the limit reads at the sensor's rail");
  }
  const double discharge_A = loadPeakDischarge_A(s), charge_A = loadPeakCharge_A(s);
  if (std::max(discharge_A, charge_A) > range_A)
    out.push_back("load (" + sectionOrigin(p, s.charger.present ? "load.charger" : "load") + ") peaks at " +
                  fmt(std::max(discharge_A, charge_A)) + " A, beyond " + sensorText(s, p) +
                  ": the BMS reads the rail, not the current");
}

}  // namespace

int thermistorReachLinks(const Scenario& s) {
  const double g = s.thermal.cell_to_cell_W_per_K;
  if (g <= 0.0) return 0;
  double loss = s.pack.cell.g_ambient_W_per_K + s.thermal.g_coolant_W_per_K;
  for (const ThermalNodeConfig& n : s.thermal.nodes) loss += n.g_each_cell_W_per_K;
  if (loss <= 0.0) return kThermistorReachLinks;
  // A cell n links from the hot one, at steady state on a long chain: g (T[n+1] - 2 T[n] +
  // T[n-1]) = loss T[n], so T[n] = T[0] r^n with r + 1/r = 2 + loss/g (the root below 1).
  const double a = loss / g;
  const double r = 1.0 / (1.0 + 0.5 * a + std::sqrt(a + 0.25 * a * a));
  const double links = std::floor(std::log(kThermistorSeenFraction) / std::log(r));
  return links < kThermistorReachLinks ? static_cast<int>(links) : kThermistorReachLinks;
}

namespace {

// Why the reach is short of kThermistorReachLinks, for the warning.
std::string reachReason(const Scenario& s, const Provenance& p, int reach) {
  if (reach >= kThermistorReachLinks) return "";
  const std::string g = p.describe("thermal.cell_to_cell_W_per_K", numberText(s.thermal.cell_to_cell_W_per_K));
  if (reach == 0 && s.thermal.cell_to_cell_W_per_K <= 0.0)
    return "; " + g + ": no heat flows from cell to cell, so a thermistor sees only the cell it sits on";
  return "; " + g + " against each cell's own losses (ambient, coolant, nodes): even at steady state a hot cell lifts a cell " +
         std::to_string(reach + 1) + " links away by less than " + fmt(100.0 * kThermistorSeenFraction) +
         " % of its own rise";
}

// A cell further than thermistorReachLinks cell-to-cell conductances from every cell a
// thermistor sits on. The cells are linked in storage order, group by group, and a
// thermistor sits on its group's first cell: with parallel cells a group's others are 1 ..
// parallel-1 links from it, so the reach counts cells, not groups.
void checkThermistorReach(const Scenario& s, const Provenance& p, std::vector<std::string>& out) {
  const ThermistorTable& therm = s.hardware.thermistors;
  const int parallel = s.pack.parallel;
  std::string where = p.describe("hardware.thermistors.at_groups");
  if (sectionOrigin(p, "hardware.thermistors.channels") != "default")
    where = "hardware.thermistors.channels (" + sectionOrigin(p, "hardware.thermistors.channels") + ")";
  if (therm.nearest.empty() || therm.nearest.front() < 0) {
    out.push_back(where + ": no thermistor sits on a cell; no cell temperature is measured");
    return;
  }
  const int reach = thermistorReachLinks(s);
  std::vector<int> far;  // 1-based cells (series groups without parallel cells)
  for (int c = 0; c < s.pack.series * parallel; ++c) {
    int links = s.pack.series * parallel;
    for (const ThermistorChannel& ch : therm.channels)
      if (ch.site == ThermSite::Cell) links = std::min(links, std::abs(ch.group * parallel - c));
    if (links > reach) far.push_back(c + 1);
  }
  if (far.empty()) return;
  std::ostringstream os;
  os << where << ": " << (parallel > 1 ? "cell" : "series group") << (far.size() > 1 ? "s " : " ") << numberRanges(far);
  const char* verb = far.size() > 1 ? "are" : "is";
  if (parallel > 1)
    os << " (1-based, " << parallel << " to a group; each thermistor sits on its group's first cell) ";
  else
    os << " (1-based) ";
  const char* unit = parallel > 1 ? " cell" : " group";
  if (reach == 0)
    os << (far.size() > 1 ? "carry" : "carries") << " no thermistor";
  else
    os << verb << " more than " << reach << unit << (reach == 1 ? "" : "s") << " from every thermistor"
       << (parallel > 1 ? " along the cell-to-cell conductances" : "");
  os << reachReason(s, p, reach) << ": a hot cell there goes unseen";
  out.push_back(os.str());
}

// Load magnitudes per cell beyond what the cell states (or beyond any plausible cell).
void checkLoadMagnitude(const Scenario& s, const Provenance& p, std::vector<std::string>& out) {
  const CellParams& c = s.pack.cell;
  const double packAh = c.capacity_Ah * s.pack.parallel;
  const std::string cellWhere = "pack.cell.capacity_Ah = " + fmt(c.capacity_Ah) + " (" + p.originOf("pack.cell.capacity_Ah") +
                                "), pack.parallel = " + std::to_string(s.pack.parallel);
  const std::string loadWhere = "load (" + sectionOrigin(p, s.charger.present ? "load.charger" : "load") + ")";
  const bool power = s.load.quantity == LoadProfile::Quantity::Power_W;
  const struct {
    double peak_A, limitC;
    bool rated;
    const char* what;
    const char* rating;
  } dirs[] = {{loadPeakDischarge_A(s), c.max_discharge_C > 0 ? c.max_discharge_C : kImplausibleDischargeC,
               c.max_discharge_C > 0, "discharge", "max_discharge_C"},
              {loadPeakCharge_A(s), c.max_charge_C > 0 ? c.max_charge_C : kImplausibleChargeC, c.max_charge_C > 0,
               "charge", "max_charge_C"}};
  for (const auto& d : dirs) {
    const double rate = d.peak_A / packAh;
    if (!(rate > d.limitC)) continue;
    std::ostringstream os;
    os << loadWhere << ": a peak " << d.what << " of " << fmt(d.peak_A) << " A";
    if (power) {
      const double cells = static_cast<double>(s.pack.series) * s.pack.parallel;
      os << " (" << fmt(d.peak_A * s.pack.series * c.v_min_V / cells) << " W per cell at v_min_V)";
    }
    os << " is " << fmt(rate) << "C per cell (" << fmt(d.peak_A / s.pack.parallel) << " A each; " << cellWhere << "), above "
       << (d.rated ? "the cell's " + std::string(d.rating) + " " + fmt(d.limitC) + " (" + p.originOf(std::string("pack.cell.") + d.rating) + ")"
                   : fmt(d.limitC) + "C, implausible for any cell (a unit slip: mA, W or kW read as A?)");
    out.push_back(os.str());
  }
}

// Balancing resistors whose heat goes nowhere the BMS can see.
void checkBalancingBoard(const Scenario& s, const Provenance& p, std::vector<std::string>& out) {
  const PassiveBalancerConfig& b = s.hardware.balancing;
  if (!b.present || !b.board_node.empty()) return;
  // (bms.balancing is packsim's core's: a user's firmware's own board limit is told instead)
  out.push_back(p.describe("hardware.balancing.resistor_ohm", numberText(b.resistor_ohm)) +
                ": the balancing resistors have no board_node, so their heat goes straight to ambient: no board "
                "temperature is simulated and " +
                (s.bms.firmware.library ? "no board-temperature limit of the firmware can act"
                                        : "bms.balancing.board_max_C can never act"));
}

// Balancing resistors that nothing switches: packsim's core balances only with a
// bms.balancing section, and no part balances on its own here. A resistor sweep over
// such a base gives identical rows.
void checkBalancingUnused(const Scenario& s, const Provenance& p, std::vector<std::string>& out) {
  const PassiveBalancerConfig& b = s.hardware.balancing;
  if (!b.present || s.bms.firmware.library || s.bms.image.balance.enabled) return;
  const MonitorPart& part = monitorPart(s.hardware.afe.model);
  if (part.balances_on_its_own != nullptr && part.balances_on_its_own(s.hardware.afe)) return;
  out.push_back(p.describe("hardware.balancing.resistor_ohm", numberText(b.resistor_ohm)) +
                ": no balancing policy switches these resistors (packsim's core balances only with a bms.balancing "
                "section, and the " + s.hardware.afe.model + " does not balance on its own here): the run never "
                "balances, and a sweep over the resistor gives the same result for every value");
}

// A run ends at a BMS tick (the last one at or before its end time): an end time between
// two ticks is cut short, which the summary's duration shows but does not explain.
void checkRunEnd(const Scenario& s, const Provenance& p, std::vector<std::string>& out) {
  if (s.vehicle.present && s.run.duration_s <= 0.0) return;  // the vehicle ends its own run
  const double end_s = s.endTime_s();
  const double ticks = std::floor(end_s / s.bms.tick_s + 1e-9);  // SimulationRun's last tick
  const double last_s = ticks * s.bms.tick_s;
  if (end_s - last_s <= 1e-9 * std::max(1.0, end_s)) return;
  const auto seconds = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return std::string(buf);
  };
  const std::string tick = "bms.tick_ms " + std::to_string(std::lround(s.bms.tick_s * 1e3));
  out.push_back((s.run.duration_s > 0.0 ? p.describe("run.duration_s", numberText(s.run.duration_s))
                                        : "run.duration_s = " + seconds(end_s) + " (default: the load profile's length)") +
                " is not a whole number of BMS ticks (" + tick + "): the run ends at its last tick, " + seconds(last_s) +
                " s, " + seconds(end_s - last_s) + " s early");
}

// A profile that charges the pack on balance over the run (its mean below 0): packsim
// counts discharge positive, and many loggers count it negative. Such a log read as it
// stands races a pack that charges -- a plausible run of the wrong sign. A constant load
// (a charge current given as such) and the vehicle, which computes its own load, are not
// judged.
void checkLoadSign(const Scenario& s, const Provenance& p, std::vector<std::string>& out) {
  const LoadProfile& l = s.load;
  if (s.vehicle.present || l.isConstant() || l.t_s.empty()) return;
  const double end_s = std::min(s.endTime_s(), l.duration_s());
  if (!(end_s > 0.0)) return;
  const double mean = l.chargeUntil_As(end_s) / end_s;
  if (!(mean < 0.0)) return;
  const bool watts = l.quantity == LoadProfile::Quantity::Power_W;
  const bool csv = p.find("load.csv") || p.find("load.csv.file");
  std::ostringstream os;
  os << "load (" << sectionOrigin(p, "load") << ") charges the pack on balance: its mean is " << fmt(mean)
     << (watts ? " W" : " A") << " over the run's first " << fmt(end_s)
     << " s; packsim counts discharge as positive and regeneration as negative: a log that records discharge as "
        "negative needs "
     << (csv ? "load.csv.scale: -1 (csv: {file, time_column, " + std::string(watts ? "power" : "current") +
                   "_column, scale: -1})"
             : "its values' signs flipped");
  out.push_back(os.str());
}

std::string describeTable(const YAML::Node& n) {
  if (n.IsSequence()) return "list of " + std::to_string(n.size()) + " values";
  if (!n.IsMap()) return "value";
  std::string axis = n["axis"] && n["axis"].IsScalar() ? n["axis"].Scalar() : "soc";
  std::vector<std::string> dims;
  if (n["x"] || n["poly"]) dims.push_back(axis);
  if (n["temp_C"] || n["arrhenius_K"]) dims.push_back("temperature");
  if (dims.empty()) return "mapping";
  std::string d = dims[0];
  for (size_t i = 1; i < dims.size(); ++i) d += " and " + dims[i];
  return "curve over " + d;
}

}  // namespace

std::string nodePlace(const std::string& file, const YAML::Node& n) {
  return n.Mark().line >= 0 ? file + ":" + std::to_string(n.Mark().line + 1) : file;
}

std::string dependenceRemovedWarning(const std::string& key, const YAML::Node& before, const std::string& beforeWhere,
                                     const YAML::Node& after, const std::string& afterWhere) {
  return key + ": the " + describeTable(before) + " of " + beforeWhere + " is replaced by the single value " +
         after.Scalar() + " (" + afterWhere + "); the dependence is gone";
}

void presetDependenceWarnings(const std::string& cellKey, const CellParams& preset, const CellParams& cell,
                              const YAML::Node& given, const std::string& presetName, Provenance& prov) {
  const struct {
    const char* key;
    const Curve& before;
    const Curve& after;
  } curves[] = {{"ocv_V", preset.ocv_V, cell.ocv_V},
                {"r0_ohm", preset.r0_ohm, cell.r0_ohm},
                {"r0_charge_ohm", preset.r0_charge_ohm, cell.r0_charge_ohm},
                {"docv_dT_V_per_K", preset.docv_dT_V_per_K, cell.docv_dT_V_per_K},
                {"hysteresis.max_V", preset.hysteresis_max_V, cell.hysteresis_max_V}};
  for (const auto& c : curves) {
    const std::string field = c.key;
    const YAML::Node node = field == "hysteresis.max_V" ? YAML::Node() : given[c.key];
    if (node && node.IsMap()) continue;  // a curve of its own: deliberate
    const std::string key = cellKey + "." + c.key;
    std::vector<std::string> lost;
    if (c.before.kind != Curve::Kind::Constant && c.after.kind == Curve::Kind::Constant)
      lost.push_back(c.before.axis == CurveAxis::Soc ? "SOC" : "discharged charge");
    if (c.before.dependsOnTemperature() && !c.after.dependsOnTemperature()) lost.push_back("temperature");
    if (lost.empty()) continue;
    std::string what = lost[0] + (lost.size() > 1 ? " and " + lost[1] : "");
    prov.warn(prov.describe(key) + " replaces " + presetName + "'s curve, which depends on " + what +
              ": this cell's " + c.key + " does not (give a curve to keep the dependence)");
  }
}

const std::vector<WarningCheck>& warningChecks() {
  static const std::vector<WarningCheck> checks = {
      {"sensor_range", checkSensorRange},
      {"thermistor_reach", checkThermistorReach},
      {"load_magnitude", checkLoadMagnitude},
      {"balancing_board", checkBalancingBoard},
      {"balancing_unused", checkBalancingUnused},
      {"run_end", checkRunEnd},
      {"load_sign", checkLoadSign},
      {"start_voltage", checkStartVoltage},
      {"rest_noise", checkRestNoise},
  };
  return checks;
}

std::vector<std::string> scenarioWarnings(const Scenario& s) {
  const Provenance none("");
  const Provenance& p = s.provenance ? *s.provenance : none;
  std::vector<std::string> out = p.warnings();
  for (const WarningCheck& c : warningChecks()) c.check(s, p, out);
  return out;
}

}  // namespace packsim
