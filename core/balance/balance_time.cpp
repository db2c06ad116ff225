#include "core/balance/balance_time.hpp"

#include <bms/bms_balance.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "core/scenario/bms_setting_table.hpp"
#include "core/sim/balance_report.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "core/text_fmt.hpp"

namespace packsim {

namespace {

[[noreturn]] void bad(const std::string& what) { throw std::invalid_argument(what); }

// Rest voltage (mean OCV) of each series group in state x.
std::vector<double> groupOcv_V(const Plant& plant, const double* x) { return groupOcv_V(plant.pack(), cellSoc(plant, x)); }

void checkOptions(const Scenario& s, const BalanceTimeOptions& o) {
  for (double r : o.resistors_ohm)
    if (!(r >= 1.0 && r <= 10000.0)) bad("--resistor: each value must be within 1 .. 10000 ohm (got " + std::to_string(r) + ")");
  if (o.delta_Ah && !(*o.delta_Ah > 0.0 && *o.delta_Ah <= 1000.0)) bad("--delta-Ah: must be within (0, 1000] Ah");
  if (o.cell_V && !(*o.cell_V >= 0.5 && *o.cell_V <= 5.0)) bad("--cell-V: must be within 0.5 .. 5 V");
  // A cell rests only within its OCV curve: 4.6 V on a 4.2 V cell was taken, its bleed
  // current at 4.6 V and its SOC held at 1 for the rest.
  if (o.cell_V) {
    const double lo = ecm::ocv(s.pack.cell, 0.0), hi = ecm::ocv(s.pack.cell, 1.0);
    if (*o.cell_V < lo || *o.cell_V > hi)
      bad(fmt("--cell-V: %.4g V is outside the cell's rest voltages, %.4g .. %.4g V (its OCV at SOC 0 and 1)", *o.cell_V,
              lo, hi));
  }
  if (o.high_cells < 1 || o.high_cells > s.pack.series)
    bad("--high-cells: must be within 1 .. " + std::to_string(s.pack.series) + " (the pack's series cells)");
  if (o.target_mV && !(*o.target_mV >= 0.1 && *o.target_mV <= 500.0)) bad("--target-mV: must be within 0.1 .. 500 mV");
  if (!(o.max_hours > 0.0 && o.max_hours <= 1000.0)) bad("--max-hours: must be within (0, 1000] h");
  if (o.resistors_ohm.empty() && !s.hardware.balancing.present)
    bad("the scenario has no hardware.balancing: give --resistor");
  if (o.when && settingChoiceIndex("balancing.when", *o.when) < 0) {
    std::string names;
    for (const std::string& n : settingRow("balancing.when").choices) names += (names.empty() ? "" : ", ") + n;
    bad("--when: must be one of " + names + " (got '" + *o.when + "')");
  }
  if (o.during_charge && !s.charger.present)
    bad("--during-charge: the scenario has no charger (load: {charger: {...}})");
}

// The scenario made into the balancing experiment (everything but the resistor). The
// firmware's balancing settings stay as configured.
Scenario experiment(const Scenario& base, const BalanceTimeOptions& o, double cellV) {
  Scenario s = base;
  s.faults.clear();
  s.expect = Expectations{};
  if (o.during_charge) {  // the scenario's charger and load stay; the charge's end ends the run
    s.charger.stop_run_when_done = true;
    s.bms.charger_present = true;
    s.bms.run_request = false;  // the BMS in its charge state
  } else {
    s.charger = ChargerConfig{};
    s.load = LoadProfile::constant(0.0);
    s.bms.charger_present = false;
    s.bms.run_request = true;
  }
  bms::BalanceConfig& policy = s.bms.image.balance;
  if (o.when) policy.when = static_cast<bms::BalanceWhen>(settingChoiceIndex("balancing.when", *o.when));
  // Decisions at 1 Hz are ample (docs/reference-systems.md D), but no slower than the
  // monitor's link supervision allows: a BQ76PL455A with a 100 ms communication timeout
  // latched its FAULT line at the first 1 s tick, and every row "tripped" at 0.00 h.
  const double commTimeout_s = s.hardware.afe.secondary.comm_timeout_s;
  s.bms.tick_s = std::max(s.bms.tick_s, commTimeout_s > 0.0 ? std::min(1.0, 0.5 * commTimeout_s) : 1.0);
  s.output.interval_s = std::max(60.0, s.bms.tick_s);
  s.run.duration_s = o.max_hours * 3600.0;
  s.run.stop_after_trip_s = 0.0;
  s.hardware.balancing.present = true;
  policy.enabled = true;
  policy.period_ms = std::max(policy.period_ms, static_cast<uint32_t>(std::lround(s.bms.tick_s * 1e3)));
  if (o.delta_Ah) {
    // Identical cells; the high ones start at cell_V, the rest delta_Ah lower.
    const PackConfig& p = s.pack;
    const double groupAh = p.cell.capacity_Ah * p.parallel;
    const double high = socAtOcv(p.cell, cellV);
    const double low = high - *o.delta_Ah / groupAh;  // >= 0: checked in balanceTime
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

// The firmware's balancing policy in the key's units, for the experiment's reasoning and text.
struct Policy {
  bms::BalanceWhen when;
  double start_delta_V, stop_delta_V, min_cell_V, board_max_C, rest_s, period_s;
  int average_readings;
};
Policy policyOf(const Scenario& s) {
  const bms::BalanceConfig& k = s.bms.image.balance;
  return {k.when,        k.startDelta_mV * 1e-3, k.stopDelta_mV * 1e-3, k.minCell_mV * 1e-3, k.boardMax_dC * 0.1,
          k.rest_ms * 1e-3, k.period_ms * 1e-3,   k.averageReadings};
}

// Why a firmware that never balanced did not start.
std::string notStartedWhy(const Scenario& s, const Plant& plant, const double* x0) {
  const Policy b = policyOf(s);
  const std::vector<double> v = groupOcv_V(plant, x0);
  if (b.when == bms::BalanceWhen::Charging) return "the scenario balances only while charging (bms.balancing.when: charging)";
  if (*std::max_element(v.begin(), v.end()) < b.min_cell_V)
    return fmt("the high cells (%.3f V) are below bms.balancing.min_cell_V (%.3f V)", *std::max_element(v.begin(), v.end()),
               b.min_cell_V);
  if (spread(v) <= b.start_delta_V)
    return fmt("the spread (%.1f mV) never exceeded bms.balancing.start_delta_mV (%.1f)", spread(v) * 1e3,
               b.start_delta_V * 1e3);
  return "the firmware never balanced";
}

// The highest cell voltage of the last recorded sample.
double highestVoltage_V(const RunResult& r) {
  const Recording& rec = r.rec;
  const size_t n = rec.samples();
  double vmax = 0.0;
  for (int c = 0; n > 0 && c < rec.cells; ++c)
    vmax = std::max(vmax, rec.cell_voltage_V[(n - 1) * static_cast<size_t>(rec.cells) + static_cast<size_t>(c)]);
  return vmax;
}

// Why a firmware that balanced stopped before the rest voltages came within the target,
// from its balancing status since it stopped (`quiet`, from `since_s`).
std::string stoppedWhy(const Scenario& s, const RunResult& r, bms::BalanceStatus quiet, double since_s) {
  const Policy b = policyOf(s);
  const double vmax = highestVoltage_V(r);
  const std::string when = fmt(" since %.2f h", since_s / 3600.0);
  if (quiet == bms::BalanceStatus::Disabled)
    return "stopped short of the target: balancing disabled by the BMS" + when + " (a fault or its state)";
  if (vmax < b.min_cell_V + b.stop_delta_V)
    return fmt("stopped short of the target: the cells still high are at %.3f V, at the bms.balancing.min_cell_V "
               "floor (%.3f V), and it never declared",
               vmax, b.min_cell_V);
  return "stopped short of the target" + when + " and never declared";
}

// A charge the BMS ended itself (core/sim/charge_summary.hpp): when, on what, and the
// imbalance it left -- "" when the charger ran to its own end or was on at the end.
std::string bmsChargeEndText(const Scenario& s, const RunResult& r, double imbalanceLeft_Ah, double end_s) {
  const ChargeSummary& c = r.summary.charge;
  if (c.off_s < 0.0) return "";
  const uint16_t full_mV = s.bms.image.chargeFullCell_mV;
  std::string text =
      fmt("the BMS ended the charge at %.2f h and kept it off: ", c.off_s / 3600.0) + chargeOffText(c, s.pack.parallel);
  if (full_mV > 0) text += fmt(", its bms.charge_full_cell_V %.3f V", full_mV * 1e-3);
  text += fmt("; %.3f Ah of imbalance left at %.2f h (truth)", imbalanceLeft_Ah, end_s / 3600.0);
  return text;
}

void simulate(const Scenario& s, double target_mV, bool duringCharge, BalanceTimeRow& row,
              std::vector<std::string>& warnings) {
  const Plant plant(s);
  std::vector<double> x0(static_cast<size_t>(plant.stateSize()), 0.0);
  plant.initialState(x0.data());
  const std::vector<double> need = groupExcess_Ah(plant.pack(), cellSoc(plant, x0.data()));
  std::vector<double> bled(need.size(), 0.0);

  const Policy b = policyOf(s);
  const double tick_s = s.bms.tick_s;
  // The firmware's decision needs a period and (with averaging) a full block of readings.
  const double settle_s = std::max(60.0, 3.0 * std::max(b.period_s, b.average_readings * tick_s));
  const double wait_start_s = (b.when == bms::BalanceWhen::Rest || b.when == bms::BalanceWhen::ChargingOrRest ? b.rest_s : 0.0) + settle_s;

  bool started = false;
  double declaredAt = -1.0, trueAt = -1.0, quietSince = -1.0, lastT = 0.0, paused_s = 0.0, pausedToTrue_s = 0.0;
  // Spells of "not allowed" after it started (its rest broken by a current reading at or
  // above rest_current_A, e.g. the sensor's noise): a pause while the condition may come
  // back, within its rest_s and a settling time.
  int restBreaks = 0;
  double notAllowed_s = 0.0;
  auto quietStatus = bms::BalanceStatus::Balancing;
  double lowestSpread_mV = INFINITY, lastOcvSpread_V = NAN, lastCharging_s = 0.0;
  std::vector<double> peak(static_cast<size_t>(plant.boardCount()), -INFINITY);
  double chargeOff_s = -1.0;  // the BMS switched the charger off then and has kept it off
  bool chargeOn = false;
  std::string reason = "time_limit";
  auto finish = [&](const char* why) {
    reason = why;
    return true;
  };
  auto stopWhen = [&](double t, const double* x, const PlantSignals& sig, const bms::Outputs& out) {
    lastT = t;
    for (int k = 0; k < plant.boardCount(); ++k)
      peak[static_cast<size_t>(k)] = std::max(peak[static_cast<size_t>(k)], x[plant.tempIndex(plant.boardNodeOf(k))]);
    // The bleed current of the interval just ended (the switches held since the last tick).
    for (size_t g = 0; g < bled.size(); ++g) bled[g] += sig.balance_current_A[g] * tick_s;
    if (sig.pack_current_A < -s.charger.end_current_A) lastCharging_s = t;
    if (out.chargerEnable) {
      chargeOn = true;
      chargeOff_s = -1.0;
    } else if (chargeOn && chargeOff_s < 0.0) {
      chargeOff_s = t;
    }
    const auto status = static_cast<bms::BalanceStatus>(out.balanceStatus);
    if (status == bms::BalanceStatus::BoardHot) paused_s += tick_s;
    if (started && status == bms::BalanceStatus::NotAllowed) {
      if (quietSince < 0.0) ++restBreaks;
      notAllowed_s += tick_s;
    }
    if (status == bms::BalanceStatus::Balancing) {
      started = true;
      declaredAt = -1.0;
      quietSince = -1.0;
      const int spread_mV = out.telemetry.maxCell_mV - out.telemetry.minCell_mV;
      lowestSpread_mV = std::min(lowestSpread_mV, static_cast<double>(spread_mV));
    } else {
      if (quietSince < 0.0) quietSince = t;
      quietStatus = status;
      if (started && status == bms::BalanceStatus::Balanced && declaredAt < 0.0) declaredAt = t;
    }
    lastOcvSpread_V = spread(groupOcv_V(plant, x));
    if (trueAt < 0.0 && lastOcvSpread_V < target_mV * 1e-3) {
      trueAt = t;
      pausedToTrue_s = paused_s;
    }
    if (declaredAt >= 0.0 && trueAt >= 0.0 && t - declaredAt >= settle_s) return finish("both_known");
    if (duringCharge) {
      // Top balancing starts late; the charge's end ends the run. The charger's own end
      // stops the run; a BMS that ends the charge itself (its first full cell) leaves the
      // charger on standby, and the run went on to --max-hours: once it has kept the
      // charger off and its balancing has stopped too, nothing changes any more.
      const bool bmsEnded = chargeOff_s >= 0.0 && t - chargeOff_s >= settle_s;
      if (bmsEnded && quietSince >= 0.0 && status != bms::BalanceStatus::BoardHot && t - quietSince >= settle_s)
        return finish("charge_ended_by_bms");
      return false;
    }
    // At rest "not allowed" is a pause: the rest condition comes back once the current
    // reading stays below rest_current_A for rest_s (the load is 0 in this experiment).
    const bool mayResume = status == bms::BalanceStatus::NotAllowed;
    if (started && quietSince >= 0.0 && status != bms::BalanceStatus::BoardHot && !mayResume &&
        t - quietSince >= settle_s && trueAt < 0.0)
      return finish("firmware_stopped");
    if (!started && t >= wait_start_s) return finish("not_started");
    // The target is reached but the firmware keeps balancing: give it half as long again.
    if (trueAt >= 0.0 && declaredAt < 0.0 && t - trueAt >= std::max(3600.0, 0.5 * trueAt))
      return finish("firmware_overran");
    return false;
  };
  const RunResult r = runScenario(s, stopWhen);
  for (const Event& e : r.events)
    if (e.kind == "config_warning" && std::find(warnings.begin(), warnings.end(), e.detail) == warnings.end())
      warnings.push_back(e.detail);

  row.simulated = true;
  if (duringCharge) {
    if (reason == "time_limit" && r.rec.samples() > 0 && r.rec.time_s.back() < s.run.duration_s)
      reason = declaredAt >= 0.0 ? "charge_done" : "charge_done_unbalanced";  // the charger finished
    row.charge_h = lastCharging_s / 3600.0;
  }
  if (r.summary.tripped) reason = "tripped";
  row.end_reason = reason;
  row.tripped = r.summary.tripped;
  row.true_h = trueAt >= 0.0 ? trueAt / 3600.0 : NAN;
  // Declared: the firmware went to Balanced after balancing and stayed there to the end.
  row.firmware_h = declaredAt >= 0.0 && reason != "tripped" ? declaredAt / 3600.0 : NAN;
  if (reason == "not_started" || (!started && !row.tripped)) {
    row.firmware_note = "never started: " + notStartedWhy(s, plant, x0.data());
  } else if (!std::isnan(row.firmware_h) && trueAt < 0.0) {
    const double vHigh = highestVoltage_V(r);
    const std::string why =
        vHigh < b.min_cell_V + b.stop_delta_V
            ? fmt(": the cells still high reached bms.balancing.min_cell_V (%.3f V at %.3f V) and none was left to bleed",
                  b.min_cell_V, vHigh)
            : fmt(" by its %.1f mV stop threshold", b.stop_delta_V * 1e3);
    row.firmware_note = fmt("declared balanced at %.2f h", row.firmware_h) + why +
                        fmt(", but the true rest voltages stayed %.1f mV apart (target %.1f mV)", lastOcvSpread_V * 1e3,
                            target_mV);
  } else if (std::isnan(row.firmware_h)) {
    if (row.tripped)
      row.firmware_note = "never declared: " + r.summary.trip_reason + " tripped at " + fmt("%.2f h", r.summary.trip_time_s / 3600.0);
    else if (reason == "charge_done_unbalanced")
      row.firmware_note = fmt("never declared: the charge ended at %.2f h ", row.charge_h) +
                          (started ? "while it was still balancing" : "before it started balancing");
    else if (reason == "firmware_stopped")
      row.firmware_note = stoppedWhy(s, r, quietStatus, quietSince);
    else if (reason == "charge_ended_by_bms")
      row.firmware_note = started ? "never declared: it stopped balancing" : "never declared: it never balanced";
    else
      row.firmware_note = fmt("never declared: still balancing at %.2f h; its readings' max-min stayed >= the %.0f mV "
                              "stop threshold (lowest seen %.0f mV)",
                              lastT / 3600.0, b.stop_delta_V * 1e3, lowestSpread_mV);
  }
  if (restBreaks > 0 && !duringCharge)
    row.firmware_note += (row.firmware_note.empty() ? "" : "; ") +
                         fmt("its rest broke %.0f times after it started, not allowed to balance %.0f %% of the time (",
                             restBreaks, 100.0 * notAllowed_s / std::max(lastT, tick_s)) +
                         "bms.balancing.when: " + settingChoice("balancing.when", s.bms.image) +
                         fmt("): each current reading of %.3f A or more (bms.balancing.rest_current_A) restarts its %.0f s "
                             "of rest; the current sensor's noise is %.3f A rms",
                             s.bms.image.balance.restCurrent_mA * 1e-3, b.rest_s, s.hardware.current_sense.noise_A_rms);
  const double span_s = trueAt >= 0.0 ? trueAt : lastT;
  row.paused_fraction = span_s > 0.0 ? (trueAt >= 0.0 ? pausedToTrue_s : paused_s) / span_s : 0.0;
  row.board_peak_C = peak;
  row.peak_board_C = peak.empty() ? NAN : *std::max_element(peak.begin(), peak.end());
  row.pack_heat_Wh = r.quad[kQuadBalanceHeat_J] / 3600.0;
  row.bled_Ah = r.quad[kQuadBalanceCharge_As] / 3600.0;
  double useful_As = 0.0, needed_As = 0.0;
  for (size_t g = 0; g < bled.size(); ++g) {
    useful_As += std::min(bled[g], need[g] * 3600.0);
    needed_As += need[g] * 3600.0;
  }
  row.pack_useful_Ah = std::min(useful_As / 3600.0, row.bled_Ah);
  row.pack_wasted_Ah = row.bled_Ah - row.pack_useful_Ah;
  row.needed_Ah = needed_As / 3600.0;
  // Final spread and imbalance from the recorded SOC of the last sample.
  const Recording& rec = r.rec;
  if (const size_t n = rec.samples(); n > 0) {
    const auto last = rec.cell_soc.begin() + static_cast<std::ptrdiff_t>((n - 1) * static_cast<size_t>(rec.cells));
    const std::vector<double> soc(last, last + rec.cells);
    row.final_spread_Ah = spread(groupCharge_Ah(plant.pack(), soc));
    row.final_imbalance_Ah = imbalance_Ah(plant.pack(), soc);
    if (duringCharge && !row.tripped)
      if (const std::string ended = bmsChargeEndText(s, r, row.final_imbalance_Ah, rec.time_s[n - 1]); !ended.empty())
        row.firmware_note += (row.firmware_note.empty() ? "" : "; ") + ended;
  }
}

// Within limits: the target reached, no protection tripped, the resistor within its
// rating. The fastest such row by true time is marked.
void markFastest(BalanceTimeResult& res) {
  BalanceTimeRow* best = nullptr;
  for (BalanceTimeRow& w : res.rows) {
    w.within_limits = w.simulated && !std::isnan(w.true_h) && !w.tripped && w.within_rating;
    if (w.within_limits && (!best || w.true_h < best->true_h)) best = &w;
  }
  if (best) best->fastest = true;
}

// The scenario's own imbalance at the start: what each series group holds above the lowest
// group's rest voltage, the group holding most, and the groups the firmware bleeds once it
// starts (more than its stop threshold above the lowest, bms chooseCells' rule), in all and
// on the board that has most of them.
struct ScenarioImbalance {
  std::vector<double> excess_Ah, soc;  // per group (groupExcess_Ah, groupSoc)
  int highest = 0;
  double highest_Ah = 0.0;  // its capacity
  double lowest_soc = 0.0;
  int high_groups = 0, high_on_one_board = 0;
};
ScenarioImbalance scenarioImbalance(const Plant& plant, const double* x0, const PassiveBalancerConfig& hw,
                                    double stop_delta_V) {
  const Pack& p = plant.pack();
  const std::vector<double> soc = cellSoc(plant, x0);
  ScenarioImbalance m;
  m.soc = groupSoc(p, soc);
  m.excess_Ah = groupExcess_Ah(p, soc);
  m.highest = static_cast<int>(std::max_element(m.excess_Ah.begin(), m.excess_Ah.end()) - m.excess_Ah.begin());
  m.highest_Ah = groupCapacity_Ah(p)[static_cast<size_t>(m.highest)];
  m.lowest_soc = *std::min_element(m.soc.begin(), m.soc.end());
  // Rest voltages: every cell has the pack's OCV curve.
  const CellParams& cell = p.cells[0];
  const double lowest_V = ecm::ocv(cell, m.lowest_soc);
  std::vector<int> perBoard(static_cast<size_t>(hw.boardOf(p.series - 1) + 1), 0);
  for (int g = 0; g < p.series; ++g) {
    if (ecm::ocv(cell, m.soc[static_cast<size_t>(g)]) - lowest_V <= stop_delta_V) continue;
    ++m.high_groups;
    m.high_on_one_board = std::max(m.high_on_one_board, ++perBoard[static_cast<size_t>(hw.boardOf(g))]);
  }
  // The analytic columns bleed the highest group at least, whatever the firmware's threshold.
  m.high_groups = std::max(1, m.high_groups);
  m.high_on_one_board = std::max(1, m.high_on_one_board);
  return m;
}

// The balancing board node's conductance to its surroundings: to ambient, to the cells
// and to other nodes, all taken at ambient (T = T_amb + P/G in steady state); 0 without
// a board node.
double boardConductance_W_per_K(const Scenario& s) {
  const std::string& name = s.hardware.balancing.board_node;
  for (const ThermalNodeConfig& n : s.thermal.nodes) {
    if (name.empty() || n.name != name) continue;
    double g = n.g_ambient_W_per_K + n.g_each_cell_W_per_K * s.pack.series * s.pack.parallel;
    for (const auto& link : n.cell_links) g += link.second;
    for (const auto& link : n.node_links) g += link.second;
    return g;
  }
  return 0.0;
}

}  // namespace

BalanceTimeResult balanceTime(const Scenario& base, const BalanceTimeOptions& o) {
  checkOptions(base, o);
  BalanceTimeResult res;
  res.scenario = base.name;
  res.parallel = base.pack.parallel;
  // Default target: half again the firmware's stop threshold. The firmware leaves each cell
  // up to that threshold above the lowest reading, so the truth settles about there, a
  // little above or below with the noise: a target at the threshold itself may never be met.
  const Policy policy = policyOf(base);
  const std::string when = settingChoice("balancing.when", base.bms.image);
  res.target_mV = o.target_mV ? *o.target_mV : std::max(0.1, 1.5 * policy.stop_delta_V * 1e3);
  res.resistor_rating_W = base.hardware.balancing.resistor_power_rating_W;
  res.board_max_C = policy.board_max_C;
  res.when = o.when ? *o.when : when;
  res.when_overridden = o.when.has_value() && *o.when != when;
  res.during_charge = o.during_charge;

  // The imbalance and the cell voltage of the analytic estimate.
  const Plant basePlant(base);
  std::vector<double> x0(static_cast<size_t>(basePlant.stateSize()), 0.0);
  basePlant.initialState(x0.data());
  const ScenarioImbalance imb = scenarioImbalance(basePlant, x0.data(), base.hardware.balancing, policy.stop_delta_V);
  const PassiveBalancerConfig& hw = base.hardware.balancing;
  const int parallel = basePlant.pack().parallel;
  res.delta_given = o.delta_Ah.has_value();
  res.delta_Ah = o.delta_Ah ? *o.delta_Ah : imb.excess_Ah[static_cast<size_t>(imb.highest)];
  if (!(res.delta_Ah > 0.0)) bad("the scenario's series groups rest at equal voltages: give --delta-Ah");
  res.cell_V = o.cell_V ? *o.cell_V : ecm::ocv(base.pack.cell, o.delta_Ah ? base.pack.initial_soc : imb.soc[static_cast<size_t>(imb.highest)]);
  // The high group's charge range for the droop form.
  const CellParams& cell = o.delta_Ah ? base.pack.cell : basePlant.pack().cells[static_cast<size_t>(imb.highest * parallel)];
  const double group_Ah = o.delta_Ah ? cell.capacity_Ah * parallel : imb.highest_Ah;
  const double socHigh = o.delta_Ah ? socAtOcv(cell, res.cell_V) : imb.soc[static_cast<size_t>(imb.highest)];
  const double socLow = o.delta_Ah ? socHigh - res.delta_Ah / group_Ah : imb.lowest_soc;
  // Checked for the analytic rows too: with --analytic-only a delta beyond the cell's
  // charge was taken (SOC below 0, the OCV table held flat there) and printed as given.
  if (socLow < 0.0) {
    std::ostringstream os;
    os << "--delta-Ah: " << res.delta_Ah << " Ah below a cell at " << res.cell_V << " V (SOC " << socHigh
       << ") empties it; at most " << socHigh * group_Ah << " Ah";
    bad(os.str());
  }
  // Bleeding ends (in the droop form) when the high group's OCV is within the target of the low one's.
  const double socTarget = std::min(socHigh, socAtOcv(cell, ecm::ocv(cell, socLow) + res.target_mV * 1e-3));
  // Cells on the most loaded board: given, the high cells sit on the first groups; from the
  // scenario, the groups the firmware bleeds at the start.
  res.high_cells = o.delta_Ah ? o.high_cells : imb.high_groups;
  const int perBoard = o.delta_Ah ? (hw.cells_per_board > 0 ? std::min(o.high_cells, hw.cells_per_board) : o.high_cells)
                                  : imb.high_on_one_board;
  const double boardG = boardConductance_W_per_K(base);

  std::vector<double> resistors = o.resistors_ohm;
  if (resistors.empty()) resistors.push_back(hw.resistor_ohm);
  const Scenario experimentBase = o.simulate ? experiment(base, o, res.cell_V) : base;
  for (double r : resistors) {
    BalanceTimeRow row;
    row.resistor_ohm = r;
    row.branch_ohm = r + hw.rds_on_ohm;
    row.current_A = res.cell_V / row.branch_ohm;
    row.power_W = res.cell_V * row.current_A;
    row.board_power_W = row.power_W * perBoard;
    const double iMax = cell.v_max_V / row.branch_ohm;
    row.resistor_W = iMax * iMax * r;
    row.within_rating = hw.resistor_power_rating_W <= 0.0 || row.resistor_W <= hw.resistor_power_rating_W;
    row.const_I_all_h = constantCurrentHours(res.delta_Ah, res.cell_V, row.branch_ohm);
    row.const_I_to_target_h = constantCurrentHours(group_Ah * (socHigh - socTarget), res.cell_V, row.branch_ohm);
    row.droop_to_target_h = ocvDroopHours(cell, group_Ah, socTarget, socHigh, row.branch_ohm);
    row.board_steady_C = boardG > 0.0 ? base.ambient_C.at(0.0) + row.board_power_W / boardG : NAN;
    row.peak_board_C = NAN;
    row.firmware_h = row.true_h = NAN;
    if (o.simulate) {
      Scenario s = experimentBase;
      s.hardware.balancing.resistor_ohm = r;
      simulate(s, res.target_mV, o.during_charge, row, res.warnings);
    }
    res.rows.push_back(row);
  }
  if (o.simulate && o.during_charge) {
    // The same charge without balancing: it ends when the charger stops delivering (the
    // charger's taper, or the firmware ending the charge on its first full cell).
    Scenario s = experimentBase;
    s.bms.image.balance.enabled = false;
    const double end_A = s.charger.end_current_A;
    double lastCharging_s = 0.0;
    auto stopWhen = [&](double t, const double*, const PlantSignals& sig, const bms::Outputs&) {
      if (sig.pack_current_A < -end_A) lastCharging_s = t;
      return t - lastCharging_s >= 600.0;
    };
    runScenario(s, stopWhen);
    const double without_h = lastCharging_s / 3600.0;
    for (BalanceTimeRow& w : res.rows) {
      w.charge_without_h = without_h;
      w.charge_added_h = w.charge_h - without_h;
    }
  }
  markFastest(res);
  return res;
}

}  // namespace packsim
