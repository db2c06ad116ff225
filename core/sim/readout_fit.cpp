#include "core/sim/readout_fit.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/scenario/provenance.hpp"
#include "core/scenario/scenario_error.hpp"
#include "core/sim/simulation.hpp"

namespace packsim {

namespace {

constexpr int kReadoutTask = 0;  // bms/bms_firmware.cpp: kTaskReadout
constexpr int kProbeTicks = 40;  // past the first read-outs (wake-up, configuration)

std::string ms(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", s * 1e3);
  return b;
}

// The longest read-out in the probe's first ticks, in seconds.
double probeReadout_s(const Scenario& s) {
  Scenario probe = s;
  probe.run.duration_s = kProbeTicks * s.bms.tick_s;
  probe.run.stop_after_trip_s = probe.run.duration_s;
  probe.faults.clear();
  probe.warnings.clear();
  probe.output.interval_s = probe.run.duration_s;
  probe.run.solver = RunConfig::Solver::Fast;  // the bus time does not depend on the integrator
  // A read-out every tick: what one read-out takes, whatever the scenario's period.
  probe.bms.readout.period_s = s.bms.tick_s;
  probe.bms.readout.alert_period_s = 0.0;
  SimulationRun run(probe, RunEnd::Scenario, Budgets::Measured);
  while (run.step()) {
  }
  return run.worstTaskTime_s(kReadoutTask);
}

// "file:line" of an origin, split for a ScenarioError ("" / 0 when it has none).
void splitOrigin(const std::string& origin, std::string& file, int& line) {
  const size_t colon = origin.rfind(':');
  file = origin;
  line = 0;
  if (colon == std::string::npos) return;
  const std::string tail = origin.substr(colon + 1);
  if (tail.empty() || tail.find_first_not_of("0123456789") != std::string::npos) return;
  file = origin.substr(0, colon);
  line = std::atoi(tail.c_str());
}

}  // namespace

std::shared_ptr<const Scenario> readoutThatFits(const Scenario& s) {
  if (s.bms.firmware.library) return nullptr;
  const double tick_s = s.bms.tick_s;
  const bool stated = s.bms.readout.period_s > 0.0;
  const double period_s = stated ? s.bms.readout.period_s : tick_s;
  const double need_s = probeReadout_s(s);
  if (need_s <= period_s * (1.0 + 1e-9)) return nullptr;
  const double fits_s = std::ceil(need_s / tick_s - 1e-9) * tick_s;
  const std::string what = "one read-out of the monitor chain takes " + ms(need_s) +
                           " ms of bus transfers and conversion waits (hardware.afe: its devices and baud)";
  if (stated) {
    std::string file = "scenario";
    int line = 0;
    if (s.provenance) splitOrigin(s.provenance->originOf("bms.readout.period_ms"), file, line);
    throw ScenarioError(file, line, 0, "bms.readout.period_ms",
                        "bms.readout.period_ms = " + ms(period_s) + " is too short: " + what +
                            "; the shortest period that holds it is " + ms(fits_s) +
                            " ms (a multiple of bms.tick_ms), or a faster bus (hardware.afe.baud)");
  }
  auto fitted = std::make_shared<Scenario>(s);
  fitted->bms.readout.period_s = fits_s;
  fitted->warnings.push_back("bms.readout.period_ms = " + ms(fits_s) + " (default (the shortest multiple of the " +
                             ms(tick_s) + " ms tick that holds one read-out)): " + what +
                             "; state bms.readout.period_ms to choose another");
  return fitted;
}

}  // namespace packsim
