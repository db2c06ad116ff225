#include "core/check/check.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <cstdio>
#include <filesystem>

#include "core/check/fault_causes.hpp"
#include "core/sim/firmware_failure.hpp"
#include "core/sim/relay_contact_text.hpp"
#include "core/scenario/load_scenario.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/scenario/target_switch.hpp"
#include "core/sim/simulation.hpp"
#include "core/sim/summary_text.hpp"
#include "core/text_fmt.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

bool startsWith(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }

// First event of `kind` at or after t whose detail starts with `prefix`; -1 if none.
const Event* firstAfter(const RunResult& r, double t, const std::string& kind, const std::string& prefix = "") {
  for (const Event& e : r.events)
    if (e.time_s >= t - 1e-9 && e.kind == kind && startsWith(e.detail, prefix)) return &e;
  return nullptr;
}

bool latchedAtTrip(const Summary& sm, const std::string& fault) {
  size_t pos = 0;
  while (pos <= sm.trip_reason.size()) {
    const size_t end = sm.trip_reason.find(", ", pos);
    if (sm.trip_reason.substr(pos, end - pos) == fault) return true;
    if (end == std::string::npos) break;
    pos = end + 2;
  }
  return false;
}

// SOC error bounds per estimator and the capacity estimate (issue 17).
void judgeEstimates(const Expectations& e, const Summary& sm, const std::function<void(const std::string&)>& fail) {
  auto stats = [&](const std::string& name) -> std::pair<std::string, const SocErrorStats*> {
    const std::string which = name.empty() ? sm.soc_estimator : name;
    return {which, which == "ekf" ? &sm.soc_error_ekf : &sm.soc_error_coulomb};
  };
  auto check = [&](const std::vector<SocErrorBound>& bounds, const char* what, double SocErrorStats::*field) {
    for (const SocErrorBound& b : bounds) {
      const auto [name, st] = stats(b.estimator);
      if (st->ticks == 0) fail(name + " SOC estimate never valid (no complete reading)");
      else if (!(std::fabs(st->*field) < b.bound))
        fail(name + " SOC error " + what + fmt(" %.2f %% is not below %.2f %%", 100.0 * std::fabs(st->*field), 100.0 * b.bound));
    }
  };
  check(e.soc_error_max_below, "max", &SocErrorStats::max);
  check(e.soc_error_rms_below, "rms", &SocErrorStats::rms);
  check(e.soc_error_end_below, "at the end", &SocErrorStats::end);
  if (e.capacity_error_below) {
    if (!(sm.capacity_estimate_Ah > 0.0))
      fail("expected a capacity estimate, but the firmware made none (two rests far enough apart in SOC)");
    else if (!(std::fabs(sm.capacity_estimate_Ah / sm.capacity_true_Ah - 1.0) < *e.capacity_error_below))
      fail(fmt("capacity estimate %.3f Ah is off the true %.3f Ah by more than %.1f %%", sm.capacity_estimate_Ah,
               sm.capacity_true_Ah, 100.0 * *e.capacity_error_below));
  }
}

// The fault_no_effect event of the injection `inj` (its fault_injected event), if any: its
// detail is the injection's description, " (", its place, ", active <start>...".
const Event* noEffectOf(const RunResult& r, const Event& inj) {
  for (const Event& e : r.events) {
    if (e.kind != "fault_no_effect") continue;
    const size_t open = e.detail.find(" (");
    if (open == std::string::npos || !injectionDetailIs(inj.detail, e.detail.substr(0, open))) continue;
    if (e.detail.find(fmt("active %.3f-", inj.time_s)) != std::string::npos ||
        e.detail.find(fmt("active from %.3f s", inj.time_s)) != std::string::npos)
      return &e;
  }
  return nullptr;
}

}  // namespace

