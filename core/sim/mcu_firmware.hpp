// Step 2 of a tick: the firmware on the simulated BMS microcontroller, run by the
// firmware host (core/firmware) on the run's hardware. Either packsim's own core
// (bms/bms_firmware.hpp, flashed with makeBmsConfig's image) or, when the scenario names
// one (bms.firmware), a user's library. Both see the board only through the contract;
// for the core, a debug probe reads its outputs of the tick (state, faults, telemetry,
// balancing decision) from its RAM for the record. The host's events go into the run's
// event log, a library's "trip: <reason>" events into the summary's trip.
#pragma once
#include <bms/bms_config.hpp>
#include <bms/bms_hal.hpp>

#include <string>

#include "core/firmware/firmware_host.hpp"
#include "core/scenario/scenario.hpp"
#include "core/sim/bms_bridge.hpp"
#include "core/sim/run_tracker.hpp"

namespace packsim {

class McuFirmware : public FirmwareSink {
 public:
  McuFirmware(const Scenario& s, const bms::Config& cfg, HardwareSim& hw, RunTracker& tracker);
  // The tasks due in [t, t + tick) with the pins sampled at t; out receives the pins
  // (and, for packsim's core, the rest of its outputs through the probe).
  void decide(double t_s, const bms::Inputs& in, bms::Outputs& out);
  std::string status() const { return host_.status(); }
  const FirmwareHost& host() const { return host_; }
  bool isLibrary() const { return library_; }

  void event(double t_s, const std::string& kind, const std::string& detail) override {
    tracker_.event(t_s, kind, detail);
  }
  void trip(double t_s, const std::string& reason) override { tracker_.firmwareTrip(t_s, reason); }

 private:
  RunTracker& tracker_;
  bool library_;
  FirmwareHost host_;
};

}  // namespace packsim
