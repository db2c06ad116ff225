// The telemetry frame the BMS sends to the data-acquisition unit every tick (I2C in
// reference system A). Fixed layout, little-endian, CRC-8 (poly 0x07) at the end:
//
//   0 sync 0xA5 | 1 payload length | 2 state | 3 precharge phase
//   4 bits: relay, precharge, discharge FET, charge FET, monitor fault
//   5 fault active u32 | 9 fault latched u32 | 13 SOC ‰ u16 | 15 current mA i32
//   19 pack mV u32 | 23 min cell mV u16 | 25 max cell mV u16 | 27 max temp dC i16
//   29 min temp dC i16 | 31 devices lost | 32 CRC-8 over bytes 0..31
#pragma once
#include <cstdint>

#include "bms_hal.hpp"

namespace bms {

constexpr uint8_t kTelemetryFrameBytes = 33;

// Encodes the outputs of one tick; returns the frame length.
uint8_t telemetryEncode(const Outputs& out, uint8_t frame[kTelemetryFrameBytes]);

}  // namespace bms
