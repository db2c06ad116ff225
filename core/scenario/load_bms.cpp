#include <bms/bms_limits.hpp>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "core/scenario/scenario_sections.hpp"

namespace packsim {

static ProtectionConfig readProtection(YamlMap& parent, const std::string& key, const char* unit, ProtectionConfig d,
                                Range range) {
  auto m = parent.optionalMap(key);
  if (!m) return d;
  const std::string u = unit;
  d.enabled = m->boolean("enabled", d.enabled);
  d.threshold = m->number("threshold_" + u, d.threshold, range);
  d.hysteresis = m->number("hysteresis_" + u, d.hysteresis, Range::nonNegative());
  d.delay_s = m->number("delay_ms", d.delay_s * 1e3, Range::closed(0.0, 600000.0)) * 1e-3;
  m->finish();
  return d;
}

BmsSettings readBms(std::optional<YamlMap> m) {
  BmsSettings b;
  if (!m) return b;
  b.tick_s = static_cast<double>(m->integer("tick_ms", 10, 1, 10000)) * 1e-3;
  if (auto p = m->optionalMap("protections")) {
    b.cell_overvoltage = readProtection(*p, "cell_overvoltage", "V", b.cell_overvoltage, Range::closed(1.0, 5.0));
    b.cell_undervoltage = readProtection(*p, "cell_undervoltage", "V", b.cell_undervoltage, Range::closed(0.5, 4.5));
    b.overcurrent_discharge =
        readProtection(*p, "overcurrent_discharge", "A", b.overcurrent_discharge, Range::positive());
    b.overcurrent_charge = readProtection(*p, "overcurrent_charge", "A", b.overcurrent_charge, Range::positive());
    b.overtemperature = readProtection(*p, "overtemperature", "C", b.overtemperature, Range::closed(0.0, 150.0));
    if (!(b.cell_undervoltage.threshold < b.cell_overvoltage.threshold))
      throw p->error("cell_undervoltage.threshold_V must be below cell_overvoltage.threshold_V");
    p->finish();
  }
  m->finish();
  return b;
}

}  // namespace packsim
