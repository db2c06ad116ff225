// The co-simulation loop. core/ owns time; one BMS tick k (t_k = k·T_bms) is:
//
//   1. sample   sensors read the plant's truth at t_k: the monitor ICs' pins, the MCU's
//               ADC codes (noise, quantisation) and GPIO levels
//   2. decide   the firmware's tasks due in [t_k, t_k+1) run on the MCU clock: packsim's
//               core (bms/bms_firmware.hpp) or the scenario's library, each talking to
//               the register-level monitor ICs over the bus at its own read-out rate
//   3. actuate  the commands the firmware wrote at or before t_k take effect at t_k;
//               each later one is kept with the MCU clock's instant of its write
//               (core/firmware/pin_timeline.hpp)
//   4. record   truth, measurements and decisions of t_k (every output interval)
//   5. advance  the plant integrates t_k -> t_k+1 under the held commands and the load,
//               stopping exactly at every load breakpoint, timed fault, MCU output
//               change and relay contact whose delay runs out inside the tick (one
//               within a rounding sliver of t_k+1 is taken at t_k+1), re-initialising
//               CVODE only where an input jumps (command change, load breakpoint, a
//               fault that changes the plant's inputs). Faults on a condition
//               (`when:`) are judged at the ticks
//
// Latency: a reading taken at t_k acts on the plant from the instant the firmware wrote
// its decision (t_k plus the bus time and code before the write), so its effect (e.g.
// zero current after a trip) is first seen by the sample at t_k+1 -- one tick.
#pragma once
#include <bms/bms_hal.hpp>

#include <functional>
#include <memory>

#include "core/scenario/scenario.hpp"
#include "core/sim/external_inputs.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/result.hpp"

namespace packsim {

struct HardwareStatus;

// Optional early end, judged once per tick after step 2 (t_k, the plant state and
// signals sampled at t_k, the firmware's outputs); true ends the run at t_k. The signals
// are a sample (Plant::sample): without the heat fields PlantSignals marks with *.
using StopCondition = std::function<bool(double t_s, const double* x, const PlantSignals& sig, const bms::Outputs& out)>;

// Who ends a run: the scenario (its end time, stop after a trip, a finished charge), or
// only its driver, which stops stepping (an FMU: the importer's stop time rules).
enum class RunEnd { Scenario, Driver };

// Budgets::Enforced: a firmware task past its budget is a contract break, and packsim's
// core gets a read-out period that fits its chain (core/sim/readout_fit.hpp).
// Budgets::Measured: tasks may overrun and only their time is kept (that fit's probe).
enum class Budgets { Enforced, Measured };

// One run, one BMS tick at a time (an FMU or a firmware host drives it step by step).
// runScenario is `while (run.step(stopWhen)) {}` then finish().
class SimulationRun {
 public:
  explicit SimulationRun(const Scenario& s, RunEnd end = RunEnd::Scenario, Budgets budgets = Budgets::Enforced);
  ~SimulationRun();
  SimulationRun(const SimulationRun&) = delete;
  SimulationRun& operator=(const SimulationRun&) = delete;

  // Ticks 1–5 at t_k, then advances k. Returns false once the run has ended (at its end
  // time, on the stop condition, a tracker stop or a finished charge); the ending tick
  // is recorded.
  bool step(const StopCondition& stopWhen = {});
  // step()'s two halves, for a driver that sets inputs between them (an FMU runs
  // advance() then tick(): its ticks in (t, t+h]). tick(): 1–4 at t_k, false once the
  // run ended at t_k; advance(): 5, the plant to t_k+1, then k+1.
  bool tick(const StopCondition& stopWhen = {});
  void advance();
  // Inputs from outside (core/sim/external_inputs.hpp), applied from the next tick or
  // advance on.
  void setExternalInputs(const ExternalInputs& in);
  // What the last tick sampled and decided (valid until the next advance()).
  const Plant& plant() const;
  const double* state() const;  // x at t_k
  const PlantSignals& signals() const;  // a sample (Plant::sample): no heat
  const bms::Outputs& outputs() const;
  const HardwareStatus& hardware() const;
  bool tripped() const;  // the BMS opened the relay on a latched fault (the summary's trip)
  double time_s() const;  // t_k of the next step(), or of the tick() just run
  bool ended() const;
  // The longest simulated time one call of firmware task `task` took so far, on any MCU.
  double worstTaskTime_s(int task) const;
  RunResult finish();  // once, after the last step

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

RunResult runScenario(const Scenario& s, const StopCondition& stopWhen = {});

}  // namespace packsim
