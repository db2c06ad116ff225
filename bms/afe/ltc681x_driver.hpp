// packsim's LTC6811-1 / LTC6813-1 driver: the firmware side of an isoSPI daisy chain on
// one SPI bus (through its isoSPI master), talking to it only through the firmware
// contract (psfw_board_api::bus_transfer, now_us / delay_us). Command set and register
// layout: ltc681x_regs.h. Freestanding: no heap, no globals; the caller owns the config,
// the state and the reading buffers.
//
//   wake-up:   before every command: after the watchdog's minimum time-out (1.8 s) of
//              silence, one wake-up pulse per device each followed by tWAKE (400 us), then
//              the configuration again (the watchdog reset it); after the isoSPI port's
//              minimum idle time (4.3 ms), one pulse per device each followed by tREADY
//   init:      wake, WRCFGA (+ WRCFGB) with REFON, ADCOPT, VUV/VOV, no discharge; wait the
//              reference's tREFUP; read CFGRA (+ CFGRB) back and compare
//   read-out:  ADCV (all cells, the configured MD / DCP), wait its conversion time, RDCVA..
//              as many groups as cells are used; ADAX (all GPIOs), wait, RDAUXA.. as many
//              groups as thermistors are used; RDSTATB (the cells' UV/OV flags), and with
//              readStatus ADSTAT + RDSTATA (sum of cells, die temperature). Every slot's PEC
//              is checked: a slot of all 1s is a device that did not answer (Timeout), any
//              other mismatch a BadCrc; each failed slot counts one PEC error for its device,
//              a group with a BadCrc is read again up to readRetries times. After a read-out
//              that lost a device the next one starts with the full wake-up from SLEEP and
//              the configuration (devices beyond a break heard nothing: idle or asleep)
//   balance:   DCC bits from the cell mask and DCTO from the timer (the smallest at least as
//              long), written with WRCFGA (+ WRCFGB): the devices enforce the timer
//   open wire: ADOW with the pull-up current twice, the cells read; twice with the
//              pull-down, read; the data sheet's rule per C pin
#pragma once
#include <stdint.h>

#include "../bms_afe.hpp"
#include "../bms_limits.hpp"
#include "../packsim_fw.h"
#include "ltc681x_regs.h"

