#include "core/sim/simulation.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "core/balance/noise_floor.hpp"
#include "core/sim/bms_bridge.hpp"
#include "core/sim/comparison.hpp"
#include "core/sim/cvode_integrator.hpp"
#include "core/sim/fast_integrator.hpp"
#include "core/sim/balance_report.hpp"
#include "core/sim/fault_scheduler.hpp"
#include "core/sim/mcu_firmware.hpp"
#include "core/sim/load_shortfall.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/plant_ode.hpp"
#include "core/sim/read_coverage.hpp"
#include "core/sim/readout_fit.hpp"
#include "core/sim/run_end.hpp"
#include "core/sim/run_tracker.hpp"
#include "core/sim/same_instant.hpp"
#include "core/sim/vehicle_run.hpp"

namespace packsim {

namespace {
std::string afterTripText(double s) {
  char buf[80];
  std::snprintf(buf, sizeof buf, "%g s after the trip (run.stop_after_trip_s)", s);
  return buf;
}

// The `load_end` event's detail: a profile's last lap is over and the run goes on with
// no load (LoadProfile::segmentAt: zero past the last lap).
std::string loadEndText(const LoadProfile& p) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "the load profile ends (%d lap%s of %g s): 0 %s from here to the run's end", p.laps,
                p.laps == 1 ? "" : "s", p.lap_s(), p.quantity == LoadProfile::Quantity::Power_W ? "W" : "A");
  return buf;
}
// The current path the plant sees over the next interval, for the scripted faults that
// act only through it (core/sim/fault_effect.hpp).
PathState pathState(const PlantInputs& in, const HardwareSim& hw, const PlantSignals& sig, const Scenario& s) {
  PathState p;
  p.terminal_V = sig.pack_voltage_V;
  p.chargerSetpoint_V = s.charger.voltage_V;
  p.relayContactClosed = hw.status().relay_closed;
  p.mainClosed = in.relay_closed;
  p.dischargeBlocked = in.discharge_blocked;
  p.chargeBlocked = in.charge_blocked;
  p.chargerOn = in.charger_limit_A > 0.0;
  p.relayCommandedOpen = !hw.relayCoil();
  return p;
}
}  // namespace

struct SimulationRun::Impl {
  Impl(std::shared_ptr<const Scenario> fitted, const Scenario& sc, RunEnd end, Budgets budgets)
      : owned(std::move(fitted)),
        s(owned ? *owned : sc),
        plant(s),
        ode(plant, s.run, inputs),
        cfg(makeBmsConfig(s)),
        hw(s, plant),
        rng(s.run.seed),
        sig(plant.makeSignals()),
        tracker(s, plant, cfg),
        scheduler(s, plant),
        tick_s(s.bms.tick_s),
        recordEvery(std::max(1L, std::lround(s.output.interval_s / s.bms.tick_s))),
        end_s(s.endTime_s()),  // past it (a driver's run) the integrators clamp t_stop to t_out
        lastTick(end == RunEnd::Driver ? std::numeric_limits<long>::max()
                                       : static_cast<long>(std::floor(s.endTime_s() / s.bms.tick_s + 1e-9))),
        driverEnds(end == RunEnd::Driver) {
    firmware.enforceBudgets(budgets == Budgets::Enforced);
    inputs.faults = &faults;  // healthy until a scripted injection switches something on
    inputs.load = s.load.segmentAt(0.0);
    if (s.run.solver == RunConfig::Solver::Fast)
      solver = std::make_unique<FastIntegrator>(plant, inputs,
                                                FastSettings{s.run.fast_max_substep_s, s.run.fast_substep_fraction});
    else
      solver = std::make_unique<CvodeIntegrator>(ode, s.run.rtol,
                                                 s.run.jacobian == RunConfig::Jacobian::Diagonal
                                                     ? CvodeIntegrator::Newton::Diagonal
                                                     : CvodeIntegrator::Newton::Sparse);

    std::vector<double> x(static_cast<size_t>(ode.size()), 0.0);
    plant.initialState(x.data());
    solver->reset(0.0, x.data());

    tracker.setHardware(&hw);
    // What the loader found questionable in the scenario (core/scenario/scenario_warnings.hpp).
    for (const std::string& w : s.warnings) tracker.event(0.0, "config_warning", w);
    // A balancing stop threshold below what the measurement noise of N channels allows.
    if (const std::string w = balanceNoiseWarning(s); !w.empty()) tracker.event(0.0, "config_warning", w);
    scheduler.reset(faults);
    if (s.vehicle.present) {  // a vehicle decides the power load each tick (core/sim/vehicle_run.hpp)
      vehicle = std::make_unique<VehicleRun>(s.vehicle, tick_s, s.bms.image.chargeFullCell_mV / 1000.0);
      tracker.setVehicle(&vehicle->sample());
    }
  }

