// The core's monitor ICs: one interface over the three parts' drivers (bms/afe), the one
// AfeConfig::model names. The drivers speak the parts' own frames and CRCs through the
// firmware contract (packsim_fw.h); this layer gives them the stack's shape from
// AfeConfig, lets them write good readings straight into the acquisition (a device
// that fails keeps its last good reading) and counts each read's result there.
//
//   init         address and configure the stack (bq536Init / pl455Init /
//                bq952Configure) and make one full read-out, so the core has data at
//                its first control tick
//   read-out     every device in full; a BQ76952's balancing is serviced (re-armed)
//   alerts       the protection flags alone (between read-outs)
//   clear        the devices' latched flags (a latch whose condition is still present
//                stays: the device decides)
//   balance      the mask and timer, per device
//   FETs         BQ76952 only: the device drives CHG / DSG; others have none
//
// Freestanding: no heap, no globals; MonitorDrivers lives in the firmware's RAM.
#pragma once
#include <cstdint>

#include "bms_config.hpp"
#include "bms_measure.hpp"
#include "packsim_fw.h"

namespace bms {

struct MonitorDrivers {
  MonitorDriverConfig cfg;  // the flashed settings with the stack's shape filled in
  Bq536State pl536;
  Pl455State pl455;
  Bq952Driver bq952;
  bool configured;          // every device took its address and configuration at init
};

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
