#include "bms_afe.hpp"

namespace bms {

uint8_t afeCellsOf(const AfeConfig& c, uint16_t cellCount, uint8_t d) {
  const uint32_t first = static_cast<uint32_t>(d) * c.cellsPerDevice;
  if (first >= cellCount) return 0;
  const uint32_t left = cellCount - first;
  return static_cast<uint8_t>(left < c.cellsPerDevice ? left : c.cellsPerDevice);
}

}  // namespace bms
