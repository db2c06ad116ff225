// packsim_bench: runs the benchmarks and prints their figures as one table.
//
//   packsim_bench [--quick] [floor|plant|macro|presets|scaling|batch|restarts|target ...]   (default: all)
//   (target: the example firmware and packsim's core in host mode and on the virtual
//    Cortex-M4, same scenarios)
//   (plant: system D's fast integrator alone, for profiling the plant with perf;
//    restarts: system B's balancer race, CVODE against the fast integrator)
//
// Figures per row: simulated time, ticks, CPU and wall time (minimum of repeats),
// real-time factor (simulated / CPU time), ns per cell-step (CPU) and the ratio to
// the floor kernel measured in this same process on the same pack.
#include <cstdio>
#include <ctime>
#include <set>
#include <string>
#include <vector>

#include "bench/benchmarks.hpp"
#include "core/sim/simulation.hpp"

using namespace packsim;
using namespace packsim::bench;

namespace {

// The instructions the emulator ran, from the last of a run's summary `target` lines
// ("cortex-m4 at 168 MHz: N instructions, ..."); "-" without one.
std::string emulatedInstructions(const std::vector<std::string>& targetLines) {
  if (targetLines.empty()) return "-";
  const std::string& last = targetLines.back();
  const size_t colon = last.find(": ");
  return last.substr(colon + 2, last.find(" instructions") - colon - 2);
}

void addRun(Table& t, const RunFigures& f, double floor_ns) {
  t.add({f.label, std::to_string(f.cells), fmt(f.sim_s, 0), std::to_string(f.ticks), fmt(f.time.cpu_s, 2),
         fmt(f.time.wall_s, 2), fmt(f.sim_s / f.time.cpu_s, 0), fmt(f.cpuNsPerCellStep(), 1),
         fmt(f.cpuNsPerCellStep() / floor_ns, 2), std::to_string(f.solver_steps),
         f.jac_evals > 0 ? std::to_string(f.jac_evals) : "-"});
}

void addFloor(Table& t, const std::string& label, int cells, long ticks, double tick_s, const FloorResult& r) {
  const double cpu_s = r.cpu_ns_per_cell_step * 1e-9 * cells * static_cast<double>(ticks);
  const double wall_s = r.wall_ns_per_cell_step * 1e-9 * cells * static_cast<double>(ticks);
  const double sim_s = static_cast<double>(ticks) * tick_s;
  t.add({label, std::to_string(cells), fmt(sim_s, 0), std::to_string(ticks), fmt(cpu_s, 3), fmt(wall_s, 3),
         fmt(sim_s / cpu_s, 0), fmt(r.cpu_ns_per_cell_step, 1), "1.00", "-", "-"});
}

Table runTable() {
  return Table({"benchmark", "cells", "sim s", "ticks", "CPU s", "wall s", "RTF", "ns/cell-step", "x floor",
                "steps", "jac evals"});
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::set<std::string> want;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true;
    else if (a == "floor" || a == "plant" || a == "macro" || a == "presets" || a == "scaling" || a == "batch" ||
             a == "restarts" || a == "target")
      want.insert(a);
    else {
      std::fprintf(stderr, "usage: %s [--quick] [floor|plant|macro|presets|scaling|batch|restarts|target ...]\n",
                   argv[0]);
      return 2;
    }
  }
  auto on = [&](const char* s) { return want.empty() || want.count(s) > 0; };
  std::printf("packsim benchmarks%s; load average %.2f at start\n", quick ? " (quick)" : "", loadAverage1());
  std::printf("Times are thread CPU time (wall in its own column), minimum of repeats; RTF = simulated / CPU time.\n\n");

