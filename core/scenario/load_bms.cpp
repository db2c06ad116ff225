#include <algorithm>
#include <bms/bms_faults.hpp>
#include <bms/bms_limits.hpp>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/scenario/bms_setting_table.hpp"
#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/value_ranges.hpp"

namespace packsim {

namespace {

// `opens: [relay, discharge_fet, charge_fet]` -> bms::ActuatorBits.
int readOpens(YamlMap& m, int fallback) {
  if (!m.has("opens")) return fallback;
  const YAML::Node n = m.node("opens");
  const std::vector<std::string> allowed = {"relay", "discharge_fet", "charge_fet"};
  if (!n.IsSequence()) throw m.errorAt("opens", "expected a list like [relay, discharge_fet, charge_fet]");
  int bits = 0;
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string v = n[i].IsScalar() ? n[i].Scalar() : "";
    const auto it = std::find(allowed.begin(), allowed.end(), v);
    if (it == allowed.end()) {
      const std::string near = closestMatch(v, allowed);
      throw m.errorAt(n[i], m.path() + ".opens[" + std::to_string(i) + "]",
                      "'" + v + "' is not one of: relay, discharge_fet, charge_fet" +
                          (near.empty() ? "" : " (did you mean '" + near + "'?)"));
    }
    bits |= 1 << (it - allowed.begin());
  }
  return bits;
}

// `action: isolate | monitor | monitor_while_driving` (bms::FaultAction).
bms::FaultAction readAction(YamlMap& m, bms::FaultAction fallback) {
  const std::vector<std::string>& names = faultActionNames();
  const std::string v = m.choice("action", names[static_cast<size_t>(fallback)], names);
  return static_cast<bms::FaultAction>(std::find(names.begin(), names.end(), v) - names.begin());
}

ProtectionConfig readProtection(YamlMap& parent, const std::string& key, const char* unit, ProtectionConfig d,
                                Range range) {
  auto m = parent.optionalMap(key);
  if (!m) return d;
  const std::string u = unit;
  d.enabled = m->boolean("enabled", d.enabled);
  d.threshold = m->number("threshold_" + u, d.threshold, range);
  // A hysteresis wider than the threshold's whole range would never release.
  d.hysteresis = m->number("hysteresis_" + u, d.hysteresis, Range::nonNegative(range.hi - range.lo));
  d.delay_s = m->number("delay_ms", d.delay_s * 1e3, Range::closed(0.0, 600000.0)) * 1e-3;
  d.opens = readOpens(*m, d.opens);
  d.action = readAction(*m, d.action);
  m->finish();
  return d;
}

// A rule on a condition rather than a value: only enabled, delay and actuators.
ProtectionConfig readFlagRule(YamlMap& parent, const std::string& key, ProtectionConfig d) {
  auto m = parent.optionalMap(key);
  if (!m) return d;
  d.enabled = m->boolean("enabled", d.enabled);
  d.delay_s = m->number("delay_ms", d.delay_s * 1e3, Range::closed(0.0, 600000.0)) * 1e-3;
  d.opens = readOpens(*m, d.opens);
  d.action = readAction(*m, d.action);
  m->finish();
  return d;
}

}  // namespace

BmsSettings readBms(std::optional<YamlMap> m) {
  BmsSettings b;
  if (!m) {
    for (const char* section : {"", "precharge", "soc", "soc.ekf", "balancing"}) readSettings(nullptr, section, b.image);
    return b;
  }
  b.tick_s = static_cast<double>(m->integer("tick_ms", 10, 1, 10000)) * 1e-3;
  if (auto r = m->optionalMap("readout")) {
    // Whole ticks: the read-out task shares the control task's clock.
    const long tick_ms = std::lround(b.tick_s * 1e3);
    auto period = [&](const char* key, long lo) {
      const long v = r->integer(key, tick_ms, lo, 3600000);
      if (v % tick_ms != 0)
        throw r->errorAt(key, std::string(key) + " = " + std::to_string(v) + " is not a multiple of bms.tick_ms (" +
                                  std::to_string(tick_ms) + ")");
      return static_cast<double>(v) * 1e-3;
    };
    b.readout.period_s = period("period_ms", tick_ms);
    if (r->has("alert_period_ms")) {
      b.readout.alert_period_s = period("alert_period_ms", tick_ms);
      if (b.readout.alert_period_s >= b.readout.period_s)
        throw r->errorAt("alert_period_ms", "must be shorter than period_ms (" +
                                                std::to_string(std::lround(b.readout.period_s * 1e3)) +
                                                " ms): the alert poll runs between read-outs");
    }
    r->finish();
  }
  m->has("firmware");  // read with the scenario's folder: readFirmware (load_firmware.cpp)
  if (auto p = m->optionalMap("protections")) {
    for (const ProtectionSpec& spec : protectionSpecs()) {
      ProtectionConfig& pc = b.protection(spec.id);
      const std::string key = bms::faultName(spec.id);
      pc = spec.use == ThresholdUse::None
               ? readFlagRule(*p, key, pc)
               : readProtection(*p, key, spec.unit, pc, Range{spec.min, spec.max, spec.minOpen, false});
    }
    if (!(b.protection(bms::FaultId::CellUnderVoltage).threshold < b.protection(bms::FaultId::CellOverVoltage).threshold))
      throw p->error("cell_undervoltage.threshold_V must be below cell_overvoltage.threshold_V");
    p->finish();
  }
  readSettings(&*m, "", b.image);  // comm_loss_count, weld detection, balance_time_s, charge_full_cell_V
  {
    std::optional<YamlMap> p = m->optionalMap("precharge");
    readSettings(p ? &*p : nullptr, "precharge", b.image);
    if (p) p->finish();
  }
  {
    std::optional<YamlMap> soc = m->optionalMap("soc");
    readSettings(soc ? &*soc : nullptr, "soc", b.image);
    b.soc_estimation = readSocEstimation(soc ? &*soc : nullptr, b.image);
    if (soc) soc->finish();
  }
  b.run_request = m->boolean("run_request", b.run_request);
  b.charger_present = m->boolean("charger_present", b.charger_present);
  {
    std::optional<YamlMap> bal = m->optionalMap("balancing");
    readBalanceSettings(bal ? &*bal : nullptr, b);
    if (bal) bal->finish();
  }
  b.charge_current_A = m->number("charge_current_A", b.charge_current_A, Range::nonNegative(1000.0));  // the charger's range
  m->finish();
  return b;
}

}  // namespace packsim
