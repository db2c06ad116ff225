// A board service called for a channel or pin the board does not have (adc_read,
// gpio_read, gpio_write, dac_write): the call returns PSFW_NO_CHANNEL or does nothing,
// as an unconnected port would, but a firmware that reads a channel that is not wired
// (a wrong channel number, a thermistor the scenario does not give the MCU) decides on
// a code that is no reading, and one that writes a pin that is not wired never drives
// what it meant to. So the host says so: one `firmware_misuse` event per service and
// channel, at its first call (docs/firmware.md, *Board services the board does not have*).
// A member board's MCU (FirmwareBoard::pins false) has no current sense, bus ADC or port
// pins by design, and packsim's core on it reads PSFW_NO_CHANNEL there: not noted.
#pragma once
#include <bitset>
#include <cstdint>
#include <string>

namespace packsim {

class ServiceMisuse {
 public:
  enum Service : uint8_t { kAdcRead, kGpioRead, kGpioWrite, kDacWrite, kServices };
  // Whether this is the first call of `s` on `channel` (noted from now on).
  bool first(Service s, uint8_t channel) {
    std::bitset<256>& seen = seen_[s];
    if (seen.test(channel)) return false;
    seen.set(channel);
    return true;
  }
  // The event's text: the call, what the board has instead, what the call did.
  // value: the level or code written (writes); returned: what a read returned;
  // mcuThermistors: the thermistor channels on the MCU's ADC.
  static std::string text(Service s, uint8_t channel, int32_t value, int32_t returned, int mcuThermistors);

 private:
  std::bitset<256> seen_[kServices];
};

}  // namespace packsim