  bool tick(const StopCondition& stopWhen);
  void advance();

  const std::shared_ptr<const Scenario> owned;  // the scenario with a fitted read-out period, if it needed one
  const Scenario& s;
  const Plant plant;
  HardwareFaults faults;
  PlantInputs inputs;
  PlantOde ode;
  std::unique_ptr<Integrator> solver;
  const bms::Config cfg;
  HardwareSim hw;  // monitor ICs, sensors, relay, FETs, fuse, precharge (bms_bridge)
  bms::Inputs in{};
  bms::Outputs out{};                  // the host's pin writes (and the boards' merged outputs)
  const bms::Outputs* decided = &out;  // the last tick's decisions (McuFirmware::decide)
  Rng rng;
  PlantSignals sig;
  RunTracker tracker;
  FaultScheduler scheduler;
  McuFirmware firmware{s, cfg, hw, tracker};  // packsim's core, or the scenario's library
  PinTimeline pins;  // the MCU's output changes not yet in effect (core/firmware/pin_timeline.hpp)
  bms::Outputs act{};  // step 3's scratch: the decisions with other pins in effect
  const double tick_s;
  const int stateCount = ode.size();  // the state checkFinite looks at each tick (no virtual call for it then)
  const long recordEvery;
  const double end_s;
  const long lastTick;
  const bool driverEnds;
  ExternalInputs ext;
  std::unique_ptr<VehicleRun> vehicle;  // `load: {vehicle: ...}`: null otherwise
  LoadShortfall shortfall{s.load.quantity == LoadProfile::Quantity::Power_W && !s.vehicle.present, tick_s};
  const LoadShortfall::Sink shortfallSink = [this](double te, const std::string& d) {
    tracker.event(te, "load_limited", d);
  };
  const PlantSignals* sampled = nullptr;  // the signals of the last tick
  bool restartNext = false;               // an input of the plant jumped at the last tick
  long k = 0;
  long recordPhase = 0;  // k % recordEvery, kept along with k (no division per tick)
  bool ended = false;
  std::string endReason = "it was stopped";  // why the run ended (for unreached faults)
};

bool SimulationRun::Impl::tick(const StopCondition& stopWhen) {
  if (ended) return false;
  Integrator& integ = *solver;
  const double t = static_cast<double>(k) * tick_s;
  if (vehicle) {  // the vehicle moves over the last tick and asks its power for the next
    PackSource pack;
    plant.thevenin(integ.state(), inputs, pack.e_V, pack.r_ohm);
    ext.load_A_or_W = vehicle->tick(t, integ.state()[plant.stateSize() + kQuadLoadEnergy_J], pack,
                                    decided->state == bms::State::Normal, decided->telemetry.maxCell_mV * 1e-3, tracker);
  }
  if (ext.applyToPlant(t, inputs)) integ.reset(t, integ.state());  // external inputs, if any
  const double* xs = integ.state();

  // 1. scripted faults due at t_k switch on (or off); then sample the truth at t_k
  //    (the fast integrator's last evaluation already sits at (t_k, x_k) under these
  //    inputs unless it restarted since: no second evaluation of the same point). Every
  //    reader here and in step 5 takes currents, voltages and temperatures, none the heat
  //    (Plant::sample leaves it out: some 1,600 instructions a tick on A, 12 cells).
  const PlantSignals* now = integ.signalsAt(t);
  const bool reuse = now != nullptr;
  if (!reuse) plant.sample(t, xs, inputs, sig);
  const bool faultChanged = scheduler.update(t, xs, reuse ? *now : sig, faults, tracker);
  if (faultChanged) plant.sample(t, xs, inputs, sig);
  if (!reuse || faultChanged) now = &sig;
  const PlantSignals& sg = *now;  // valid until the plant advances (step 5)
  hw.sample(t, sg, hw.measurementView(t, xs, inputs, sg), faults, rng, in);
  ext.applyToPins(in);
  if (shortfall.watching())  // a power load only: a current load is always given
    shortfall.tick(t, inputs.load.current_A(t), sg.pack_voltage_V * sg.pack_current_A,
                   inputs.relay_closed && !inputs.discharge_blocked, shortfallSink);

  // 2. the firmware decides: its tasks due in [t_k, t_k+1) run on the MCU's clock,
  //    talking to the monitor chain over the bus (a hung MCU does not: its pins hold
  //    their last level, and only the monitor ICs' own FAULT line can still open the
  //    relay)
  decided = &firmware.decide(t, in, out, faults);
  const bms::Outputs& decision = *decided;
  const std::vector<PinChange> written = firmware.takePinChanges();
  tracker.pinsWritten(written);  // a user's firmware's relay commands, at their instants
  for (const PinChange& c : written) pins.push(c);

  // 3. actuators: the commands in effect at t_k (those the firmware wrote at or before
  //    it; later ones act inside the tick, step 5) drive the switching hardware
  //    (delays, weld, fuse, FETs, precharge) whose state the plant sees from t_k
  // (the decisions with the pins in effect: a copy only when those differ from them)
  const PinLevels& inEffect = pins.at(t);
  const bool pinsDiffer = pinsOf(decision) != inEffect;
  if (pinsDiffer) {
    act = decision;
    applyPins(act, inEffect);
  }
  const bool relayChanged = hw.actuate(t, pinsDiffer ? act : decision, sg, faults, inputs);
  if (scheduler.watching()) scheduler.noteEffects(pathState(inputs, hw, sg, s));
  sampled = &sg;
  restartNext = relayChanged || faultChanged;

  // 4. record
  tracker.tick(t, xs, sg, decision);
  const bool stop = k >= lastTick || (!driverEnds && (tracker.stopRequested(t) || hw.chargeComplete())) ||
                    (stopWhen && stopWhen(t, xs, sg, decision)) || (vehicle && vehicle->done());
  if (recordPhase == 0 || stop) {
    tracker.record(t, xs, sg, decision);
    if (vehicle) vehicle->recorded(t);  // its array powers are means over the recording interval
  }
  if (stop) {
    ended = true;
    endReason = k >= lastTick                    ? kRunEndScheduled
                : !driverEnds && tracker.stopRequested(t) ? afterTripText(s.run.stop_after_trip_s)
                : !driverEnds && hw.chargeComplete()      ? "the charge was complete"
                : vehicle && vehicle->done()              ? vehicle->endReason()
                                                          : "it was stopped";
    return false;
  }
  return true;
}

