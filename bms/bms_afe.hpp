// What the core knows of its monitor ICs: the part class, the stack's shape as flashed,
// and one device's reading in firmware units. The bytes on the bus (frames, CRCs,
// registers) belong to the drivers in bms/afe/, which fill DeviceReading and report a
// FrameResult per device; the core never parses a frame itself.
#pragma once
#include <cstddef>
#include <cstdint>

#include "bms_limits.hpp"

namespace bms {

enum class AfeModel : uint8_t { Bq76pl536a = 0, Bq76pl455a = 1, Bq76952 = 2 };

// Shape of the monitor stack, as flashed into the firmware.
struct AfeConfig {
  AfeModel model;
  uint8_t deviceCount;
  uint8_t cellsPerDevice;        // the last device may hold fewer
  uint8_t thermistorsPerDevice;  // inputs in use per device (AFE thermistors)
  bool crcEnabled;               // BQ76952 only; the others always carry a CRC
  uint8_t commLossCount;         // consecutive bad read-outs of a device that mean "device lost"
};

// What one good read of a device says, in firmware units.
struct DeviceReading {
  uint16_t cell_mV[kMaxCellsPerDevice];
  uint16_t thermCode[kMaxThermPerDevice];  // ratiometric codes (PL536A/PL455A)
  int16_t temp_dC[kMaxThermPerDevice];     // converted by the device (BQ76952)
  uint32_t stack_mV;                       // module / stack voltage channel
  int16_t die_dC;
  bool fault;          // the device's own protection has latched (FAULT / safety status)
  bool alert;          // a threshold is crossed, not yet debounced
  uint8_t fetStatus;   // BQ76952 FET_STATUS
  uint8_t safetyA;     // BQ76952 SAFETY_STATUS_A (PL536A FAULT_STATUS, PL455A summary low byte)
  uint8_t safetyB;     // BQ76952 SAFETY_STATUS_B (PL536A ALERT_STATUS, PL455A summary high byte)
  int32_t current_mA;  // BQ76952 CC2
  int32_t charge_mAs;  // BQ76952 accumulated charge
};

// How a driver's read of one device ended. Timeout: nothing answered; BadLength,
// BadHeader, BadCrc: an answer that failed the driver's checks (a stuck 0x00 / 0xFF
// line shows as a bad header or CRC).
enum class FrameResult : uint8_t { Ok = 0, Timeout, BadLength, BadHeader, BadCrc };

// A cell ADC code in mV (rounded, clamped to 0..65535) at the flashed LSB.
uint16_t afeCellCodeToMv(uint16_t code, float lsb_uV);
// Cells held by device d (the last device may be partly populated).
uint8_t afeCellsOf(const AfeConfig& c, uint16_t cellCount, uint8_t d);

}  // namespace bms
