// Monitor-IC driver: frame layouts of the three supported monitor classes and the
// parser the firmware runs on every reply. The simulator's monitor models
// (models/afe) build frames with the same layout constants; the parser trusts
// nothing: length, header, address and CRC are all checked, and a device whose
// replies fail `commLossCount` times in a row is reported lost.
//
// BQ76PL536A-like (SPI, CRC-8), reply to a read of registers 0x00.. (big-endian):
//   [addr·2][reg 0x00][len][STATUS][GPAI 2][VCELL1..6 2 each][TEMP1 2][TEMP2 2]
//   [ALERT_STATUS][FAULT_STATUS][COV_FAULT][CUV_FAULT][DIE_TEMP 2][CRC-8 over all before]
//   cell mV = code · cellLsb; GPAI (module voltage) mV = code · 6 · cellLsb;
//   TEMPx ratiometric codes; DIE_TEMP signed 0.1 degC. Devices are auto-addressed 1..63.
// BQ76PL455A-like (UART, CRC-16 low byte first), reply to a sample command:
//   [init = N-1][VCELL n × 2][VMODULE 2][AUX0 2][AUX1 2][DIE_TEMP 2][FAULT_SUMMARY 2][CRC lo][CRC hi]
//   cell V = code · 5/65535; module V = code · 100/65535.
// BQ76952-like (I2C block read, optional CRC-8), little-endian:
//   [len N][cell mV n × int16][stack 10 mV u16][TS1 TS2 TS3 0.1 K u16][die 0.1 K u16]
//   [CC2 10 mA int16][accumulated charge mA·s int32][SAFETY_ALERT_A][SAFETY_STATUS_A]
//   [SAFETY_STATUS_B][FET_STATUS][CRC-8 over all before, if enabled]
// An all-0x00 reply passes a CRC-8 with initial value 0, so headers are always checked.
#pragma once
#include <cstddef>
#include <cstdint>

#include "bms_limits.hpp"

namespace bms {

enum class AfeModel : uint8_t { Bq76pl536a = 0, Bq76pl455a = 1, Bq76952 = 2 };

// One reply as the MCU received it. length 0: no reply before the timeout.
struct AfeFrame {
  uint8_t length;
  uint8_t bytes[kMaxFrameBytes];
};

// --- BQ76PL536A-like layout ---
constexpr uint8_t kPl536CellSlots = 6;
constexpr uint8_t kPl536DataLen = 25;
constexpr uint8_t kPl536FrameLen = 3 + kPl536DataLen + 1;
enum Pl536Offset : uint8_t {  // offsets into the data (after the 3-byte header)
  kPl536Status = 0, kPl536Gpai = 1, kPl536Cell1 = 3, kPl536Temp1 = 15, kPl536Temp2 = 17,
  kPl536Alert = 19, kPl536Fault = 20, kPl536CovCells = 21, kPl536CuvCells = 22, kPl536DieTemp = 23,
};
enum Pl536Status : uint8_t { kPl536Drdy = 0x01, kPl536Cbt = 0x02, kPl536AlertBit = 0x20, kPl536FaultBit = 0x40 };
enum Pl536AlertBits : uint8_t { kPl536Ot1 = 0x01, kPl536Ot2 = 0x02, kPl536Tsd = 0x08 };
enum Pl536FaultBits : uint8_t { kPl536Cov = 0x01, kPl536Cuv = 0x02, kPl536CrcFault = 0x04, kPl536Por = 0x08 };
constexpr float kPl536GpaiCellLsbs = 6.0f;  // module voltage LSB in cell LSBs

// --- BQ76PL455A-like layout ---
constexpr uint8_t pl455DataLen(uint8_t cells) { return static_cast<uint8_t>(2 * cells + 10); }
constexpr uint8_t pl455FrameLen(uint8_t cells) { return static_cast<uint8_t>(1 + pl455DataLen(cells) + 2); }
enum Pl455Summary : uint16_t {
  kPl455Uv = 1u << 0, kPl455Ov = 1u << 1, kPl455AuxUv = 1u << 2, kPl455AuxOv = 1u << 3,
  kPl455CmpUv = 1u << 4, kPl455CmpOv = 1u << 5, kPl455Comm = 1u << 6, kPl455Sys = 1u << 7,
  kPl455Chip = 1u << 8, kPl455Gpi = 1u << 9,
};
constexpr float kPl455CellLsb_uV = 5.0e6f / 65535.0f;
constexpr float kPl455ModuleLsb_mV = 1.0e5f / 65535.0f;

// --- BQ76952-like layout ---
constexpr uint8_t bq952DataLen(uint8_t cells) { return static_cast<uint8_t>(2 * cells + 20); }
constexpr uint8_t bq952FrameLen(uint8_t cells, bool crc) {
  return static_cast<uint8_t>(1 + bq952DataLen(cells) + (crc ? 1 : 0));
}
enum Bq952SafetyA : uint8_t { kBqCuv = 0x04, kBqCov = 0x08, kBqOcc = 0x10, kBqOcd1 = 0x20, kBqOcd2 = 0x40, kBqScd = 0x80 };
enum Bq952SafetyB : uint8_t { kBqUtc = 0x01, kBqUtd = 0x02, kBqOtc = 0x08, kBqOtd = 0x10, kBqOtf = 0x40 };
enum Bq952Fet : uint8_t { kBqChgFet = 0x01, kBqPchgFet = 0x02, kBqDsgFet = 0x04, kBqPdsgFet = 0x08, kBqAlrtPin = 0x40 };

// Shape of the monitor stack, as flashed into the firmware.
struct AfeConfig {
  AfeModel model;
  uint8_t deviceCount;
  uint8_t cellsPerDevice;        // the last device may hold fewer
  uint8_t thermistorsPerDevice;  // inputs in use per device (AFE thermistors)
  bool crcEnabled;               // BQ76952 only; the others always carry a CRC
  uint8_t commLossCount;         // consecutive bad replies that mean "device lost"
};

// What one good reply says, in firmware units.
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

enum class FrameResult : uint8_t { Ok = 0, Timeout, BadLength, BadHeader, BadCrc };

// A cell ADC code in mV (rounded, clamped to 0..65535) at the flashed LSB.
uint16_t afeCellCodeToMv(uint16_t code, float lsb_uV);
// Cells held by device d (the last device may be partly populated).
uint8_t afeCellsOf(const AfeConfig& c, uint16_t cellCount, uint8_t d);
// The length a good reply of device d has.
uint8_t afeFrameLength(const AfeConfig& c, uint16_t cellCount, uint8_t d);
// Checks and decodes one reply. cellLsb_uV is the flashed cell-code scaling (ignored
// for the BQ76952, which reports mV). Returns Ok and fills `out` only for a good frame.
FrameResult afeParse(const AfeConfig& c, uint16_t cellCount, uint8_t d, float cellLsb_uV, const AfeFrame& f,
                     DeviceReading& out);

}  // namespace bms