void SimulationRun::Impl::advance() {
  // 5. advance the plant to t_k+1, stopping exactly at every input discontinuity in
  //    between -- a load breakpoint, a scripted fault starting or ending -- wherever it
  //    falls in the tick; one that rounding puts within a sliver of t_k+1
  //    (core/sim/same_instant.hpp) is taken at t_k+1
  Integrator& integ = *solver;
  const double t = static_cast<double>(k) * tick_s;
  const double t_next = static_cast<double>(k + 1) * tick_s;
  bool restart = restartNext;
  const bms::Outputs& decisions = *decided;  // the tick's (unchanged here); their pins applied at their instants
  if (ext.applyToPlant(t, inputs)) restart = true;  // set since the tick at t_k
  sampled = nullptr;
  double tc = t;
  while (tc < t_next) {
    if (restart) integ.reset(tc, integ.state());
    restart = false;
    const double loadBreak_s = inputs.load.t1_s;
    const double faultBreak_s = scheduler.nextChange_s(tc);
    const bool faultInside = !reached(faultBreak_s, t_next);
    // An MCU output written inside the tick, or a relay contact whose delay runs out
    const double pinBreak_s = std::min(pins.next_s(), hw.nextSwitch_s(tc));
    const bool pinInside = !reached(pinBreak_s, t_next);
    double t_to = reached(loadBreak_s, t_next) ? t_next : loadBreak_s;
    // CVODE never steps past the next load breakpoint (nor past the run's end); a fault
    // at the tick needs no stop of its own: the tick restarts the integrator there.
    double t_stop = std::min(loadBreak_s, end_s + tick_s);
    if (faultInside && faultBreak_s < t_to) t_to = t_stop = faultBreak_s;
    if (pinInside && pinBreak_s < t_to) t_to = t_stop = pinBreak_s;
    integ.advance(t_to, std::max(t_stop, t_to));
    tc = t_to;
    if (reached(tc, inputs.load.t1_s)) {  // the load's next piece (past any sliver-short one)
      while (reached(tc, inputs.load.t1_s)) {
        const double t1 = inputs.load.t1_s;
        inputs.load = s.load.segmentAt(t1);
        if (!(inputs.load.t1_s > t1)) throw std::logic_error("load profile: no piece after t = " + std::to_string(t1) + " s");
      }
      restart = true;
      // Past a profile's last lap the load is zero: said where the run goes on after it.
      if (std::isinf(inputs.load.t1_s) && !vehicle && !reached(inputs.load.t0_s, end_s))
        tracker.event(inputs.load.t0_s, "load_end", loadEndText(s.load));
    }
    if (faultInside && reached(tc, faultBreak_s)) {  // a timed fault starts or ends here
      plant.sample(tc, integ.state(), inputs, sig);
      if (scheduler.update(tc, integ.state(), sig, faults, tracker)) restart = true;
      if (scheduler.watching()) scheduler.noteEffects(pathState(inputs, hw, sig, s));
    }
    if (pinInside && reached(tc, pinBreak_s)) {  // the outputs act at the instant they were written
      plant.sample(tc, integ.state(), inputs, sig);
      act = decisions;
      applyPins(act, pins.at(tc));
      if (hw.actuatePins(tc, t_next, act, sig, faults, inputs)) restart = true;
      tracker.hardwareChanged(tc);
      if (scheduler.watching()) scheduler.noteEffects(pathState(inputs, hw, sig, s));
    }
  }
  if (restart) integ.reset(tc, integ.state());
  tracker.checkFinite(t_next, integ.state(), stateCount);
  ++k;
  if (++recordPhase == recordEvery) recordPhase = 0;
}

