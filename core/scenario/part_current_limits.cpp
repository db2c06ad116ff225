#include "core/scenario/part_current_limits.hpp"

#include <string>

#include "core/scenario/derived_defaults.hpp"
#include "core/scenario/provenance.hpp"
#include "core/text_fmt.hpp"

namespace packsim {

namespace {

std::string amps(double a) { return fmt("%.3g A", a); }

// Whether the scenario states hardware.afe.protection.<key> (else it is the part's default).
bool stated(const YAML::Node& root, const char* key) {
  YAML::Node n = root;
  for (const char* k : {"hardware", "afe", "protection"}) {
    if (!n.IsMap() || !n[k].IsDefined()) return false;
    n = n[k];
  }
  return n.IsMap() && n[key].IsDefined();
}

}  // namespace

void warnPartCurrentLimits(const YAML::Node& root, const Scenario& s) {
  Provenance* prov = Provenance::active();
  const MonitorConfig& afe = s.hardware.afe;
  if (!prov || afe.model != "bq76952" || !(afe.shunt_ohm > 0.0)) return;
  const double shunt_mOhm = afe.shunt_ohm * 1e3;
  const ProtectionConfig& ocd = s.bms.protection(bms::FaultId::OverCurrentDischarge);
  const ProtectionConfig& occ = s.bms.protection(bms::FaultId::OverCurrentCharge);
  struct Row {
    const char* key;
    double mV;
    const ProtectionConfig& bms;
    const char* bmsKey;
    double load_A;
  };
  const Row rows[] = {
      {"ocd1_mV", afe.bq.ocd1_mV, ocd, "overcurrent_discharge", loadPeakDischarge_A(s)},
      {"scd_mV", afe.bq.scd_mV, ocd, "overcurrent_discharge", loadPeakDischarge_A(s)},
      {"occ_mV", afe.bq.occ_mV, occ, "overcurrent_charge", loadPeakCharge_A(s)},
  };
  for (const Row& r : rows) {
    const double a = r.mV / shunt_mOhm;
    const bool belowBms = r.bms.enabled && a < r.bms.threshold;
    const bool belowLoad = a < r.load_A;
    if (!belowBms && !belowLoad) continue;
    std::string why;
    if (belowBms) why = "below bms.protections." + std::string(r.bmsKey) + ".threshold_A " + amps(r.bms.threshold);
    if (belowLoad) why += std::string(belowBms ? " and " : "below ") + "the load's peak " + amps(r.load_A);
    prov->warn("hardware.afe.protection." + std::string(r.key) + " = " + fmt("%g", r.mV) +
               (stated(root, r.key) ? "" : " (the part's default)") + ": " + amps(a) + " on the " +
               fmt("%g", shunt_mOhm) + " mOhm shunt, " + why +
               ": the BQ76952 trips the pack first, on its FAULT line; state the part's threshold for this shunt");
  }
}

}  // namespace packsim