  if (on("floor") || on("macro")) {
    // System D: the bundled scenario, unchanged but for the solver.
    const Scenario cv = bundledScenario("motorcycle_110s.yaml", {{"run.solver", "cvode"}});
    const Scenario fa = bundledScenario("motorcycle_110s.yaml", {{"run.solver", "fast"}});
    const long raceTicks = std::lround(fa.endTime_s() / fa.bms.tick_s);
    const int runs = quick ? 1 : 3;  // three 20-minute races = one hour of racing
    Table t = runTable();
    const FloorResult fl = runFloor(fa, raceTicks, quick ? 3 : 5);
    addFloor(t, "floor: bare ECM + thermal, 110 cells", fa.pack.series * fa.pack.parallel, raceTicks, fa.bms.tick_s, fl);
    if (on("macro")) {
      addRun(t, timeFastIntegratorOnly(fa, quick ? 1 : 3), fl.cpu_ns_per_cell_step);
      addRun(t, timeScenario("system D, fast  (full co-simulation)", fa, runs, 1), fl.cpu_ns_per_cell_step);
      addRun(t, timeScenario("system D, cvode (full co-simulation)", cv, runs, 1), fl.cpu_ns_per_cell_step);
    }
    std::printf("System D (110s1p, 10 ms BMS tick, 1 Hz recording), %s:\n%s\n",
                quick ? "one 20-minute race" : "one hour of racing = three 20-minute races", t.str().c_str());
  }

  if (want.count("plant") > 0) {
    const Scenario fa = bundledScenario("motorcycle_110s.yaml", {{"run.solver", "fast"}});
    Table t = runTable();
    addRun(t, timeFastIntegratorOnly(fa, quick ? 3 : 10), 1.0);
    std::printf("System D's plant alone (x floor column: ns, no floor measured):\n%s\n", t.str().c_str());
  }

  if (on("presets")) {
    // Every reference preset as bundled (its read-out rates, tick and recording), with
    // the fast integrator and with CVODE; system C also at a 10 ms BMS tick (the small-pack
    // case: a whole stack's firmware and frames for 6 cells); system D also read out every 10 ms (its boards
    // at 1 MHz SPI: at the team's ~62 kHz a 36-cell board takes longer than 10 ms to read).
    struct Preset { const char* label; const char* file; Overrides extra; };
    const Preset presets[] = {
        {"A eco-marathon 12s1p", "eco_marathon_12s.yaml", {}},
        {"B solar car 28s15p", "solar_car_28s15p.yaml", {}},
        {"C bench 6s1p 2C", "bench_6s_ncr18650_2C.yaml", {}},
        {"C at a 10 ms tick", "bench_6s_ncr18650_2C.yaml", {{"bms.tick_ms", "10"}}},
        {"D motorcycle 110s1p", "motorcycle_110s.yaml", {}},
        {"D read every 10 ms, 1 MHz SPI", "motorcycle_110s.yaml", {{"bms.readout.period_ms", "10"}, {"hardware.afe.baud", "1000000"}}},
        {"E scooter 16s1p", "scooter_16s_lto.yaml", {}},
    };
    Table t = runTable();
    for (const Preset& p : presets) {
      Overrides fo = p.extra, co = p.extra;
      fo.push_back({"run.solver", "fast"});
      co.push_back({"run.solver", "cvode"});
      const Scenario fa = bundledScenario(p.file, fo), cv = bundledScenario(p.file, co);
      const long ticks = std::lround(std::floor(fa.endTime_s() / fa.bms.tick_s + 1e-9));
      const FloorResult fl = runFloor(fa, ticks, quick ? 2 : 3);
      addFloor(t, std::string("floor ") + p.label, fa.pack.series * fa.pack.parallel, ticks, fa.bms.tick_s, fl);
      RunFigures plant = timeFastIntegratorOnly(fa, quick ? 1 : 3);
      plant.label = std::string("plant ") + p.label;
      addRun(t, plant, fl.cpu_ns_per_cell_step);
      addRun(t, timeScenario(std::string("fast  ") + p.label, fa, 1, quick ? 1 : 3), fl.cpu_ns_per_cell_step);
      if (!quick) addRun(t, timeScenario(std::string("cvode ") + p.label, cv, 1, 1), fl.cpu_ns_per_cell_step);
      std::fflush(stdout);
    }
    std::printf("Reference presets as bundled (their read-out rates; the whole run, setup to recording):\n%s\n",
                t.str().c_str());
  }

