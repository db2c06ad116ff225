#include "core/scenario/derived_defaults.hpp"

#include <algorithm>
#include <initializer_list>
#include <sstream>

#include "core/scenario/provenance.hpp"

namespace packsim {

namespace {

bool stated(const YAML::Node& n, std::initializer_list<const char*>::const_iterator key,
            std::initializer_list<const char*>::const_iterator end) {
  if (key == end) return true;
  if (!n.IsMap()) return false;
  const YAML::Node child = n[*key];
  return child.IsDefined() && stated(child, key + 1, end);
}

bool stated(const YAML::Node& root, std::initializer_list<const char*> path) {
  return stated(root, path.begin(), path.end());
}

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(4);
  os << v;
  return os.str();
}

}  // namespace

double loadPeakDischarge_A(const Scenario& s) {
  double peak = 0.0;
  const double scale = s.load.quantity == LoadProfile::Quantity::Power_W ? 1.0 / (s.pack.series * s.pack.cell.v_min_V) : 1.0;
  for (double v : s.load.i_A) peak = std::max(peak, v * scale);
  return peak;
}

double loadPeakCharge_A(const Scenario& s) {
  double peak = s.charger.present ? s.charger.current_A : 0.0;
  const double scale = s.load.quantity == LoadProfile::Quantity::Power_W ? 1.0 / (s.pack.series * s.pack.cell.v_min_V) : 1.0;
  for (double v : s.load.i_A) peak = std::max(peak, -v * scale);
  return peak;
}

void applyDerivedDefaults(const YAML::Node& root, Scenario& s) {
  Provenance* prov = Provenance::active();
  const CellParams& cell = s.pack.cell;
  const double packAh = cell.capacity_Ah * s.pack.parallel;
  const std::string perPack = " x " + fmt(cell.capacity_Ah) + " Ah x " + std::to_string(s.pack.parallel) + " in parallel";
  // packsim's core's protection defaults are warned of only when the core runs: a user's
  // firmware (bms.firmware) judges on its own thresholds, and "state the threshold" sent
  // its engineer to a key it never reads.
  const bool coreRuns = !s.bms.firmware.library;
  auto note = [&](const std::string& key, double v, const std::string& why) {
    if (!prov) return;
    prov->recordDefault(key, numberText(v), "default (" + why + ")");
    if (coreRuns) prov->warn(key + " = " + fmt(v) + " (default): " + why + "; state it if the pack's hardware differs");
  };

  // Charge limit: from the cell, never another pack's 5 A.
  ProtectionConfig& occ = s.bms.protection(bms::FaultId::OverCurrentCharge);
  if (!stated(root, {"bms", "protections", "overcurrent_charge", "threshold_A"})) {
    const bool rated = cell.max_charge_C > 0.0;
    occ.threshold = (rated ? cell.max_charge_C : kDefaultChargeC) * packAh;
    if (!stated(root, {"bms", "protections", "overcurrent_charge", "hysteresis_A"}))
      occ.hysteresis = std::min(occ.hysteresis, 0.1 * occ.threshold);
    if (occ.enabled)
      note("bms.protections.overcurrent_charge.threshold_A", occ.threshold,
           rated ? "the cell's max_charge_C " + fmt(cell.max_charge_C) + perPack
                 : "1C" + perPack + ": the cell states no max_charge_C");
  }
  ProtectionConfig& ocd = s.bms.protection(bms::FaultId::OverCurrentDischarge);
  if (!stated(root, {"bms", "protections", "overcurrent_discharge", "threshold_A"})) {
    if (cell.max_discharge_C > 0.0) {
      ocd.threshold = cell.max_discharge_C * packAh;
      if (!stated(root, {"bms", "protections", "overcurrent_discharge", "hysteresis_A"}))
        ocd.hysteresis = std::min(ocd.hysteresis, 0.1 * ocd.threshold);
      if (ocd.enabled)
        note("bms.protections.overcurrent_discharge.threshold_A", ocd.threshold,
             "the cell's max_discharge_C " + fmt(cell.max_discharge_C) + perPack);
    } else if (ocd.enabled && prov && coreRuns) {
      prov->warn("bms.protections.overcurrent_discharge.threshold_A = " + fmt(ocd.threshold) +
                 " (default): the firmware table's limit, not derived from this pack (its cell states no "
                 "max_discharge_C); state the threshold or pack.cell.max_discharge_C");
    }
  }

  // Thermistors: four spread over the string unless stated (readHardware).
  if (prov && !stated(root, {"hardware", "thermistors", "at_groups"}) && !stated(root, {"hardware", "thermistors", "channels"})) {
    std::string sites;
    for (const ThermistorSite& t : s.hardware.thermistor_sites) sites += (sites.empty() ? "" : ", ") + std::to_string(t.cell + 1);
    prov->recordDefault("hardware.thermistors.at_groups", "[" + sites + "]", "default (up to 4 spread over the string)");
  }

  // Current sensor: sized to the limits it must judge and the load it must measure.
  CurrentSense& cs = s.hardware.current_sense;
  if (!stated(root, {"hardware", "current_sense", "shunt_ohm"}) && !stated(root, {"hardware", "current_sense", "amp_gain"})) {
    double limit_A = 0.0;
    for (const ProtectionConfig* p : {&ocd, &occ})
      if (p->enabled) limit_A = std::max(limit_A, p->threshold);
    const double load_A = std::max(loadPeakDischarge_A(s), loadPeakCharge_A(s));
    const double range_A = std::max(kSensorRangeOverLimit * limit_A, kSensorRangeOverLoad * load_A);
    if (range_A > 0.0) {
      cs.amp_gain = (cs.vref_V / 2.0) / (range_A * cs.shunt_ohm);
      const std::string why = "a +/-" + fmt(range_A) + " A range: " +
                              (kSensorRangeOverLimit * limit_A >= kSensorRangeOverLoad * load_A
                                   ? "1.5 x the highest over-current limit " + fmt(limit_A) + " A"
                                   : "1.25 x the load's peak " + fmt(load_A) + " A") +
                              ", on the " + fmt(cs.shunt_ohm * 1e3) + " mOhm shunt";
      note("hardware.current_sense.amp_gain", cs.amp_gain, why);
    }
  }
}

}  // namespace packsim
