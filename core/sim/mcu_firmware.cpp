#include "core/sim/mcu_firmware.hpp"

#include <bms/bms_firmware.hpp>

namespace packsim {

namespace {

FirmwareHost makeHost(const Scenario& s, const bms::Config& cfg, HardwareSim& hw, FirmwareSink& sink) {
  if (s.bms.firmware.library)
    return FirmwareHost(s.bms.firmware, hw.monitorBuses(), s.bms.tick_s, hw.mcuThermistorCount(), sink);
  return FirmwareHost(bms::coreFirmware(), coreImage(cfg), hw.monitorBuses(), s.bms.tick_s, hw.mcuThermistorCount(),
                      sink);
}

}  // namespace

McuFirmware::McuFirmware(const Scenario& s, const bms::Config& cfg, HardwareSim& hw, RunTracker& tracker)
    : tracker_(tracker), library_(s.bms.firmware.library), host_(makeHost(s, cfg, hw, *this)) {}

void McuFirmware::decide(double t_s, const bms::Inputs& in, bms::Outputs& out) {
  host_.step(t_s, in, out);
  if (!library_ && host_.ram()) out = bms::coreFirmwareOutputs(host_.ram());
}

}  // namespace packsim