CheckOutcome judge(const Scenario& s, const RunResult& r) {
  CheckOutcome o;
  o.name = s.name;
  for (const Event& ev : r.events)
    if (ev.kind == "config_warning" || ev.kind == "monitor_unread") o.warnings.push_back(ev.detail);
    else if (ev.kind == "cell_model_range") o.warnings.push_back("beyond the cell model: " + ev.detail);
    else if (ev.kind == "false_fault") o.warnings.push_back("a false fault: " + ev.detail);
    else if (ev.kind == "load_limited") o.warnings.push_back("load not met: " + ev.detail);
    else if (ev.kind == "firmware_misuse") o.warnings.push_back("the firmware " + fmt("at %.4f s: ", ev.time_s) + ev.detail);
    else if (ev.kind == "register_misuse") o.warnings.push_back("bus misuse " + fmt("from %.4f s: ", ev.time_s) + ev.detail);
  if (const std::string never = relayNeverClosed(s, r); !never.empty()) o.warnings.push_back("the relay " + never);
  // A trip is judged by what the BMS decided; whether it isolated the pack is the contact's.
  if (r.summary.tripped && !contactOpenFrom(r, r.summary.trip_time_s))
    o.warnings.push_back("the BMS tripped at " + fmt("%.3f s", r.summary.trip_time_s) + " (" + r.summary.trip_reason +
                         ") but " + contactFrom(r, r.summary.trip_time_s) + ": the trip did not isolate the pack");
  o.target = r.summary.firmware_target;
  const Expectations& e = s.expect;
  const Summary& sm = r.summary;
  auto fail = [&](const std::string& m) { o.failures.push_back(m); };

  if (e.no_trip && *e.no_trip && sm.tripped)
    fail("expected no trip, but the BMS tripped at " + fmt("%.3f s", sm.trip_time_s) + " (" + sm.trip_reason +
         "): " + contactFrom(r, sm.trip_time_s));
  if (e.no_trip && !*e.no_trip && !sm.tripped) fail("expected a trip, but the BMS never opened the relay on a fault");
  if (e.trip_reason) {
    if (!sm.tripped)
      fail("expected a trip on " + *e.trip_reason + ", but there was none");
    else if (!latchedAtTrip(sm, *e.trip_reason))
      fail("expected the trip on " + *e.trip_reason + ", got " + sm.trip_reason);
  }
  if (e.trip_within_s) {
    const auto [a, b] = *e.trip_within_s;
    if (!sm.tripped || sm.trip_time_s < a - 1e-9 || sm.trip_time_s > b + 1e-9)
      fail(fmt("expected a trip within [%.3f, %.3f] s, ", a, b) +
           (sm.tripped ? fmt("got %.3f s", sm.trip_time_s) : std::string("got none")));
  }
  if (e.relay_open_by_s) {
    bool open = false;
    bool reclosed = false;
    // The contact itself, not the command: a welded relay or the monitor's FAULT line
    // make the two differ.
    for (const Event& ev : r.events) {
      if (ev.kind != "relay_contact") continue;
      if (ev.time_s <= *e.relay_open_by_s + 1e-9) open = ev.detail == "opened";
      else if (ev.detail == "closed") reclosed = true;
    }
    if (!open) fail(fmt("expected the relay contact open by %.3f s", *e.relay_open_by_s));
    if (reclosed) fail(fmt("the relay closed again after %.3f s", *e.relay_open_by_s));
  }
  for (const DetectionExpectation& d : e.detected) {
    const Event* ev = firstAfter(r, 0.0, "fault_active", d.fault + ":");
    if (!ev) ev = firstAfter(r, 0.0, "firmware", "trip: " + d.fault);  // a library firmware's report
    if (!ev)
      fail("expected " + d.fault + fmt(" within [%.3f, %.3f] s, never raised", d.from_s, d.to_s));
    else if (ev->time_s < d.from_s - 1e-9 || ev->time_s > d.to_s + 1e-9)
      fail("expected " + d.fault + fmt(" within [%.3f, %.3f] s, raised at %.3f s", d.from_s, d.to_s, ev->time_s));
  }
  if (e.min_cell_V_above && !(sm.min_cell_V > *e.min_cell_V_above))
    fail(fmt("lowest cell %.4f V (cell ", sm.min_cell_V) + std::to_string(sm.min_cell) +
         fmt(") is not above %.4f V", *e.min_cell_V_above));
  const double spread = sm.final_soc_max - sm.final_soc_min;
  if (e.final_soc_spread_above && !(spread > *e.final_soc_spread_above))
    fail(fmt("final SOC spread %.4f is not above ", spread) + fmt("%.4f", *e.final_soc_spread_above));
  if (e.final_soc_spread_below && !(spread < *e.final_soc_spread_below))
    fail(fmt("final SOC spread %.4f is not below ", spread) + fmt("%.4f", *e.final_soc_spread_below));
  if (e.max_temp_C_below && !(sm.max_temp_C < *e.max_temp_C_below))
    fail(fmt("hottest cell %.2f C (cell ", sm.max_temp_C) + std::to_string(sm.hottest_cell) +
         fmt(") is not below %.2f C", *e.max_temp_C_below));
  if (e.energy_delivered_Wh_above && !(sm.energy_delivered_Wh > *e.energy_delivered_Wh_above))
    fail(fmt("energy delivered %.2f Wh is not above %.2f Wh", sm.energy_delivered_Wh, *e.energy_delivered_Wh_above));
  {
    const VehicleSummary& v = sm.vehicle;
    const double km = v.distance_m / 1000.0;
    if ((e.vehicle_distance_km_above || e.vehicle_distance_km_below || e.vehicle_finished) && !v.present)
      fail("the vehicle expectations need a vehicle (load: {vehicle: ...})");
    else {
      if (e.vehicle_distance_km_above && !(km > *e.vehicle_distance_km_above))
        fail(fmt("the vehicle drove %.3f km, not above ", km) + fmt("%.3f km", *e.vehicle_distance_km_above));
      if (e.vehicle_distance_km_below && !(km < *e.vehicle_distance_km_below))
        fail(fmt("the vehicle drove %.3f km, not below ", km) + fmt("%.3f km", *e.vehicle_distance_km_below));
      if (e.vehicle_finished && v.finished != *e.vehicle_finished)
        fail(std::string("the vehicle ") + (v.finished ? "finished" : "did not finish") + " its route");
    }
  }

  judgeEstimates(e, sm, fail);
  // A firmware that failed (load, init, crash, hang, contract break) fails the check
  // with its reason, unless the scenario means it to.
  const std::string fwFailure = firmwareFailure(s, r);
  if (!fwFailure.empty() && !e.firmware_fault) fail(fwFailure);
  if (fwFailure.empty() && e.firmware_fault) fail("expected a firmware_fault, but the firmware ran to the end");
  if (e.mcu_resets) {
    const auto n = std::count_if(r.events.begin(), r.events.end(), [](const Event& ev) { return ev.kind == "mcu_reset"; });
    if (n != *e.mcu_resets)
      fail("expected " + std::to_string(*e.mcu_resets) + " MCU resets, got " + std::to_string(n));
  }
  if (e.energy_lost_vs_compare_Wh_above || e.min_cell_V_below_compare) {
    const Comparison& c = sm.compare;
    if (!c.present) {
      fail("no comparison run (compare: {scenario: ...})");
    } else {
      const double lost = c.lostWh();
      if (e.energy_lost_vs_compare_Wh_above && !(lost > *e.energy_lost_vs_compare_Wh_above))
        fail("energy lost against " + c.name +
             fmt(" %.2f Wh is not above ", lost) + fmt("%.2f Wh", *e.energy_lost_vs_compare_Wh_above));
      if (e.min_cell_V_below_compare && *e.min_cell_V_below_compare && !(sm.min_cell_V < c.min_cell_V))
        fail(fmt("lowest cell %.4f V is not below ", sm.min_cell_V) + c.name + fmt("'s %.4f V", c.min_cell_V));
    }
  }

  // Detection latency of every injected fault: to the first BMS fault this injection can
  // cause (core/check/fault_causes), not to whatever fault came next.
  // A fault raised after an injection was removed, once a later injection that can cause
  // it too had started, is the later one's (a 0.1 s over-current that tripped nothing is
  // not credited with the trip of another one 10 s later).
  const std::vector<InjectionSpan> spans = injectionSpans(r.events);
  for (const InjectionSpan& span : spans) {
    const Event& inj = *span.injected;
    std::string line = inj.detail + fmt(" @%.3f s: ", inj.time_s);
    const FaultKind kind = span.kind;
    const bool known = span.known;
    const std::vector<std::string>& causes = known ? faultsCausedBy(kind) : std::vector<std::string>{};
    auto causedHere = [&](const std::string& name) { return std::find(causes.begin(), causes.end(), name) != causes.end(); };
    FaultLatency fl;
    fl.injected = inj.detail;
    fl.injected_at_s = inj.time_s;
    if (known && kind == FaultKind::SupplyBrownout) {  // what the MCU did: reset, or rode it through
      const Event* reset = firstAfter(r, inj.time_s, "mcu_reset", "brown-out");
      const Event* removed = firstAfter(r, inj.time_s, "fault_removed", inj.detail);
      if (reset && (!removed || reset->time_s <= removed->time_s + 1e-9))
        line += fmt("the MCU reset at %.3f s (no BMS fault expected)", reset->time_s);
      else
        line += "above the brown-out threshold, the MCU rode it through (no BMS fault expected)";
      o.fault_latencies.push_back(fl);
      o.latencies.push_back(line);
      continue;
    }
    // An injection that never acted (its fault_no_effect event, core/sim/fault_effect.hpp)
    // caused nothing: a BMS fault after it came from elsewhere, and crediting it with one
    // (a charger overvoltage "detected" by the trip an imbalanced cell causes anyway) is
    // a test result that did not happen.
    if (const Event* none = noEffectOf(r, inj)) {
      line += "no effect: " + none->detail.substr(none->detail.find("): ") + 3);
      o.fault_latencies.push_back(fl);
      o.latencies.push_back(line);
      continue;
    }
    if (causes.empty()) {
      line += "an operator input, not a fault (no BMS fault expected)";
      o.fault_latencies.push_back(fl);
      o.latencies.push_back(line);
      continue;
    }
    // The first fault raised at or after the injection that it can cause; a library
    // firmware reports its detection as the event "trip: <reason>" (docs/firmware.md).
    const Event* det = nullptr;
    std::string detName;
    const Event* unrelated = nullptr;  // the first fault after it that it cannot cause
    std::string unrelatedName;
    const Event* taken = nullptr;  // the first it could cause that a later injection caused
    const InjectionSpan* takenBy = nullptr;
    std::string takenName;
    for (const Event& e : r.events) {
      if (e.time_s < inj.time_s - 1e-9) continue;
      std::string name;
      if (e.kind == "fault_active") name = e.detail.substr(0, e.detail.find(':'));
      else if (e.kind == "firmware" && startsWith(e.detail, "trip: ")) name = e.detail.substr(6, e.detail.find_first_of(" ,(:", 6) - 6);
      else continue;
      if (causedHere(name)) {
        if (const InjectionSpan* later = laterCause(spans, span, name, e.time_s)) {
          if (!taken) {
            taken = &e;
            takenBy = later;
            takenName = name;
          }
          continue;
        }
        det = &e;
        detName = e.kind == "firmware" ? e.detail.substr(6) : name;
        break;
      }
      if (!unrelated) {
        unrelated = &e;
        unrelatedName = name;
      }
    }
    const Event* line_ = causedHere("monitor_fault") ? firstAfter(r, inj.time_s, "monitor_fault_line", "asserted") : nullptr;
    if (line_ && laterCause(spans, span, "monitor_fault", line_->time_s)) line_ = nullptr;
    // The relay opening counts for this injection when it followed its own detection
    // (or the monitor's FAULT line it caused).
    const double causeAt_s = std::min(det ? det->time_s : INFINITY, line_ ? line_->time_s : INFINITY);
    // A contact already open when the fault was raised (an earlier trip, a precharge not
    // yet done) did not open on it: its next opening, after a re-close, is another story.
    // (Without a cause, the contact as the injection found it.)
    const double refAt_s = std::isfinite(causeAt_s) ? causeAt_s : inj.time_s;
    const Event* openSince = nullptr;  // the contact's last event before then: open when "opened" or none
    bool closedThen = false;
    for (const Event& e : r.events)
      if (e.kind == "relay_contact" && e.time_s < refAt_s - 1e-9) {
        closedThen = e.detail == "closed";
        openSince = closedThen ? nullptr : &e;
      }
    const Event* open = std::isfinite(causeAt_s) && closedThen ? firstAfter(r, causeAt_s, "relay_contact", "opened") : nullptr;
    if (det) {
      fl.detected_fault = detName;
      fl.detection_latency_s = det->time_s - inj.time_s;
    }
    if (open) fl.relay_open_latency_s = open->time_s - inj.time_s;
    o.fault_latencies.push_back(fl);
    if (det) line += detName + fmt(" after %.3f s", det->time_s - inj.time_s);
    else line += "no BMS fault it can cause";
    if (line_ && (!det || line_->time_s < det->time_s))
      line += fmt(", monitor FAULT line after %.3f s", line_->time_s - inj.time_s);
    if (open) {
      line += fmt(", relay open after %.3f s", open->time_s - inj.time_s);
    } else if (const Event* other = firstAfter(r, inj.time_s, "relay_contact", "opened");
               !closedThen && (std::isfinite(causeAt_s) || !other)) {
      line += openSince ? fmt(", relay already open (since %.3f s)", openSince->time_s) : std::string(", relay not closed yet");
    } else {
      line += other ? fmt(", relay opened at %.3f s but not on a fault this injection causes", other->time_s)
                    : std::string(", relay not opened");
    }
    if (!det && unrelated)
      line += " (" + unrelatedName + fmt(" at %.3f s is not caused by it)", unrelated->time_s);
    if (!det && taken)
      line += fmt(" (removed at %.3f s; ", span.end_s) + takenName +
              fmt(" at %.3f s followed ", taken->time_s) + takenBy->injected->detail +
              fmt(" injected at %.3f s)", takenBy->start_s);
    o.latencies.push_back(line);
  }
  // A scripted fault the run never reached (it ended first), or one that could not act
  // (an over-current with the relay open, a weld never commanded open), tested nothing.
  int unreached = 0, noEffect = 0;
  for (const Event& ev : r.events) {
    if (ev.kind == "fault_not_reached") {
      ++unreached;
      if (e.present) fail("scripted fault never happened: " + ev.detail);
    } else if (ev.kind == "fault_no_effect") {
      ++noEffect;
      if (e.present) fail("scripted fault had no effect: " + ev.detail);
    }
  }
  o.verdict = sm.tripped ? fmt("trip at %.3f s (", sm.trip_time_s) + sm.trip_reason + ")" : "no trip";
  if (!e.soc_error_max_below.empty() || !e.soc_error_rms_below.empty() || !e.soc_error_end_below.empty())
    o.verdict += fmt(", SOC error max coulomb %.2f %%, ekf %.2f %%", 100.0 * sm.soc_error_coulomb.max, 100.0 * sm.soc_error_ekf.max);
  if (e.capacity_error_below)
    o.verdict += fmt(", capacity %.3f Ah (true %.3f Ah)", sm.capacity_estimate_Ah, sm.capacity_true_Ah);
  if (!fwFailure.empty()) o.verdict += "; " + fwFailure;
  if (unreached > 0) o.verdict += ", " + std::to_string(unreached) + " scripted fault" + (unreached > 1 ? "s" : "") + " not reached";
  if (noEffect > 0) o.verdict += ", " + std::to_string(noEffect) + " scripted fault" + (noEffect > 1 ? "s" : "") + " without effect";
  // Without an expect: block the run is reported, not passed.
  o.nothing_to_check = !e.present && o.failures.empty();
  if (o.nothing_to_check) o.verdict = "ran, nothing to check (" + o.verdict + ")";
  o.passed = o.failures.empty();
  return o;
}

