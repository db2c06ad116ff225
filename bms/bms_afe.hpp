// What the core knows of its monitor ICs: which registered part (bms_afe_driver.hpp),
// the stack's shape as flashed, the part's own settings as an opaque block, and one
// device's reading in firmware units. The bytes on the bus (frames, CRCs, registers)
// belong to the parts' drivers in bms/afe/, which fill DeviceReading and report a
// FrameResult per device; the core never parses a frame itself.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "bms_limits.hpp"

namespace bms {

// A part's own settings as flashed: its driver's settings struct, stored as bytes so
// that the configuration image holds any registered part's (afeSettingsGet / Put in
// bms_afe_driver.hpp copy it in and out, so the block needs no alignment).
struct AfeSettings {
  uint8_t bytes[kAfeSettingsBytes];
};

// The monitor stack, as flashed into the firmware.
struct AfeConfig {
  uint8_t part;                  // index of its driver in the registry (afeDriver(part))
  uint8_t deviceCount;
  uint8_t cellsPerDevice;        // the last device may hold fewer
  uint8_t thermistorsPerDevice;  // inputs in use per device (AFE thermistors)
  uint8_t commLossCount;         // consecutive bad read-outs of a device that mean "device lost"
  AfeSettings settings;          // the part's own settings (its driver's struct)
};

static_assert(kMaxThermPerDevice <= 8, "DeviceReading::thermConverted holds one bit per thermistor input");

// What one good read of a device says, in firmware units.
struct DeviceReading {
  uint16_t cell_mV[kMaxCellsPerDevice];
  // A part reports its thermistor inputs one way (its driver writes that array, its
  // temperature_dC reads it): ratiometric codes or temperatures it converted itself.
  union {
    uint16_t thermCode[kMaxThermPerDevice];  // ratiometric codes (parts that convert no temperature)
    int16_t temp_dC[kMaxThermPerDevice];     // converted by the device (parts that do)
  };
  uint32_t stack_mV;                       // module / stack voltage channel
  int16_t die_dC;
  bool fault;          // the device's own protection has latched (FAULT / safety status)
  bool alert;          // a threshold is crossed, not yet debounced
  uint8_t fetStatus;   // a part with FETs: their status as it reports it
  uint8_t safetyA;     // the part's first protection status byte (its driver's header says which)
  uint8_t safetyB;     // its second
  // Bit i: the core's last conversion of thermCode[i] (Telemetry::temperature_dC) still
  // holds, so the next tick need not convert the same code again. The core sets it when
  // it converts (bms_measure.cpp); a driver of a part whose temperature_dC is
  // afeRatiometricTemp_dC clears it whenever it writes another code (afeSetThermCodes);
  // a reading built afresh has it clear. It sits in what was the struct's padding.
  uint8_t thermConverted;
  int32_t current_mA;  // a part with a current input: its reading
  int32_t charge_mAs;  // ... and its accumulated charge
  // A part that measures in a loop of its own (not on the host's command) sets these:
  // sameLoop, its loop has not run since the previous read-out (the cells are the ones
  // read before: no new sample for the estimators); loopCurrent, current_mA was
  // measured in the same loop as cell_mV (the current those cells were under; false
  // where the part's current register sat at its rail). A reading built afresh, or by a
  // part that converts on command (the cells are this read-out's, under the MCU's
  // current of this tick), has both clear.
  bool sameLoop;
  bool loopCurrent;
};

// How a driver's read of one device ended. Timeout: nothing answered; BadLength,
// BadHeader, BadCrc: an answer that failed the driver's checks (a stuck 0x00 / 0xFF
// line shows as a bad header or CRC). NotRead: the driver spent this call on something
// else (recovering the chain) and read nothing: the device's standing, good or bad, is
// as it was, and no reading is new.
enum class FrameResult : uint8_t { Ok = 0, Timeout, BadLength, BadHeader, BadCrc, NotRead };

// A cell ADC code in mV (rounded, clamped to 0..65535) at the flashed LSB. Inline: the
// drivers convert every cell of every read-out with it.
inline uint16_t afeCellCodeToMv(uint16_t code, float lsb_uV) {
  const float mv = static_cast<float>(code) * lsb_uV * 0.001f;
  if (mv <= 0.0f) return 0;
  if (mv >= 65535.0f) return 65535;
  return static_cast<uint16_t>(mv + 0.5f);
}
// A ratiometric part's driver writes its thermistor inputs' codes (all
// kMaxThermPerDevice, 0 where unused) through this: an input whose code differs from the
// one held loses the core's conversion of it (thermConverted).
inline void afeSetThermCodes(DeviceReading& r, const uint16_t (&codes)[kMaxThermPerDevice]) {
  if (std::memcmp(r.thermCode, codes, sizeof codes) == 0) return;  // the usual read-out: every code as held
  uint32_t changed = 0;
  for (uint8_t i = 0; i < kMaxThermPerDevice; ++i) {
    changed |= static_cast<uint32_t>(r.thermCode[i] != codes[i]) << i;
    r.thermCode[i] = codes[i];
  }
  r.thermConverted = static_cast<uint8_t>(r.thermConverted & ~changed);
}

// Cells held by device d (the last device may be partly populated). Inline: measure()
// asks it for every device every tick.
inline uint8_t afeCellsOf(const AfeConfig& c, uint16_t cellCount, uint8_t d) {
  const uint32_t first = static_cast<uint32_t>(d) * c.cellsPerDevice;
  if (first >= cellCount) return 0;
  const uint32_t left = cellCount - first;
  return static_cast<uint8_t>(left < c.cellsPerDevice ? left : c.cellsPerDevice);
}

}  // namespace bms