namespace bms {

enum class LtcPart : uint8_t { Ltc6811 = 0, Ltc6813 = 1 };

// Devices one chain (one host) drives: its state and a reading per device must fit the
// core's block for a part's RAM (kAfeDataBytes, with LtcReading staging each device's
// groups until all of them passed). 16 LTC6813s hold 288 cells, more than a BMS image
// monitors (kMaxCells); a longer LTC6811 string is split over boards
// (hardware.afe.devices_per_board), each its own host and chain.
constexpr uint8_t kLtcMaxDevices = 16;

struct LtcConfig {
  uint8_t bus;                   // PSFW_BUS_MONITOR(n)
  LtcPart part;
  uint8_t deviceCount;           // 1..kLtcMaxDevices, device 0 nearest the MCU
  uint8_t cellsPerDevice;        // inputs C1..Cn in use, 1..12 (6811) / 1..18 (6813)
  uint16_t cellCount;            // the last device may hold fewer
  uint8_t thermistorsPerDevice;  // NTCs on GPIO1..n, 0..5 (6811) / 0..9 (6813)
  uint8_t adcMode;               // LTC681X_MD_FAST / _NORMAL / _FILTERED
  bool adcopt;                   // CFGRA ADCOPT: 14 kHz / 3 kHz / 2 kHz instead of 27 kHz / 7 kHz / 26 Hz
  bool dischargePermitted;       // ADCV's DCP bit
  bool readStatus;               // ADSTAT + RDSTATA each read-out (sum of cells, die temperature)
  uint16_t ov_mV;                // the devices' UV / OV comparators (CFGRA VOV, VUV)
  uint16_t uv_mV;
  uint8_t readRetries;           // extra reads of a group whose PEC failed on some device
  uint32_t period_us;            // the read-out's period: a recovery reads as well only within it (0: never)
};

// One device's results as its registers hold them (100 uV codes unless noted).
struct LtcReading {
  uint16_t cell[LTC681X_CELLS_MAX];
  uint16_t gpio[LTC681X_GPIOS_MAX];
  uint16_t ref;
  uint16_t sc;    // sum of cells / 20 (6811) or / 30 (6813)
  uint16_t itmp;  // die temperature code
  uint32_t ov;    // bit per cell input: above VOV at its last conversion
  uint32_t uv;
  uint8_t statb5;  // THSD, MUXFAIL
};

struct LtcState {
  uint32_t lastActivity_us;  // now_us of the last transfer
  bool woken;                // the chain has been woken since init
  uint8_t configured;        // devices whose configuration read back as written at init
  uint8_t cfga[kLtcMaxDevices][LTC681X_GROUP_BYTES];  // the image the driver writes, per device
  uint8_t cfgb[kLtcMaxDevices][LTC681X_GROUP_BYTES];
  uint32_t pecErrors[kLtcMaxDevices];  // slots that failed their PEC, per device
  uint32_t sleepWakeups;     // wake-ups from the core's SLEEP (configuration rewritten)
  uint32_t idleWakeups;      // wake-ups of the isoSPI ports
  uint32_t readouts;
  bool recover;              // the last read-out lost a device: wake the whole chain from SLEEP first
  uint32_t readout_us;       // how long the last read-out without a failure took (0: none yet)
  // One frame's scratch, in the firmware's RAM rather than on its stack (a full chain's slots).
  uint8_t tx[LTC681X_CMD_LEN + LTC681X_SLOT_BYTES * kLtcMaxDevices];
  uint8_t rx[LTC681X_SLOT_BYTES * kLtcMaxDevices];
  uint8_t group[kLtcMaxDevices][LTC681X_GROUP_BYTES];  // the last group read, per device
  FrameResult groupRes[kLtcMaxDevices];
};

// Power-up: wake, configure, read back. True when every device took its configuration.
bool ltcInit(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api);
// One read-out of the chain. res[d] is Ok and out[d] complete only when every group of
// device d passed its PEC.
void ltcReadAll(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, LtcReading* out,
                FrameResult* res);
// The cells' UV / OV flags alone (an alert poll): ADCV, then RDSTATB (+ RDAUXD on an
// LTC6813 with cells 13-18 in use); out[d].ov / uv written only where res[d] is Ok.
void ltcPollFlags(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, LtcReading* out,
                  FrameResult* res);
// Balancing switches (one bit per series cell, kBalanceWords words) and the discharge
// timer the devices enforce (0 s: timer off, the switches stay until changed or the
// watchdog resets them).
void ltcSetBalance(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, const uint32_t* mask,
                   uint32_t time_s);
// LTC6813: MUTE (every discharge switch off, DCC bits kept) or UNMUTE. No-op on the 6811.
void ltcSetMute(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, bool mute);
// The data sheet's open-wire check. openPins[d]: bit p set when C pin p (0..cells) of
// device d is open; pullUp / pullDown: scratch for the two passes' cell codes.
void ltcOpenWireCheck(const LtcConfig& c, LtcState& s, psfw_board* b, const psfw_board_api* api, LtcReading* pullUp,
                      LtcReading* pullDown, uint32_t* openPins, FrameResult* res);
// The conversion time (us) the driver waits for a command of `kind` over all channels.
uint32_t ltcConversionTime_us(const LtcConfig& c, enum ltc681x_conversion kind);
// A reading in the core's units: cells in mV, GPIO codes (100 uV; VREF2 = 30000 is the
// thermistor divider's full scale), the sum of cells in mV, die temperature in 0.1 degC;
// alert = a used cell outside VUV / VOV (the parts latch nothing: fault stays false);
// safetyA / safetyB = the OV / UV flags of cells 1-8.
// False when the device has more cells than DeviceReading holds (kMaxCellsPerDevice).
bool ltcToDeviceReading(const LtcConfig& c, uint8_t d, const LtcReading& r, DeviceReading& out);

}  // namespace bms
