#include "core/balance/balance_time.hpp"

#include <bms/bms_balance.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"

namespace packsim {

double socAtOcv(const CellParams& cell, double v) {
  double lo = 0.0, hi = 1.0;
  if (v <= ecm::ocv(cell, lo)) return lo;
  if (v >= ecm::ocv(cell, hi)) return hi;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ecm::ocv(cell, mid) < v ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

namespace {

[[noreturn]] void bad(const std::string& what) { throw std::invalid_argument(what); }

// Charge (Ah) in each series group.
std::vector<double> groupCharge_Ah(const Plant& plant, const double* x) {
  const Pack& p = plant.pack();
  std::vector<double> q(static_cast<size_t>(p.series), 0.0);
  for (int c = 0; c < p.cellCount(); ++c)
    q[static_cast<size_t>(c / p.parallel)] += plant.cellStates(x, c)[CellLayout::soc] * p.cells[static_cast<size_t>(c)].capacity_Ah;
  return q;
}

// Rest voltage (mean OCV) of each series group.
std::vector<double> groupOcv_V(const Plant& plant, const double* x) {
  const Pack& p = plant.pack();
  std::vector<double> v(static_cast<size_t>(p.series), 0.0);
  for (int c = 0; c < p.cellCount(); ++c)
    v[static_cast<size_t>(c / p.parallel)] +=
        ecm::ocv(p.cells[static_cast<size_t>(c)], plant.cellStates(x, c)[CellLayout::soc]) / p.parallel;
  return v;
}

double spread(const std::vector<double>& q) {
  const auto [lo, hi] = std::minmax_element(q.begin(), q.end());
  return *hi - *lo;
}

void checkOptions(const Scenario& s, const BalanceTimeOptions& o) {
  for (double r : o.resistors_ohm)
    if (!(r >= 1.0 && r <= 10000.0)) bad("--resistor: each value must be within 1 .. 10000 ohm (got " + std::to_string(r) + ")");
  if (o.delta_Ah && !(*o.delta_Ah > 0.0 && *o.delta_Ah <= 1000.0)) bad("--delta-Ah: must be within (0, 1000] Ah");
  if (o.cell_V && !(*o.cell_V >= 0.5 && *o.cell_V <= 5.0)) bad("--cell-V: must be within 0.5 .. 5 V");
  if (o.high_cells < 1 || o.high_cells > s.pack.series)
    bad("--high-cells: must be within 1 .. " + std::to_string(s.pack.series) + " (the pack's series cells)");
  if (!(o.target_mV >= 1.0 && o.target_mV <= 500.0)) bad("--target-mV: must be within 1 .. 500 mV");
  if (!(o.max_hours > 0.0 && o.max_hours <= 1000.0)) bad("--max-hours: must be within (0, 1000] h");
  if (o.resistors_ohm.empty() && !s.hardware.balancing.present)
    bad("the scenario has no hardware.balancing: give --resistor");
}

// The scenario made into the balancing experiment (everything but the resistor).
Scenario experiment(const Scenario& base, const BalanceTimeOptions& o, double cellV) {
  Scenario s = base;
  s.faults.clear();
  s.expect = Expectations{};
  s.charger = ChargerConfig{};
  s.load = LoadProfile::constant(0.0);
  s.bms.run_request = true;
  s.bms.charger_present = false;
  s.bms.tick_s = std::max(s.bms.tick_s, 1.0);  // decisions at 1 Hz are ample (DOMAIN.md D)
  s.output.interval_s = std::max(60.0, s.bms.tick_s);
  s.run.duration_s = o.max_hours * 3600.0;
  s.run.stop_after_trip_s = 0.0;
  s.hardware.balancing.present = true;
  BalanceSettings& b = s.bms.balancing;
  b.enabled = true;
  b.when = "always";
  // Start above the target, stop at half of it: measurement noise cannot end the
  // run early, and the truth decides when the target is reached.
  b.start_delta_V = o.target_mV * 1e-3;
  b.stop_delta_V = 0.5 * o.target_mV * 1e-3;
  b.min_cell_V = std::min(b.min_cell_V, 0.5 * cellV);  // the experiment is about time, not the floor
  b.period_s = std::max(b.period_s, s.bms.tick_s);
  if (o.delta_Ah) {
    // Identical cells; the high ones start at cell_V, the rest delta_Ah lower.
    const PackConfig& p = s.pack;
    const double groupAh = p.cell.capacity_Ah * p.parallel;
    const double high = socAtOcv(p.cell, cellV);
    const double low = high - *o.delta_Ah / groupAh;
    if (low < 0.0) {
      std::ostringstream os;
      os << "--delta-Ah: " << *o.delta_Ah << " Ah below a cell at " << cellV << " V (SOC " << high
         << ") empties it; at most " << high * groupAh << " Ah";
      bad(os.str());
    }
    s.pack.spread = CellSpread{};
    s.pack.cell_overrides.clear();
    s.pack.initial_soc = low;
    for (int g = 0; g < o.high_cells; ++g)
      for (int k = 0; k < p.parallel; ++k) {
        CellOverride c;
        c.cell = g * p.parallel + k;
        c.initial_soc = high;
        s.pack.cell_overrides.push_back(c);
      }
  }
  return s;
}

void simulate(const Scenario& s, const BalanceTimeOptions& o, BalanceTimeRow& row) {
  const Plant plant(s);
  std::vector<double> x0(static_cast<size_t>(plant.stateSize()), 0.0);
  plant.initialState(x0.data());
  const double initialSpread = spread(groupCharge_Ah(plant, x0.data()));
  const double settle_s = std::max(60.0, 2.0 * s.bms.balancing.period_s);
  bool started = false;
  double balancedSince = -1.0, lastT = 0.0, peak = -INFINITY;
  std::string reason = "time_limit";
  auto stopWhen = [&](double t, const double* x, const PlantSignals&, const bms::Outputs& out) {
    lastT = t;
    if (plant.boardNode() >= 0) peak = std::max(peak, x[plant.tempIndex(plant.boardNode())]);
    const auto status = static_cast<bms::BalanceStatus>(out.balanceStatus);
    if (status == bms::BalanceStatus::Balancing) {
      started = true;
      balancedSince = -1.0;
    } else if (balancedSince < 0.0) {
      balancedSince = t;
    }
    if (started && spread(groupCharge_Ah(plant, x)) <= 1e-3 * initialSpread) {
      reason = "charge_removed";
      return true;
    }
    if (started && spread(groupOcv_V(plant, x)) < o.target_mV * 1e-3) {
      reason = "within_target";
      return true;
    }
    if (balancedSince >= 0.0 && t - balancedSince >= settle_s) {  // the BMS has stopped for good
      reason = started ? "bms_stopped" : "not_started";
      return true;
    }
    return false;
  };
  const RunResult r = runScenario(s, stopWhen);
  row.simulated = true;
  row.end_reason = reason;
  row.simulated_h = (reason == "bms_stopped" ? balancedSince : lastT) / 3600.0;
  if (reason == "not_started") row.simulated_h = 0.0;
  row.peak_board_C = plant.boardNode() >= 0 ? peak : NAN;
  row.energy_Wh = r.quad[kQuadBalanceHeat_J] / 3600.0;
  row.charge_removed_Ah = r.quad[kQuadBalanceCharge_As] / 3600.0;
  // Final spread from the recorded SOC of the last sample.
  const Recording& rec = r.rec;
  const size_t n = rec.samples();
  if (n > 0) {
    std::vector<double> q(static_cast<size_t>(plant.pack().series), 0.0);
    for (int c = 0; c < rec.cells; ++c)
      q[static_cast<size_t>(c / plant.pack().parallel)] +=
          rec.cell_soc[(n - 1) * static_cast<size_t>(rec.cells) + static_cast<size_t>(c)] *
          plant.pack().cells[static_cast<size_t>(c)].capacity_Ah;
    row.final_spread_Ah = spread(q);
  }
}

}  // namespace

BalanceTimeResult balanceTime(const Scenario& base, const BalanceTimeOptions& o) {
  checkOptions(base, o);
  BalanceTimeResult res;
  res.scenario = base.name;
  res.high_cells = o.delta_Ah ? o.high_cells : 1;
  res.target_mV = o.target_mV;

  // The imbalance and the cell voltage of the analytic estimate.
  const Plant basePlant(base);
  std::vector<double> x0(static_cast<size_t>(basePlant.stateSize()), 0.0);
  basePlant.initialState(x0.data());
  const std::vector<double> q = groupCharge_Ah(basePlant, x0.data());
  const int highest = static_cast<int>(std::max_element(q.begin(), q.end()) - q.begin());
  const double highestSoc = basePlant.cellStates(x0.data(), highest * basePlant.pack().parallel)[CellLayout::soc];
  res.delta_Ah = o.delta_Ah ? *o.delta_Ah : spread(q);
  res.cell_V = o.cell_V ? *o.cell_V
                        : ecm::ocv(base.pack.cell, o.delta_Ah ? base.pack.initial_soc : highestSoc);
  if (!(res.delta_Ah > 0.0)) bad("the scenario's cells hold equal charge: give --delta-Ah");

  std::vector<double> resistors = o.resistors_ohm;
  if (resistors.empty()) resistors.push_back(base.hardware.balancing.resistor_ohm);
  const Scenario experimentBase = o.simulate ? experiment(base, o, res.cell_V) : base;
  for (double r : resistors) {
    BalanceTimeRow row;
    row.resistor_ohm = r;
    row.branch_ohm = r + base.hardware.balancing.rds_on_ohm;
    row.current_A = res.cell_V / row.branch_ohm;
    row.power_W = res.cell_V * row.current_A;
    row.board_power_W = row.power_W * res.high_cells;
    row.analytic_h = res.delta_Ah / row.current_A;
    row.peak_board_C = NAN;
    if (o.simulate) {
      Scenario s = experimentBase;
      s.hardware.balancing.resistor_ohm = r;
      simulate(s, o, row);
    }
    res.rows.push_back(row);
  }
  return res;
}

}  // namespace packsim
