#include "core/sim/library_firmware.hpp"

namespace packsim {

LibraryFirmware::LibraryFirmware(const Scenario& s, HardwareSim& hw, RunTracker& tracker)
    : tracker_(tracker), host_(s.bms.firmware, hw.monitorBuses(), s.bms.tick_s, hw.mcuThermistorCount(), *this) {}

}  // namespace packsim
