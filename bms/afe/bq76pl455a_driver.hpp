// packsim's BQ76PL455A driver: the command sequences a BMS firmware sends over the
// UART daisy chain, through the firmware contract's bus_transfer only (frame format,
// registers and CRC in bq76pl455a_regs.h). Freestanding: no heap, no globals; the
// caller owns the config and the state.
//
//   pl455Init:        auto-address (DEVCONFIG, DEV_CTRL auto-address, one broadcast ADDR
//                     write per device, read-back), then configure every device: channel
//                     select, oversampling, comparator, ADC and AUX thresholds, FAULT
//                     output mask; clear the faults latched at power-up
//   pl455ReadAll:     one broadcast sample (all devices convert together), wait the
//                     conversion time, then per device: STATUS + FAULT_SUM, then the held
//                     results; a bad CRC is retried up to crcRetries times, a timeout is not
//   pl455PollFaults:  STATUS + FAULT_SUM only, per device (between read-outs)
//   pl455ClearFaults: write 1s to every FAULT_SUM group (broadcast)
//   pl455WriteBalance: CBCONFIG time + CBENBL mask per device; the device ends it
#pragma once
#include <stdint.h>

#include "../bms_afe.hpp"
#include "../packsim_fw.h"
#include "bq76pl455a_regs.h"

namespace bms {

struct Pl455Config {
  uint8_t bus;                   // PSFW_BUS_MONITOR(n)
  uint8_t deviceCount;           // 1..16
  uint8_t cellsPerDevice;        // the last device may hold fewer
  uint16_t cellCount;
  uint8_t thermistorsPerDevice;  // AUX inputs read, 0..8 (AUX0 up)
  float cellLsb_uV;              // VCELL scaling as flashed (5 V / 65535 nominal)
  uint8_t oversamplingLog2;      // OVERSMPL: 2^n samples averaged per channel
  bool comparators;              // secondary comparators on, driving the FAULT line
  uint8_t commTimeoutCode;       // CTO fault timer code (0 off): a device that hears no frame
                                 // for that long drives the FAULT line too
  // Thresholds written at init; 0 keeps the device's EEPROM values.
  uint16_t compUv_mV, compOv_mV; // comparator thresholds (25 mV steps)
  uint16_t cellUv_mV, cellOv_mV; // ADC checks on every sample
  uint16_t auxHotCode;           // AUX code below which an NTC input is over temperature
  uint8_t crcRetries;            // extra attempts after a bad CRC
};

// A request with response to one device: command, address, register, one data byte, CRC.
constexpr uint8_t kPl455RequestLen = 6;
// A broadcast write of one register: command, register, one data byte, CRC.
constexpr uint8_t kPl455BroadcastLen = 5;

struct Pl455State {
  uint8_t devicesFound;     // answered the address read-back at init
  uint32_t crcRetriesUsed;  // since init
  uint32_t readouts;
  FrameResult last[kMaxDevices];
  // The read-out's command frames, built at init (their bytes never change): the sample
  // broadcast, and per device the STATUS + FAULT_SUM read and the held results' send.
  uint8_t sampleCommand[kPl455BroadcastLen];
  uint8_t statusRequest[PL455_MAX_DEVICES][kPl455RequestLen];
  uint8_t heldRequest[PL455_MAX_DEVICES][kPl455RequestLen];
};

// Time one sample of a device takes: channels x oversamples x 100 us.
uint32_t pl455ConversionTime_us(const Pl455Config& c, uint8_t device);
// Cells held by device d.
uint8_t pl455CellsOf(const Pl455Config& c, uint8_t device);
// CBCONFIG time code for a request: the longest time not above it (at least the shortest).
uint8_t pl455BalanceTimeCode(uint32_t time_s);

// Returns the number of devices that took their address.
uint8_t pl455Init(const Pl455Config& c, Pl455State& s, psfw_board* b, const psfw_board_api* api);
// Fills out[d] and result[d] for every device (out[d] only where result[d] is Ok).
void pl455ReadAll(const Pl455Config& c, Pl455State& s, psfw_board* b, const psfw_board_api* api, DeviceReading* out,
                  FrameResult* result);
// STATUS + FAULT_SUM of every device: a quick poll between read-outs. Updates only
// io[d]'s fault, alert, safetyA and safetyB, and only where result[d] is Ok.
void pl455PollFaults(const Pl455Config& c, Pl455State& s, psfw_board* b, const psfw_board_api* api, DeviceReading* io,
                     FrameResult* result);
// Returns false if the bus refused the frame.
bool pl455ClearFaults(const Pl455Config& c, psfw_board* b, const psfw_board_api* api);
// balanceMask: one bit per cell of the whole chain (kBalanceWords words), bottom first.
bool pl455WriteBalance(const Pl455Config& c, psfw_board* b, const psfw_board_api* api, const uint32_t* balanceMask,
                       uint32_t time_s);

}  // namespace bms
