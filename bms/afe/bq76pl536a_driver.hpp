// packsim's BQ76PL536A driver: the firmware side of a BQ76PL536A stack on one SPI
// bus, talking to it only through the firmware contract (psfw_board_api::bus_transfer,
// now_us/delay_us). Register layout: bq76pl536a_regs.h. Freestanding: no heap, no
// globals; the caller owns the config and the state.
//
//   init:      broadcast RESET; address the devices bottom-up (write ADDRESS_CONTROL
//              of address 0, read it back from the new address); clear POR / AR;
//              ADC_CONTROL (cells, GPAI, thermistors), IO_CONTROL (thermistor bias);
//              each CONFIG_COV..CONFIG_OTT behind its own shadow-write key, read back
//   read-out:  broadcast ADC_CONVERT, wait the conversion time, then per device read
//              DEVICE_STATUS..TEMPERATURE2 and ALERT_STATUS..CUV_FAULT (a bad CRC is
//              re-read up to crcRetries times; DRDY still clear is re-read after one
//              more conversion time)
//   poll:      ALERT_STATUS..CUV_FAULT only, per device (between read-outs)
//   clear:     write 1 then 0 to the latch bits (FAULT_STATUS, ALERT_STATUS)
//   balance:   per device CB_TIME then CB_CTRL (the device's timer switches them off)
#pragma once
#include <stdint.h>

#include "../bms_afe.hpp"
#include "../bms_limits.hpp"
#include "../packsim_fw.h"
#include "bq76pl536a_regs.h"

namespace bms {

struct Bq536Config {
  uint8_t bus;                   // PSFW_BUS_MONITOR(n)
  uint8_t deviceCount;           // 1..62
  uint8_t cellsPerDevice;        // 1..6 (the last device may hold fewer)
  uint16_t cellCount;
  uint8_t thermistorsPerDevice;  // 0..2 inputs biased and converted
  float cellLsb_uV;              // VCELL scaling as flashed (6250/16383 mV nominal)
  uint8_t crcRetries;            // extra reads of a reply that failed its CRC
  uint16_t conversionPerChannel_us;  // ADC timing the driver waits for
  // The devices' own comparators, written to CONFIG_* at init (datasheet steps).
  bool protectionEnabled;
  uint16_t cov_mV;
  uint32_t covDelay_us;
  uint16_t cuv_mV;
  uint32_t cuvDelay_us;
  int16_t ot_C;
  uint16_t otDelay_ms;
};

struct Bq536State {
  uint8_t addressed;   // devices that took their address at init (bottom-up)
  uint8_t configured;  // of those, devices whose CONFIG_* read back as written
  // The read-out's broadcast ADC_CONVERT frame, built by init: the same bytes and CRC at
  // every read-out (a CRC a read-out saved).
  uint8_t convertFrame[BQ536_WRITE_FRAME_LEN];
  uint32_t crcRetries;  // reads repeated after a bad CRC (diagnostics)
  uint32_t readouts;
};

// Power-up sequence. Returns true when every device is addressed and configured.
bool bq536Init(const Bq536Config& c, Bq536State& s, psfw_board* b, const psfw_board_api* api);
// One read-out of the whole stack: convert, wait, read each device. res[d] is Ok and
// out[d] filled only for a good reply.
void bq536ReadAll(const Bq536Config& c, Bq536State& s, psfw_board* b, const psfw_board_api* api,
                  DeviceReading* out, FrameResult* res);
// The protection flags alone (ALERT_STATUS .. CUV_FAULT of every device): a quick poll
// between full read-outs. Updates only io[d]'s fault, alert, safetyA and safetyB, and
// only where res[d] is Ok.
void bq536PollFlags(const Bq536Config& c, Bq536State& s, psfw_board* b, const psfw_board_api* api, DeviceReading* io,
                    FrameResult* res);
// Clears every device's latched protection and housekeeping flags (a latch whose
// condition is still present stays set: the device decides).
void bq536ClearFaults(const Bq536Config& c, psfw_board* b, const psfw_board_api* api);
// Balance switches (one bit per series cell) and the timer the devices enforce.
void bq536SetBalance(const Bq536Config& c, psfw_board* b, const psfw_board_api* api,
                     const uint32_t* mask /* kBalanceWords */, uint32_t time_s);

}  // namespace bms
