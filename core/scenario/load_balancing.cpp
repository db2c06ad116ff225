// Balancing and charging sections: hardware.balancing (passive resistors),
// hardware.active_balancer (converters to a supercap bus), bms.balancing (policy) and
// the charger load kind (load: {charger: {...}}).
#include <bms/bms_limits.hpp>

#include "core/scenario/bms_setting_table.hpp"
#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/value_ranges.hpp"

namespace packsim {

PassiveBalancerConfig readPassiveBalancer(YamlMap m) {
  PassiveBalancerConfig b;
  b.present = m.boolean("present", true);
  // No resistor value is "typical": it sets the bleed current and heat, so present
  // balancing hardware states it (docs/scenario.md).
  b.resistor_ohm = b.present ? m.number("resistor_ohm", Range::closed(1.0, 10000.0))
                             : m.number("resistor_ohm", b.resistor_ohm, Range::closed(1.0, 10000.0));
  b.rds_on_ohm = m.number("rds_on_ohm", b.rds_on_ohm, Range::closed(0.0, 100.0));
  b.board_node = m.string("board_node", "");
  b.board_thermistors = static_cast<int>(m.integer("board_thermistors", 0, 0, 8));
  if (b.board_thermistors > 0 && b.board_node.empty())
    throw m.errorAt("board_thermistors", "board thermistors need a board_node (a thermal.nodes entry) to sit on");
  b.cells_per_board = static_cast<int>(m.integer("cells_per_board", 0, 0, bms::kMaxCells));
  b.resistor_power_rating_W = m.number("resistor_power_rating_W", 0.0, Range::closed(0.0, 100.0));
  m.finish();
  return b;
}

ActiveBalancerConfig readActiveBalancer(YamlMap m) {
  ActiveBalancerConfig a;
  a.present = m.boolean("present", true);
  a.converter_current_A = m.number("converter_current_A", a.converter_current_A, Range::closed(0.01, 100.0));
  if (m.has("losses")) {
    if (m.has("efficiency")) throw m.errorAt("losses", "give either efficiency or losses, not both");
    YamlMap l = m.map("losses");
    a.loss_model = true;
    a.loss_fixed_W = l.number("fixed_W", 0.0, Range::closed(0.0, 100.0));
    a.loss_series_ohm = l.number("series_ohm", 0.0, Range::closed(0.0, 100.0));
    l.finish();
  } else if (m.has("efficiency") && m.node("efficiency").IsMap()) {
    YamlMap e = m.map("efficiency");
    a.efficiency_at_A = e.numbers("current_A", Range::nonNegative(100.0), 2);  // the converter_current_A range
    a.efficiency = e.numbers("efficiency", Range{0.0, 1.0, true, false}, 2);
    if (a.efficiency.size() != a.efficiency_at_A.size())
      throw e.errorAt("efficiency", "needs as many values as current_A");
    for (size_t i = 1; i < a.efficiency_at_A.size(); ++i)
      if (!(a.efficiency_at_A[i] > a.efficiency_at_A[i - 1])) throw e.errorAt("current_A", "values must increase strictly");
    e.finish();
  } else {
    a.efficiency = {m.number("efficiency", a.efficiency.front(), Range{0.0, 1.0, true, false})};
    a.efficiency_at_A = {0.0};
  }
  a.bus_capacitance_F = m.number("bus_capacitance_F", a.bus_capacitance_F, Range::closed(0.001, 100000.0));
  a.bus_rated_V = m.number("bus_rated_V", a.bus_rated_V, Range::closed(1.0, 100.0));
  a.bus_initial_V = m.number("bus_initial_V", a.bus_initial_V, Range::closed(0.0, a.bus_rated_V));
  a.precharge_ohm = m.number("precharge_ohm", a.precharge_ohm, Range::closed(0.01, 10000.0));
  a.precharge_below_V = m.number("precharge_below_V", a.precharge_below_V, Range::closed(0.0, a.bus_rated_V));
  a.bus_low_V = m.number("bus_low_V", a.bus_low_V, Range::closed(0.0, a.bus_rated_V));
  a.bus_high_V = m.number("bus_high_V", a.bus_high_V, Range::closed(0.0, a.bus_rated_V));
  a.module_min_V = m.number("module_min_V", a.module_min_V, Range::closed(0.5, 5.0));
  a.module_max_V = m.number("module_max_V", a.module_max_V, Range::closed(0.5, 5.0));
  a.deadband_V = m.number("deadband_mV", a.deadband_V * 1e3, Range::closed(0.0, 1000.0)) * 1e-3;
  if (!(a.precharge_below_V <= a.bus_low_V && a.bus_low_V < a.bus_high_V))
    throw m.error("needs precharge_below_V <= bus_low_V < bus_high_V <= bus_rated_V");
  if (!(a.module_min_V < a.module_max_V)) throw m.errorAt("module_min_V", "must be below module_max_V");
  m.finish();
  return a;
}

void readBalanceSettings(YamlMap* m, BmsSettings& b) {
  const std::map<std::string, double> v = readSettings(m, "balancing", b.image);  // the firmware's policy
  if (m == nullptr) return;
  if (!(v.at("stop_delta_mV") <= v.at("start_delta_mV"))) throw m->errorAt("stop_delta_mV", "must not exceed start_delta_mV");
  if (!(v.at("board_resume_C") <= v.at("board_max_C"))) throw m->errorAt("board_resume_C", "must not exceed board_max_C");
  b.balancing.measure_paused = m->boolean("measure_paused", b.balancing.measure_paused);
}

ChargerConfig readCharger(YamlMap m) {
  ChargerConfig c;
  c.present = true;
  c.current_A = m.number("current_A", Range::closed(0.001, 1000.0));
  c.voltage_V = m.number("voltage_V", Range::closed(0.5, 2000.0));
  c.end_current_A = m.number("end_current_A", 0.05 * c.current_A, Range::closed(0.0, c.current_A));
  if (!(c.end_current_A < c.current_A)) throw m.errorAt("end_current_A", "must be below current_A");
  c.stop_run_when_done = m.boolean("stop_run_when_done", true);
  m.finish();
  return c;
}

}  // namespace packsim