SimulationRun::SimulationRun(const Scenario& s, RunEnd end, Budgets budgets)
    : impl_(std::make_unique<Impl>(budgets == Budgets::Enforced ? readoutThatFits(s) : nullptr, s, end, budgets)) {}
SimulationRun::~SimulationRun() = default;

bool SimulationRun::step(const StopCondition& stopWhen) {
  if (!impl_->tick(stopWhen)) return false;
  impl_->advance();
  return true;
}
bool SimulationRun::tick(const StopCondition& stopWhen) { return impl_->tick(stopWhen); }
double SimulationRun::worstTaskTime_s(int task) const { return impl_->firmware.worstTaskTime_s(task); }
void SimulationRun::advance() {
  if (!impl_->ended) impl_->advance();
}
void SimulationRun::setExternalInputs(const ExternalInputs& in) { impl_->ext = in; }
const Plant& SimulationRun::plant() const { return impl_->plant; }
const double* SimulationRun::state() const { return impl_->solver->state(); }
const PlantSignals& SimulationRun::signals() const { return impl_->sampled ? *impl_->sampled : impl_->sig; }
const bms::Outputs& SimulationRun::outputs() const { return *impl_->decided; }
const HardwareStatus& SimulationRun::hardware() const { return impl_->hw.status(); }
bool SimulationRun::tripped() const { return impl_->tracker.tripped(); }
double SimulationRun::time_s() const { return static_cast<double>(impl_->k) * impl_->tick_s; }
bool SimulationRun::ended() const { return impl_->ended; }

RunResult SimulationRun::finish() {
  Impl& m = *impl_;
  const double end_s = static_cast<double>(m.k) * m.tick_s;
  // Before the run's end event: faults never reached, a power load's last shortfall, the
  // MCU's thermistors the firmware never read.
  m.scheduler.reportUnreached(end_s, m.endReason, m.tracker);
  m.scheduler.reportNoEffect(end_s, m.tracker);
  m.shortfall.finish(end_s, m.shortfallSink);
  for (const std::string& note : unreadMcuThermistors(m.s, m.hw.boards(), m.firmware.mcuThermistorsRead(), end_s))
    m.tracker.event(end_s, "monitor_unread", note);
  RunResult r = m.tracker.finish(m.solver->state() + m.plant.stateSize(), m.endReason);
  if (m.s.hardware.balancing.present) {
    std::vector<double> x0(static_cast<size_t>(m.plant.stateSize()), 0.0);
    m.plant.initialState(x0.data());
    r.summary.balance = summarizeBalancing(m.s, m.plant, x0.data(), m.solver->state(), r.quad, r.events);
  }
  r.bus_trace = m.hw.takeBusTrace();
  r.can_trace = m.firmware.takeCanTrace();
  r.solver = m.solver->stats();
  r.summary.firmware_status = m.firmware.status();
  r.summary.fet_notes = m.hw.fetNotes(static_cast<double>(m.k) * m.tick_s);
  r.summary.firmware_target = m.firmware.host().targetSummary(static_cast<double>(m.k) * m.tick_s);
  r.summary.firmware_target_figures = m.firmware.host().targetFigures(static_cast<double>(m.k) * m.tick_s);
  if (m.vehicle) r.summary.vehicle = m.vehicle->summary(static_cast<double>(m.k) * m.tick_s);
  compareWithReference(m.s, r);  // the `compare:` reference run, if the scenario names one
  return r;
}

RunResult runScenario(const Scenario& s, const StopCondition& stopWhen) {
  SimulationRun run(s);
  while (run.step(stopWhen)) {
  }
  return run.finish();
}

}  // namespace packsim
