// Compile-time capacities of the BMS core. Every array in bms/ is sized by these,
// so a build for a given vehicle fixes its memory at link time (no heap).
#pragma once
#include <cstdint>

namespace bms {

constexpr uint16_t kMaxCells = 256;         // series cell groups one BMS can monitor
constexpr uint8_t kMaxThermistors = 48;     // temperature channels (cells, board, FETs)

}  // namespace bms
