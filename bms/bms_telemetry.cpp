#include "bms_telemetry.hpp"

#include "bms_crc.hpp"

namespace bms {

namespace {

void put(uint8_t* p, uint32_t v, uint8_t bytes) {
  for (uint8_t i = 0; i < bytes; ++i) p[i] = static_cast<uint8_t>((v >> (8u * i)) & 0xFFu);
}

}  // namespace

uint8_t telemetryEncode(const Outputs& out, uint8_t f[kTelemetryFrameBytes]) {
  const Telemetry& tm = out.telemetry;
  f[0] = 0xA5;
  f[1] = kTelemetryFrameBytes - 3;
  f[2] = static_cast<uint8_t>(out.state);
  f[3] = tm.prechargePhase;
  f[4] = static_cast<uint8_t>((out.relayClose ? 1u : 0u) | (out.prechargeClose ? 2u : 0u) |
                              (out.dischargeFetOn ? 4u : 0u) | (out.chargeFetOn ? 8u : 0u) |
                              (tm.monitorFault ? 16u : 0u));
  put(f + 5, out.faultActive, 4);
  put(f + 9, out.faultLatched, 4);
  put(f + 13, tm.soc_permille, 2);
  put(f + 15, static_cast<uint32_t>(tm.packCurrent_mA), 4);
  put(f + 19, tm.packVoltage_mV, 4);
  put(f + 23, tm.minCell_mV, 2);
  put(f + 25, tm.maxCell_mV, 2);
  put(f + 27, static_cast<uint16_t>(tm.maxTemp_dC), 2);
  put(f + 29, static_cast<uint16_t>(tm.minTemp_dC), 2);
  uint8_t lost = 0;  // devices lost: one pass per set bit (none on the usual tick)
  for (uint64_t m = tm.devicesLost; m != 0; m &= m - 1) ++lost;
  f[31] = lost;
  f[32] = crcCrc8Fixed<kTelemetryFrameBytes - 1>(f);
  return kTelemetryFrameBytes;
}

}  // namespace bms
