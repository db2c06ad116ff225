// The core's monitor ICs: one interface over the registered parts' drivers, dispatched
// through the driver table (bms_afe_driver.hpp) of the part Config::afe.part names. The
// drivers speak the parts' own frames and CRCs through the firmware contract
// (packsim_fw.h) and take the stack's shape from AfeConfig; good readings go straight
// into the acquisition (a device that fails keeps its last good reading) and each
// read's result is counted there.
//
//   init         the part's init (address and configure the stack) and one full
//                read-out, so the core has data at its first control tick
//   read-out     every device in full (a part's driver may service timers here, e.g.
//                re-arm balancing)
//   alerts       the protection flags alone (between read-outs)
//   clear        the devices' latched flags (a latch whose condition is still present
//                stays: the device decides)
//   balance      the mask and timer
//   FETs         only a part with its own FETs (AfeDriverApi::writeFets)
//
// Freestanding: no heap, no globals; MonitorDrivers lives in the firmware's RAM.
#pragma once
#include <cstdint>

#include "bms_afe_driver.hpp"
#include "bms_config.hpp"
#include "bms_measure.hpp"
#include "packsim_fw.h"

namespace bms {

struct MonitorDrivers {
  alignas(8) uint8_t data[kAfeDataBytes];  // the part's driver state (its own struct, placed by its init)
  bool configured;                         // every device took its address and configuration at init
};

// The registered driver of Config::afe.part (nullptr: none).
inline const AfeDriverApi* apiOf(const Config& c) {
  const AfeDriver* d = afeDriver(c.afe.part);
  return d != nullptr ? d->api : nullptr;
}
// Whether Config::afe.part names a registered driver (an image that does not is refused).
bool monitorPartKnown(const Config& c);
// Whether the part drives FETs of its own (the core then writes them when they change).
// (Inline: asked at every control tick.)
inline bool monitorHasFets(const Config& c) {
  const AfeDriverApi* p = apiOf(c);
  return p != nullptr && p->writeFets != nullptr;
}

bool monitorInit(const Config& c, MonitorDrivers& m, AcquisitionState& a, psfw_board* b, const psfw_board_api* api);
void monitorReadAll(const Config& c, MonitorDrivers& m, AcquisitionState& a, psfw_board* b, const psfw_board_api* api);
void monitorPollAlerts(const Config& c, MonitorDrivers& m, AcquisitionState& a, psfw_board* b,
                       const psfw_board_api* api);
void monitorClearFaults(const Config& c, MonitorDrivers& m, psfw_board* b, const psfw_board_api* api);
// mask: one bit per series cell (kBalanceWords words); time_s: the devices' timer.
void monitorWriteBalance(const Config& c, MonitorDrivers& m, psfw_board* b, const psfw_board_api* api,
                         const uint32_t* mask, uint32_t time_s);
void monitorWriteFets(const Config& c, MonitorDrivers& m, psfw_board* b, const psfw_board_api* api, bool chargeOn,
                      bool dischargeOn);

}  // namespace bms