  if (on("scaling")) {
    struct Size { int series, parallel; };
    const Size sizes[] = {{12, 1}, {110, 1}, {28, 15}, {50, 20}, {250, 20}};
    const double fast_s = quick ? 20.0 : 120.0, cvode_s = quick ? 10.0 : 60.0;
    Table t = runTable();
    for (const Size& z : sizes) {
      const std::string name = std::to_string(z.series) + "s" + std::to_string(z.parallel) + "p";
      const Scenario fa = scaledPack(z.series, z.parallel, fast_s, "fast");
      const Scenario cv = scaledPack(z.series, z.parallel, cvode_s, "cvode");
      const FloorResult fl = runFloor(fa, std::lround(fast_s / fa.bms.tick_s), quick ? 2 : 3);
      addFloor(t, "floor " + name, z.series * z.parallel, std::lround(fast_s / fa.bms.tick_s), fa.bms.tick_s, fl);
      addRun(t, timeScenario("fast  " + name, fa, 1, quick ? 1 : 2), fl.cpu_ns_per_cell_step);
      addRun(t, timeScenario("cvode " + name, cv, 1, 1), fl.cpu_ns_per_cell_step);
      std::fflush(stdout);
    }
    std::printf("Scaling (system D's cell and race; current, shunt and over-current limits x parallel):\n%s\n",
                t.str().c_str());
  }

  if (on("restarts")) {
    // System B's race with its active balancer: a converter switches at most 100 ms ticks,
    // and CVODE restarts at each switch (core/sim/cvode_integrator.hpp). The first
    // 5 minutes (1 with --quick), without the `compare:` run; CVODE's CPU time on the
    // diagonal Newton matrix and on the sparse one (run.jacobian) as a ratio to the fast
    // integrator's (the scenario's own solver), all measured here.
    const double dur = quick ? 60.0 : 300.0;
    Scenario fa = bundledScenario("solar_car_28s15p_balancer.yaml", {{"run.duration_s", fmt(dur, 0)}});
    fa.compare_scenario.clear();
    Scenario cv = fa, sp = fa;
    cv.run.solver = sp.run.solver = RunConfig::Solver::Cvode;
    cv.run.jacobian = RunConfig::Jacobian::Diagonal;
    sp.run.jacobian = RunConfig::Jacobian::Sparse;
    const RunFigures f = timeScenario("fast  B + active balancer", fa, 1, quick ? 1 : 3);
    const RunFigures c = timeScenario("cvode B + active balancer, diagonal", cv, 1, quick ? 1 : 2);
    const RunFigures k = timeScenario("cvode B + active balancer, sparse", sp, 1, 1);
    Table t({"benchmark", "sim s", "CPU s", "wall s", "x fast (CPU)", "steps", "restarts", "jac evals", "setups"});
    for (const RunFigures* r : {&f, &c, &k})
      t.add({r->label, fmt(r->sim_s, 0), fmt(r->time.cpu_s, 2), fmt(r->time.wall_s, 2),
             fmt(r->time.cpu_s / f.time.cpu_s, 1), std::to_string(r->solver_steps), std::to_string(r->reinits),
             r->jac_evals > 0 ? std::to_string(r->jac_evals) : "-",
             r->lin_setups > 0 ? std::to_string(r->lin_setups) : "-"});
    std::printf("Restarts at input switches (system B's race with its active balancer):\n%s\n", t.str().c_str());
  }

