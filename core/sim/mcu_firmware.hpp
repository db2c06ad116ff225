// Step 2 of a tick: the firmware on the simulated BMS microcontrollers, run by the
// firmware host (core/firmware) on the run's hardware. Either packsim's own core
// (bms/bms_firmware.hpp, flashed with makeBmsConfig's image) or, when the scenario names
// one (bms.firmware), a user's library. Both see the board only through the contract.
//
// A pack of several monitor boards (hardware.afe.devices_per_board) has one MCU per
// board, each running packsim's core for its board (core/scenario/monitor_boards.hpp),
// all on one CAN bus (core/firmware/can_bus.hpp); board 0's is the pack host, wired to
// the pack's pins. They run one after another in each tick.
//
// packsim's core runs as linked-in code (host mode) or, with bms.firmware.target and no
// elf, as packsim_core_cm4.elf on the virtual MCU (target mode, one board), flashed with
// the same image.
//
// For packsim's core a debug probe reads each MCU's outputs of the tick from its RAM
// for the record (state, faults, telemetry, balancing decision): the pack host's, with
// every board's cells, temperatures, devices and balancing bits at their pack positions.
// The hosts' events go into the run's event log, a library's "trip: <reason>" events
// into the summary's trip.
#pragma once
#include <bms/bms_config.hpp>
#include <bms/bms_firmware.hpp>
#include <bms/bms_hal.hpp>

#include <memory>
#include <string>
#include <vector>

#include "core/firmware/can_bus.hpp"
#include "core/firmware/firmware_host.hpp"
#include "core/scenario/scenario.hpp"
#include "core/sim/bms_bridge.hpp"
#include "core/sim/result.hpp"
#include "core/sim/run_tracker.hpp"

namespace packsim {

class McuFirmware : public FirmwareSink {
 public:
  McuFirmware(const Scenario& s, const bms::Config& cfg, HardwareSim& hw, RunTracker& tracker);
  // The tasks due in [t, t + tick) with the pins sampled at t; out receives the pins
  // (and, for packsim's core, the rest of its outputs through the probe). A hung MCU
  // (host_dead) runs nothing: its pins hold their last level. A supply below the
  // brown-out threshold (supply_brownout) holds every MCU in reset, outputs off; they
  // boot at the first tick it is back (FirmwareHost::holdInReset).
  // Returns the tick's decisions: `out`, or (packsim's core on one board, host mode)
  // the outputs in the MCU's RAM, read in place instead of copied (a kilobyte and more
  // a tick), with their pins copied into `out`, where the host's next writes land.
  // Valid until the next decide().
  const bms::Outputs& decide(double t_s, const bms::Inputs& in, bms::Outputs& out, const HardwareFaults& f);
  // The pack host's output changes of the last decide(), each at the instant its
  // firmware wrote it (core/firmware/pin_timeline.hpp); the members' pins drive nothing.
  std::vector<PinChange> takePinChanges() { return hosts_.front()->takePinChanges(); }
  // "" while every MCU runs, else the first stopped one's line; a library's always.
  std::string status() const;
  const FirmwareHost& host(int board = 0) const { return *hosts_[static_cast<size_t>(board)]; }
  // Per board, the MCU-ADC thermistor inputs its firmware read (FirmwareHost::mcuThermistorsRead).
  std::vector<uint64_t> mcuThermistorsRead() const {
    std::vector<uint64_t> read;
    for (const auto& h : hosts_) read.push_back(h->mcuThermistorsRead());
    return read;
  }
  bool isLibrary() const { return library_; }
  bool anyDead() const;
  // The longest call of `task` on any board so far (FirmwareHost::worstTaskTime_s).
  double worstTaskTime_s(int task) const;
  void enforceBudgets(bool on);
  const CanBus* can() const { return can_.get(); }
  // A board alone with hardware.can: every frame on its bus (the firmware's, queued in
  // the run's ticks, and the scenario's), in the order they went on the wire.
  std::vector<CanTraceRow> takeCanTrace();

  void event(double t_s, const std::string& kind, const std::string& detail) override {
    tracker_.event(t_s, kind, detail);
  }
  void trip(double t_s, const std::string& reason) override { tracker_.firmwareTrip(t_s, reason); }

 private:
  const bms::Outputs& probe(bms::Outputs& out);

  RunTracker& tracker_;
  const HardwareSim& hw_;
  bool library_;
  double nominal_V_, brownout_V_;  // hardware.mcu_supply
  std::unique_ptr<CanBus> can_;                     // several boards, or a board alone with hardware.can
  // A board alone's bus: node 0 the MCU, node 1 the vehicle / charger sending the
  // scenario's frames, each copy queued in the tick before it is ready.
  std::vector<ScriptedCanFrame> scripted_;
  std::vector<double> nextScripted_s_;
  bool aloneCan_ = false;
  double tickFor_s_;
  void injectScripted(double before_s);
  std::vector<std::unique_ptr<FirmwareHost>> hosts_;  // per board, the pack host first
  std::vector<bms::Outputs> memberPins_;            // what the members' unconnected pins got
  std::string coreElf_;                               // target mode: the core's ELF
  std::unique_ptr<bms::CoreFirmwareRam> targetRam_;  // target mode: the probe's copy of the MCU's RAM
  const bms::Outputs* decided_ = nullptr;             // what the last decide() returned
};

}  // namespace packsim
