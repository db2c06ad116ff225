#include "bms_afe.hpp"

namespace bms {

uint16_t afeCellCodeToMv(uint16_t code, float lsb_uV) {
  const float mv = static_cast<float>(code) * lsb_uV * 0.001f;
  if (mv <= 0.0f) return 0;
  if (mv >= 65535.0f) return 65535;
  return static_cast<uint16_t>(mv + 0.5f);
}

uint8_t afeCellsOf(const AfeConfig& c, uint16_t cellCount, uint8_t d) {
  const uint32_t first = static_cast<uint32_t>(d) * c.cellsPerDevice;
  if (first >= cellCount) return 0;
  const uint32_t left = cellCount - first;
  return static_cast<uint8_t>(left < c.cellsPerDevice ? left : c.cellsPerDevice);
}

}  // namespace bms