CheckOutcome checkScenarioFile(const std::string& path, const std::string& target) {
  CheckOutcome o;
  o.name = path;
  try {
    const Scenario s = target.empty() ? loadScenarioFile(path) : loadScenarioOnTarget(path, {}, target);
    o = judge(s, runScenario(s));
    o.name = path;
  } catch (const NotOnTarget& e) {
    o.skipped = true;
    o.passed = true;
    o.error_message = e.what();
  } catch (const std::exception& e) {
    o.error = true;
    o.passed = false;
    o.error_message = e.what();
  }
  return o;
}

std::vector<std::string> collectScenarioFiles(const std::vector<std::string>& paths) {
  std::vector<std::string> files;
  for (const std::string& p : paths) {
    if (!fs::is_directory(p)) {
      files.push_back(p);
      continue;
    }
    std::vector<std::string> found;
    for (auto it = fs::recursive_directory_iterator(p); it != fs::recursive_directory_iterator(); ++it) {
      const std::string name = it->path().filename().string();
      if (it->is_directory() && (name == "cells" || name == "profiles")) {
        it.disable_recursion_pending();
        continue;
      }
      if (it->is_regular_file() && it->path().extension() == ".yaml") found.push_back(it->path().string());
    }
    std::sort(found.begin(), found.end());
    files.insert(files.end(), found.begin(), found.end());
  }
  return files;
}

}  // namespace packsim
