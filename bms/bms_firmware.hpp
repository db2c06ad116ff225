// packsim's BMS core as a firmware on the contract (packsim_fw.h): what would run on the
// microcontroller, and the only way the simulator runs the core. It sees the board as
// any other firmware does: monitor ICs over bus transactions (bms_monitor.hpp), the
// current-sense and bus ADC, thermistors on its own ADC, GPIO in and out.
//
//   configuration  the blob is a CoreImage: a tag, its size and the Config as flashed
//   init           tasks set to the configured rates; the monitor stack addressed,
//                  configured and read once; one control step (the power-up outputs)
//   task 0 read-out  every readout.period_ms: every device in full into the acquisition
//   task 1 alerts    every readout.alertPeriod_ms (not run when 0): the devices'
//                    protection flags alone (skipped when a read-out has just read them)
//   task 2 control   every tickPeriod_ms: ADC and GPIO in -> bms::step -> relay,
//                    precharge, FET and charger pins; then on the bus only what changed
//                    (balancing mask and timer, a fault clear, the monitor part's own FETs); the
//                    telemetry frame out
// Tasks due together run in that order, so a control tick sees a read-out of the same
// instant. All state is in CoreFirmwareRam, handed over by the board (no statics).
#pragma once
#include <cstdint>

#include "bms_core.hpp"
#include "bms_monitor.hpp"
#include "bms_telemetry.hpp"
#include "packsim_fw.h"

namespace bms {

constexpr uint32_t kCoreImageTag = 0x314D4350u;  // "PCM1": packsim core, image layout 1

// The configuration blob: what the flash holds.
struct CoreImage {
  uint32_t tag;    // kCoreImageTag
  uint32_t bytes;  // sizeof(CoreImage): an image of another build is refused
  Config cfg;
};

struct CoreFirmwareRam {
  Config cfg;
  CoreState core;
  MonitorDrivers monitors;
  Inputs in;
  Outputs out;
  uint32_t readoutDue_ms;               // when the last read-out started
  uint32_t writtenMask[kBalanceWords];  // balancing as last written to the devices
  uint8_t writtenArm;
  bool fetsWritten, writtenChg, writtenDsg;  // the monitor part's FETs as last commanded
  uint8_t telemetry[kTelemetryFrameBytes];
};

// The firmware's descriptor (what psfw_firmware_entry returns for a library firmware).
const psfw_firmware* coreFirmware();

// The core's outputs of its last control tick, read from its RAM as a debugger reads
// variables: the simulator records them (state, faults, telemetry); they act on the
// board only through the pins and the bus.
const Outputs& coreFirmwareOutputs(const void* ram);

// Task numbers of the descriptor.
enum CoreTask : uint32_t { kTaskReadout = 0, kTaskAlerts = 1, kTaskControl = 2 };

}  // namespace bms
