// Watches a run tick by tick: turns changes of the BMS outputs into events, keeps the
// extremes for the summary (lowest cell, hottest cell, trip), and records samples at
// the output interval.
#pragma once
#include <bms/bms_config.hpp>
#include <bms/bms_hal.hpp>

#include "core/scenario/scenario.hpp"
#include "core/sim/plant.hpp"
#include "core/sim/result.hpp"
#include "core/sim/bms_bridge.hpp"
#include "core/sim/cell_model_range.hpp"
#include "core/sim/false_fault.hpp"
#include "core/sim/limit_watch.hpp"
#include "core/firmware/pin_timeline.hpp"

namespace packsim {

class RunTracker {
 public:
  RunTracker(const Scenario& s, const Plant& plant, const bms::Config& cfg);
  RunTracker(const RunTracker&) = delete;  // limitSink_ holds `this`
  RunTracker& operator=(const RunTracker&) = delete;

  void tick(double t, const double* x, const PlantSignals& sig, const bms::Outputs& out);
  void record(double t, const double* x, const PlantSignals& sig, const bms::Outputs& out);
  bool stopRequested(double t) const {  // (inline: asked every tick)
    return r_.summary.tripped && t >= r_.summary.trip_time_s + s_.run.stop_after_trip_s;
  }
  bool tripped() const { return r_.summary.tripped; }
  // Throws if the integration produced a non-finite state.
  void checkFinite(double t, const double* x, int n) const;
  // endReason: why the run ended (the `run` event's detail after "end: ").
  RunResult finish(const double* quadratures, const std::string& endReason);
  void event(double t, const std::string& kind, const std::string& detail);
  // A user's firmware wrote its output pins (each change at its MCU-clock instant): its
  // `relay` command events, at those instants (packsim's core's come from its outputs).
  void pinsWritten(const std::vector<PinChange>& changes);
  // A library firmware reported a trip (its event "trip: <reason>"); the first one is
  // the summary's trip (packsim's core trips through its latched faults instead).
  void firmwareTrip(double t, const std::string& reason);
  // Events for what the switching hardware did since the last call (contacts, fuse,
  // FAULT line, charger, active balancer), at t: each tick, and inside a tick at the
  // instant an MCU output or a relay's delay moved a contact.
  void hardwareChanged(double t);
  // The switching hardware and monitors whose actual state is recorded (bms_bridge).
  void setHardware(const HardwareSim* hw);
  // A vehicle run's state, recorded with every sample (/vehicle channels).
  void setVehicle(const VehicleSample* v);

 private:
  // The events of the rows of the firmware's outputs (run_tracker.cpp kOutputEdges)
  // that report what the hardware did (report) or the firmware's decisions (!report).
  void outputEvents(double t, const bms::Outputs& out, bool report);
  void noteLimit(double t, const double* x, int cell, bool byTrip = false);
  void noteSocRange(double t, const double* x, int cell);
  // The BMS switched the charger on or off this tick: its event, with the truth when off.
  void noteCharger(double t, const double* x, const PlantSignals& sig, bool on);
  // State estimation against the truth (issue 17).
  void judgeEstimates(const double* x, const PlantSignals& sig, const bms::Outputs& out);

  const Scenario& s_;
  const Plant& plant_;
  const bms::Config& cfg_;
  const bool core_;          // packsim's core runs (not a user's firmware): kOutputEdges applies
  bool relayPin_ = false;    // a user's firmware's relay pin as last written
  RunResult r_;
  bool first_ = true;
  uint64_t lastOutput_[8] = {};  // per row of kOutputEdges: its field at the last tick
  bool chargerOn_ = false;       // the BMS's charger enable at the last tick (runs with a charger)
  std::vector<double> limitSoc_;  // SOC of every cell when the first one hit its limit
  double lastT_ = 0.0;
  const double* lastX_ = nullptr;
  // Energy into the pack at its terminals (regeneration, a charger): the load-energy
  // quadrature's falls from tick to tick, and its value at the last tick.
  double energyIn_J_ = 0.0, lastLoadEnergy_J_ = 0.0;
  void takeEnergyIn(double loadEnergy_J);
  const HardwareSim* hw_ = nullptr;
  const VehicleSample* vehicle_ = nullptr;
  HardwareStatus lastHw_;
  SocErrorTracker socErrorCoulomb_, socErrorEkf_;
  int32_t displayAt_mV_ = -1;  // trueDisplayBars's input last tick (-1: none yet) and its bars
  uint8_t displayBars_ = 0;
  std::vector<uint8_t> socOut_;  // per cell: 1 went below SOC 0, 2 went above SOC 1
  LimitWatch limits_;            // cells past a protection limit the BMS has not seen
  CellModelRange modelRange_;    // cells past the temperatures the cell model stands for
  FalseFaultWatch falseFaults_;  // protections the BMS raised on readings the cells did not have
  LimitWatch::EventSink limitSink_;  // its events: limit_unseen (made once, not per tick)
  FalseFaultWatch::EventSink falseFaultSink_;  // false_fault, likewise
  // register_misuse: per board, the misuse entries already reported, and each one's
  // event (its count is filled in at the end)
  struct MisuseReported {
    int board;
    size_t entry, event;
  };
  std::vector<size_t> misuseSeen_;
  std::vector<MisuseReported> misuseEvents_;
  // Each board's misuse log (its monitor part's own, where it stays for the run), taken
  // once by setHardware: read through it each tick instead of the two out-of-line calls
  // down to the part (some 40 instructions a tick).
  std::vector<const std::vector<RegisterMisuse>*> misuseLogs_;
  void noteMisuse();
  std::string misuseDetail(int board, const RegisterMisuse& m) const;
  std::vector<double> cellTemp_C_;
  std::vector<double> cellMin_V_;  // each cell's v_min_V, in a row for the per-tick scan
  double highestMin_V_ = -INFINITY;  // the highest of them
  // Each cell's temperature and SOC in the state (Plant::tempIndex, cellStates), likewise
  std::vector<size_t> cellTempIndex_, cellSocIndex_;
};

}  // namespace packsim
