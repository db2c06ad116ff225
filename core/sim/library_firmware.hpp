// Step 2 of a tick when the scenario names a firmware library (bms.firmware): the
// firmware host (core/firmware) on the run's hardware, its events into the run's
// event log, its "trip: <reason>" events into the summary's trip.
#pragma once
#include <bms/bms_hal.hpp>

#include <string>

#include "core/firmware/firmware_host.hpp"
#include "core/scenario/scenario.hpp"
#include "core/sim/bms_bridge.hpp"
#include "core/sim/run_tracker.hpp"

namespace packsim {

class LibraryFirmware : public FirmwareSink {
 public:
  LibraryFirmware(const Scenario& s, HardwareSim& hw, RunTracker& tracker);
  void decide(double t_s, const bms::Inputs& in, bms::Outputs& out) { host_.step(t_s, in, out); }
  std::string status() const { return host_.status(); }
  const FirmwareHost& host() const { return host_; }

  void event(double t_s, const std::string& kind, const std::string& detail) override {
    tracker_.event(t_s, kind, detail);
  }
  void trip(double t_s, const std::string& reason) override { tracker_.firmwareTrip(t_s, reason); }

 private:
  RunTracker& tracker_;
  FirmwareHost host_;
};

}  // namespace packsim
