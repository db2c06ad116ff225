// Compile-time capacities of the BMS core. Every array in bms/ is sized by these,
// so a build for a given vehicle fixes its memory at link time (no heap).
#pragma once
#include <cstdint>

namespace bms {

constexpr uint16_t kMaxCells = 256;         // series cell groups one BMS can monitor
constexpr uint8_t kMaxThermistors = 48;     // temperature channels (cells, board, FETs)
constexpr uint8_t kMaxDevices = 64;         // monitor ICs on the bus / daisy chain
constexpr uint8_t kMaxCellsPerDevice = 18;  // the largest monitor class (the LTC6813's 18 cells)
constexpr uint8_t kMaxThermPerDevice = 8;   // thermistor inputs per monitor IC (16-cell class: 8 AUX)
constexpr uint8_t kMaxOcvPoints = 16;       // OCV table rows for the SOC estimate
constexpr uint8_t kDisplayBars = 8;         // SOC display bars (reference system C)
constexpr uint8_t kBalanceWords = (kMaxCells + 31) / 32;
constexpr uint8_t kMaxBoards = 16;          // monitor boards, each with its own balancing-board thermistors
constexpr uint8_t kMaxBalanceAverage = 64;  // readings the balancing decision may average per cell
// A monitor part's flashed settings and its driver's state in RAM (its driver's own
// structs; bms_afe_driver.hpp). The settings block is what the drivers of the three TI
// parts took together before they shared one block; the data block was too (1264
// bytes) until the LTC681x joined: the 18-cell part grew DeviceReading by two cells
// while one array became the union of the ratiometric codes and the converted
// temperatures (bms_afe.hpp), 12 bytes less a device, and the 64 devices' 768 bytes went
// to this block (2032), where the LTC681x driver keeps its chain's readings. So the
// configuration image (1216 bytes) and the core's RAM (18176 bytes) keep their sizes on
// a 64-bit host; a part needing more raises them (its static_assert says so), and the
// core's image and RAM grow with them.
constexpr uint16_t kAfeSettingsBytes = 127;
constexpr uint16_t kAfeDataBytes = 2032;

}  // namespace bms
