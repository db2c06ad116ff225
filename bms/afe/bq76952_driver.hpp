// packsim's firmware driver for the BQ76952 (one device per I2C bus), speaking the
// part's own protocol through the firmware contract (bms/packsim_fw.h): bus
// transactions, now_us / delay_us. Freestanding: no heap, no globals; the caller owns
// the driver state. Register layout: bms/afe/bq76952_regs.h.
//
//   configure:  DEVICE_NUMBER check; SET_CFGUPDATE, the protection thresholds and
//               delays into data memory (the part takes them only in CONFIG_UPDATE),
//               EXIT_CFGUPDATE, read-back of every value; FET_ENABLE if the part is in
//               FET test mode; clear the power-up alarms.
//   read-out:   DASTATUS6 (accumulated charge; its echo, length and checksum are the
//               reply's header), wait for a fresh measurement loop (Alarm Status
//               FULLSCAN) if asked, then three block reads (cells + stack + CC2,
//               safety alerts/status, temperatures + FET status); FULLSCAN cleared.
//               A bad CRC is retried `crcRetries` times; the result per device is a
//               bms::FrameResult and a bms::DeviceReading in firmware units, whose
//               sameLoop says FULLSCAN was clear (the loop read before, again) and
//               loopCurrent that CC2 is the current of the cells' loop.
//   poll:       Safety Alert/Status A..C and FET_STATUS only (between read-outs).
//   faults:     write 1s to Alarm Status (latched bits clear once their condition is gone).
//   balancing:  CB_ACTIVE_CELLS with the mask; the device ends balancing on its own one
//               Cell Balance Interval after the last write, so the driver re-arms it at
//               half the interval until the requested time is up, then writes 0.
//               With balancingConfig set the part balances on its own (configured
//               at configure with its thresholds); the host then writes no mask.
//   FETs:       ALL_FETS_ON / CHG_PCHG_OFF / DSG_PDSG_OFF / ALL_FETS_OFF.
// Signs: DeviceReading current and charge are positive in discharge (the part reports
// charge positive; the driver turns it round).
#pragma once
#include <stdint.h>

#include "../bms_afe.hpp"
#include "../packsim_fw.h"
#include "bq76952_regs.h"

namespace bms {

// The part's protections in firmware units (written to data memory at configure, in
// the part's steps; a value outside the part's range is written as its nearest limit:
// validate the configuration before it reaches the firmware).
struct Bq952ProtectionConfig {
  uint16_t cov_mV, covDelay_ms, covRecovery_mV;
  uint16_t cuv_mV, cuvDelay_ms, cuvRecovery_mV;
  uint16_t occ_mV, occDelay_ms;    // across the shunt
  uint16_t ocd1_mV, ocd1Delay_ms;  // across the shunt
  uint16_t scd_mV;                 // rounded to the nearest of the part's settings
  uint8_t currentRecovery_s;       // OCC / OCD1 / SCD recovery time
  int8_t otc_C, otd_C, otf_C, utc_C, utd_C;
  uint8_t otDelay_s, utDelay_s;
  uint8_t tempRecovery_C;          // hysteresis: recovery = threshold -/+ this
};

// The part's autonomous balancing (used when balancingConfig has BQ952_CB_CHG or
// BQ952_CB_RLX): the same thresholds for the charging and the relax case.
struct Bq952AutoBalanceConfig {
  int8_t minCellTemp_C, maxCellTemp_C, maxIntTemp_C;
  uint8_t maxCells;       // balanced at once
  uint16_t minCell_mV;    // only cells above this
  uint8_t startDelta_mV;  // start this far above the lowest cell
  uint8_t stopDelta_mV;   // stop here
};

struct Bq952DriverConfig {
  uint8_t deviceCount;          // one device per bus
  uint8_t firstBus;             // device d sits on bus firstBus + d
  uint8_t cellsPerDevice;       // the last device may hold fewer
  uint16_t cellCount;
  uint8_t thermistorsPerDevice; // TS1..TS3 in use
  bool crc;                     // the part's I2C CRC mode
  uint8_t crcRetries;           // further attempts after a bad CRC
  bool waitForScan;             // wait for a fresh measurement loop before reading
  uint32_t scanTimeout_us;      // give up waiting (the read-out goes on with the old loop)
  uint8_t userAmps;             // DA Configuration USER_AMPS (0..3: 0.1, 1, 10, 100 mA)
  bool writeProtections;        // configure the protections below (else keep the part's)
  Bq952ProtectionConfig protection;
  uint8_t balanceInterval_s;    // Cell Balance Interval written at configure (>= 2)
  uint8_t balancingConfig;      // Balancing Configuration (BQ952_CB_*); 0: host-controlled only
  Bq952AutoBalanceConfig autoBalance;
};

struct Bq952DeviceState {
  uint16_t balanceMask;       // as last written
  uint32_t balanceUntil_ms;   // the host's balancing time ends
  uint32_t balanceArmed_ms;   // last CB_ACTIVE_CELLS write
  uint8_t interval_s;         // the device's Cell Balance Interval
};

struct Bq952Driver {
  psfw_board* board;
  const psfw_board_api* api;
  uint32_t crcRetriesUsed;  // statistics: retried transactions
  Bq952DeviceState dev[kMaxDevices];
};

void bq952Init(Bq952Driver& drv, psfw_board* board, const psfw_board_api* api);
// Cells of device d under this configuration.
uint8_t bq952CellsOf(const Bq952DriverConfig& c, uint8_t d);
FrameResult bq952Configure(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d);
FrameResult bq952Read(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, DeviceReading& out);
// Safety Alert/Status A..C and FET_STATUS alone: the quick poll between read-outs.
// Updates only io's fault, alert, safetyA, safetyB and fetStatus, on Ok.
FrameResult bq952PollSafety(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, DeviceReading& io);
FrameResult bq952ClearFaults(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d);
// Starts (mask != 0) or stops balancing for time_s seconds from now.
FrameResult bq952SetBalance(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, uint16_t mask, uint32_t time_s);
// Called every read-out: re-arms running balancing, stops it when its time is up.
FrameResult bq952ServiceBalance(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d);
FrameResult bq952SetFets(Bq952Driver& drv, const Bq952DriverConfig& c, uint8_t d, bool chargeOn, bool dischargeOn);

}  // namespace bms
