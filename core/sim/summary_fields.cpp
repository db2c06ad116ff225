#include "core/sim/summary_fields.hpp"

#include <algorithm>

namespace packsim {

namespace {

using S = Summary;
bool vehicle(const S& m) { return m.vehicle.present; }
bool balancing(const S& m) { return m.balance.present; }
bool charger(const S& m) { return m.charge.present; }

}  // namespace

const std::vector<SummaryField>& summaryFields() {
  // clang-format off
  static const std::vector<SummaryField> rows = {
      {"duration_s",              [](const S& m) { return m.duration_s; }, nullptr, 1},
      {"charge_delivered_Ah",     [](const S& m) { return m.charge_delivered_Ah; }, nullptr, 6},
      {"energy_delivered_Wh",     [](const S& m) { return m.energy_delivered_Wh; }, nullptr, 5},
      {"energy_in_Wh",            [](const S& m) { return m.energy_in_Wh; }},
      {"heat_Wh",                 [](const S& m) { return m.heat_Wh; }, nullptr, 7},
      {"min_cell_V",              [](const S& m) { return m.min_cell_V; }, nullptr, 8},
      {"min_cell",                [](const S& m) -> long long { return m.min_cell; }, nullptr, 9},
      {"min_cell_time_s",         [](const S& m) { return m.min_cell_time_s; }, nullptr, 10},
      {"max_temp_C",              [](const S& m) { return m.max_temp_C; }, nullptr, 11},
      {"hottest_cell",            [](const S& m) -> long long { return m.hottest_cell; }, nullptr, 12},
      {"hottest_time_s",          [](const S& m) { return m.hottest_time_s; }, nullptr, 13},
      {"tripped",                 [](const S& m) -> long long { return m.tripped ? 1 : 0; }, nullptr, 2},
      {"trip_time_s",             [](const S& m) { return m.trip_time_s; }, nullptr, 3},
      {"trip_reason",             [](const S& m) { return m.trip_reason; }, nullptr, 4},
      {"final_soc_min",           [](const S& m) { return m.final_soc_min; }, nullptr, 20},
      {"final_soc_max",           [](const S& m) { return m.final_soc_max; }, nullptr, 21},
      {"limit_reached",           [](const S& m) -> long long { return m.limit_reached ? 1 : 0; }, nullptr, 17},
      {"limit_time_s",            [](const S& m) { return m.limit_time_s; }, nullptr, 19},
      {"limit_cell",              [](const S& m) -> long long { return m.limit_cell; }, nullptr, 18},
      {"limit_by_bms_trip",       [](const S& m) -> long long { return m.limit_by_bms_trip ? 1 : 0; }},
      {"energy_start_Wh",         [](const S& m) { return m.energy_start_Wh; }, nullptr, 14},
      {"energy_left_Wh",          [](const S& m) { return m.energy_left_Wh; }, nullptr, 15},
      {"energy_stranded_Wh",      [](const S& m) { return m.energy_stranded_Wh; }, nullptr, 16},
      {"soc_estimator",           [](const S& m) { return m.soc_estimator; }},
      {"soc_error_coulomb_max",   [](const S& m) { return m.soc_error_coulomb.max; }},
      {"soc_error_coulomb_rms",   [](const S& m) { return m.soc_error_coulomb.rms; }},
      {"soc_error_coulomb_end",   [](const S& m) { return m.soc_error_coulomb.end; }},
      {"soc_error_ekf_max",       [](const S& m) { return m.soc_error_ekf.max; }},
      {"soc_error_ekf_rms",       [](const S& m) { return m.soc_error_ekf.rms; }},
      {"soc_error_ekf_end",       [](const S& m) { return m.soc_error_ekf.end; }},
      {"soc_error_ekf_group_max", [](const S& m) { return m.soc_error_ekf_group_max; }},
      {"soc_error_ekf_group",     [](const S& m) -> long long { return m.soc_error_ekf_group; }},
      {"capacity_estimate_Ah",    [](const S& m) { return m.capacity_estimate_Ah; }},
      {"capacity_true_Ah",        [](const S& m) { return m.capacity_true_Ah; }},
      {"display_bars_hidden_max", [](const S& m) -> long long { return m.display_bars_hidden_max; }},
      {"display_bars_extra_max",  [](const S& m) -> long long { return m.display_bars_extra_max; }},
      {"limit_unseen_longest_s",  [](const S& m) { return m.limit_unseen_longest_s; }},
      {"limit_unseen_longest",    [](const S& m) { return m.limit_unseen_longest; }},
      {"relay_closed",            [](const S& m) -> long long { return m.relay_closed ? 1 : 0; }},
      {"unmonitored_groups",      [](const S& m) -> long long { return m.unmonitored_groups; }},
      // Passive balancing (hardware.balancing): a resistor sweep's summary.csv shows what each bled and when it was done.
      {"balance_bled_Ah",         [](const S& m) { return m.balance.bled_Ah; }, balancing},
      {"balance_heat_Wh",         [](const S& m) { return m.balance.heat_Wh; }, balancing},
      {"balance_started_s",       [](const S& m) { return m.balance.started_s; }, balancing},
      {"balance_balanced_s",      [](const S& m) { return m.balance.balanced_s; }, balancing},
      {"balance_spread_start_Ah", [](const S& m) { return m.balance.spread_start_Ah; }, balancing},
      {"balance_spread_end_Ah",   [](const S& m) { return m.balance.spread_end_Ah; }, balancing},
      {"balance_imbalance_start_Ah", [](const S& m) { return m.balance.imbalance_start_Ah; }, balancing},
      {"balance_imbalance_end_Ah",   [](const S& m) { return m.balance.imbalance_end_Ah; }, balancing},
      // A charger (load.charger): when the BMS enabled it and switched it off for good, with the truth then.
      {"charge_on_s",             [](const S& m) { return m.charge.on_s; }, charger},
      {"charge_off_s",            [](const S& m) { return m.charge.off_s; }, charger},
      {"charge_off_cell",         [](const S& m) -> long long { return m.charge.off_cell; }, charger},
      {"charge_off_cell_V",       [](const S& m) { return m.charge.off_cell_V; }, charger},
      {"charge_off_current_A",    [](const S& m) { return m.charge.off_current_A; }, charger},
      {"charge_off_soc_mean",     [](const S& m) { return m.charge.off_soc_mean; }, charger},
      // A vehicle on its route (docs/vehicle.md): a sweep's summary.csv shows the fastest speed that finishes.
      {"vehicle_distance_km",     [](const S& m) { return m.vehicle.distance_m / 1000.0; }, vehicle},
      {"vehicle_finished",        [](const S& m) -> long long { return m.vehicle.finished ? 1 : 0; }, vehicle},
      {"vehicle_time_s",          [](const S& m) { return m.vehicle.time_s - m.vehicle.start_s; }, vehicle},
      {"vehicle_time_lost_s",     [](const S& m) { const VehicleSummary& v = m.vehicle;
                                                   return v.finished && v.reference_time_s > 0.0 ? v.time_s - v.reference_time_s : 0.0; }, vehicle},
      {"vehicle_pack_Wh",         [](const S& m) { return m.vehicle.pack_Wh; }, vehicle},
      {"vehicle_array_Wh",        [](const S& m) { return m.vehicle.array_Wh; }, vehicle},
      {"vehicle_limit_time_s",    [](const S& m) { return m.vehicle.limited ? m.vehicle.limit_time_s : -1.0; }, vehicle},
  };
  // clang-format on
  return rows;
}

std::vector<std::string> summaryCsvLeadingColumns() {
  std::vector<const SummaryField*> ranked;
  for (const SummaryField& f : summaryFields())
    if (f.csv_rank > 0) ranked.push_back(&f);
  std::sort(ranked.begin(), ranked.end(), [](const SummaryField* a, const SummaryField* b) { return a->csv_rank < b->csv_rank; });
  std::vector<std::string> names;
  for (const SummaryField* f : ranked) names.emplace_back(f->name);
  return names;
}

}  // namespace packsim