  if (on("target")) {
    // The example firmware as a host library and as Cortex-M4 code in the emulator, on
    // the same scenarios (the ELFs and the library next to this executable).
    Table t({"example firmware (system C / D)", "sim s", "host CPU s", "target CPU s", "target / host",
             "instructions", "RTF target"});
    const char* names[] = {"c_example_firmware_overcurrent", "c_example_firmware_hot_cell", "d_example_firmware_device_silent"};
    for (const char* n : names) {
      const std::string name = n;
      const Scenario host = bundledScenario("firmware/" + name + ".yaml");
      const Scenario target = bundledScenario("firmware/target/" + name + "_cm4.yaml");
      const RunFigures h = timeScenario(name, host, 1, quick ? 1 : 3);
      const RunFigures g = timeScenario(name, target, 1, quick ? 1 : 3);
      const std::string instr = emulatedInstructions(runScenario(target).summary.firmware_target);
      t.add({name, fmt(g.sim_s, 0), fmt(h.time.cpu_s, 3), fmt(g.time.cpu_s, 3), fmt(g.time.cpu_s / h.time.cpu_s, 2),
             instr, fmt(g.sim_s / g.time.cpu_s, 0)});
    }
    std::printf("Target mode (Unicorn, 168 MHz Cortex-M4) against host mode (the same C as an x86-64 library):\n%s\n",
                t.str().c_str());
    // packsim's own core (bms/, C++): linked in (host mode) and packsim_core_cm4.elf on
    // the virtual MCU (--target cortex-m4), the same scenario and image.
    Table c({"packsim's core", "sim s", "host CPU s", "target CPU s", "target / host", "instructions", "RTF target"});
    const char* coreNames[] = {"scooter_16s_lto_cold_charge", "faults/e_channel_gain", "faults/a_overcurrent"};
    for (const char* n : coreNames) {
      const std::string file = std::string(n) + ".yaml";
      const Scenario host = bundledScenario(file);
      const Scenario target = bundledScenario(file, {{"bms.firmware.target", "cortex-m4"}});
      const RunFigures h = timeScenario(n, host, 1, quick ? 1 : 3);
      const RunFigures g = timeScenario(n, target, 1, quick ? 1 : 3);
      const std::string instr = emulatedInstructions(runScenario(target).summary.firmware_target);
      c.add({n, fmt(g.sim_s, 0), fmt(h.time.cpu_s, 3), fmt(g.time.cpu_s, 3), fmt(g.time.cpu_s / h.time.cpu_s, 1), instr,
             fmt(g.sim_s / g.time.cpu_s, 0)});
    }
    std::printf("packsim's core in target mode (packsim_core_cm4.elf) against host mode (linked in):\n%s\n",
                c.str().c_str());
  }

  if (on("batch")) {
    const int cases = quick ? 4 : 8;
    const double dur = quick ? 120.0 : 300.0;
    const BatchFigures b = runBatchBench(cases, dur, quick ? 1 : 2);
    Table t({"batch (core/batch, fast solver)", "cases", "1 thread wall s", "2 threads wall s", "speed-up",
             "cores obtained 1t / 2t", "CPU s 1t / 2t", "load avg before/after", "all ok"});
    t.add({"system D Monte Carlo, " + fmt(dur, 0) + " s each", std::to_string(b.cases), fmt(b.wall1_s, 2),
           fmt(b.wall2_s, 2), fmt(b.wall1_s / b.wall2_s, 2), fmt(b.cores1, 2) + " / " + fmt(b.cores2, 2),
           fmt(b.cpu1_s, 2) + " / " + fmt(b.cpu2_s, 2),
           fmt(b.load_before, 2) + " / " + fmt(b.load_after, 2), b.all_ok ? "yes" : "NO"});
    std::printf("Batch on 2 cores (wall time; cores obtained = process CPU / wall: below 2 the machine was busy;\n"
                "equal CPU s for 1 and 2 threads: the threads do not slow each other down):\n%s\n",
                t.str().c_str());
  }
  return 0;
}
