// Reads the state-estimation keys of `bms.soc` strictly (docs/state-estimation.md).
#include "core/scenario/bms_setting_table.hpp"
#include "core/scenario/scenario_sections.hpp"

namespace packsim {

namespace {

// A list that must rise strictly (an OCV table, display thresholds).
void checkRising(YamlMap& m, const std::string& key, const std::vector<double>& v) {
  for (size_t i = 1; i < v.size(); ++i)
    if (!(v[i] > v[i - 1]))
      throw m.errorAt(key, "values must rise strictly; element " + std::to_string(i + 1) + " (" +
                               std::to_string(v[i]) + ") is not above element " + std::to_string(i) + " (" +
                               std::to_string(v[i - 1]) + ")");
}

}  // namespace

SocEstimationSettings readSocEstimation(YamlMap* soc, bms::Config& image) {
  SocEstimationSettings e;
  if (soc == nullptr) {
    readSettings(nullptr, "soc.ekf", image);
    return e;
  }
  YamlMap& m = *soc;
  if (m.has("cell_capacity_Ah")) e.cell_capacity_Ah = m.number("cell_capacity_Ah", Range::closed(0.001, 10000.0));
  if (m.has("ocv_V")) {
    e.ocv_V = m.numbers("ocv_V", Range::closed(0.5, 5.0), 2);
    if (e.ocv_V.size() > 16) throw m.errorAt("ocv_V", "at most 16 points (the firmware's table), got " + std::to_string(e.ocv_V.size()));
    checkRising(m, "ocv_V", e.ocv_V);
  }
  if (m.has("cell_r0_ohm")) {
    const size_t points = e.ocv_V.empty() ? 11 : e.ocv_V.size();
    e.cell_r0_ohm = m.node("cell_r0_ohm").IsSequence() ? m.numbers("cell_r0_ohm", Range::closed(0.0, 10.0))
                                                        : std::vector<double>{m.number("cell_r0_ohm", Range::closed(0.0, 10.0))};
    if (e.cell_r0_ohm.size() != 1 && e.cell_r0_ohm.size() != points)
      throw m.errorAt("cell_r0_ohm", "give one value or one per OCV table point (" + std::to_string(points) + "), got " +
                                         std::to_string(e.cell_r0_ohm.size()));
  }
  if (m.has("cell_r1_ohm")) e.cell_r1_ohm = m.number("cell_r1_ohm", Range::closed(0.0, 10.0));
  if (m.has("tau1_s")) e.tau1_s = m.number("tau1_s", Range::closed(0.01, 100000.0));
  if (m.has("r0_arrhenius_K")) e.r0_arrhenius_K = m.number("r0_arrhenius_K", Range::closed(0.0, 20000.0));
  e.r0_ref_temp_C = m.number("r0_ref_temp_C", e.r0_ref_temp_C, Range::closed(-40.0, 85.0));
  std::optional<YamlMap> k = m.optionalMap("ekf");
  readSettings(k ? &*k : nullptr, "soc.ekf", image);  // the EKF's noise settings
  if (k) {
    if (k->has("initial_soc")) e.initial_soc = k->number("initial_soc", Range::closed(0.0, 1.0));
    k->finish();
  }
  if (m.has("display_bars_V")) {
    e.display_bars_V = m.numbers("display_bars_V", Range::closed(0.5, 5.0), 7);
    if (e.display_bars_V.size() != 7)
      throw m.errorAt("display_bars_V", "expected 7 thresholds (8 bars), got " + std::to_string(e.display_bars_V.size()));
    checkRising(m, "display_bars_V", e.display_bars_V);
  }
  return e;
}

namespace {

// `key: 0.03` (the reported estimator) or `key: {coulomb: 0.05, ekf: 0.03}`.
std::vector<SocErrorBound> readBounds(YamlMap& m, const std::string& key) {
  std::vector<SocErrorBound> out;
  if (!m.has(key)) return out;
  const Range r = Range::closed(0.0, 1.0);
  if (!m.node(key).IsMap()) {
    out.push_back({"", m.number(key, r)});
    return out;
  }
  YamlMap b = m.map(key);
  for (const char* name : {"coulomb", "ekf"})
    if (b.has(name)) out.push_back({name, b.number(name, r)});
  b.finish();
  if (out.empty()) throw b.error("give a bound for coulomb and/or ekf, e.g. {coulomb: 0.05, ekf: 0.03}");
  return out;
}

}  // namespace

void readSocExpectations(YamlMap& m, Expectations& e) {
  e.soc_error_max_below = readBounds(m, "soc_error_max_below");
  e.soc_error_rms_below = readBounds(m, "soc_error_rms_below");
  e.soc_error_end_below = readBounds(m, "soc_error_end_below");
  if (m.has("capacity_error_below")) e.capacity_error_below = m.number("capacity_error_below", Range::closed(0.0, 1.0));
}

}  // namespace packsim
