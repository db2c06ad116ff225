// packsim's core as a stand-alone firmware: the contract's entry symbol, returning the
// core's descriptor (bms_firmware.hpp). packsim links the core in and calls
// coreFirmware() directly; this file is for a build of the core on its own, as
// packsim_core_cm4.elf for the virtual Cortex-M4 (bms.firmware.target, docs/firmware.md).
#include "bms_firmware.hpp"

extern "C" const psfw_firmware* psfw_firmware_entry(void) { return bms::coreFirmware(); }
