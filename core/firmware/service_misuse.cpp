#include "core/firmware/service_misuse.hpp"

#include <bms/packsim_fw.h>

namespace packsim {

namespace {

std::string returnedText(int32_t returned) {
  return returned == PSFW_NO_CHANNEL ? "it returned PSFW_NO_CHANNEL (-3)"
                                     : "it returned " + std::to_string(returned) +
                                           " (no such channel in contract versions 1 and 2, the code PSFW_BUS_TIMEOUT shares)";
}

std::string adcChannels(int mcuThermistors) {
  std::string s = "0 current sense, 1 bus voltage";
  if (mcuThermistors == 1) s += ", 16 the thermistor on the MCU's ADC";
  if (mcuThermistors > 1)
    s += ", 16-" + std::to_string(PSFW_ADC_THERMISTOR0 + mcuThermistors - 1) + " the " + std::to_string(mcuThermistors) +
         " thermistors on the MCU's ADC";
  return s;
}

}  // namespace

std::string ServiceMisuse::text(Service s, uint8_t channel, int32_t value, int32_t returned, int mcuThermistors) {
  const std::string ch = std::to_string(channel), v = std::to_string(value);
  switch (s) {
    case kAdcRead:
      return "adc_read(channel " + ch + "): the board has no such ADC channel (it has " + adcChannels(mcuThermistors) +
             "); " + returnedText(returned) + ", no reading";
    case kGpioRead:
      return "gpio_read(pin " + ch +
             "): the board has no such input pin (0-6: internal and external E-switch, relay aux, monitor FAULT, "
             "charger present, run request, reset request); " +
             returnedText(returned);
    case kGpioWrite:
      return "gpio_write(pin " + ch + ", " + v +
             "): the board has no such output pin (0 relay, 1 precharge, 2 discharge FET, 3 charge FET, 4 charger "
             "enable); the write drives nothing";
    case kDacWrite:
      return "dac_write(channel " + ch + ", " + v +
             "): the board has no such DAC channel (0 charger current, mA); the write drives nothing";
    case kServices:
      break;
  }
  return {};
}

}  // namespace packsim
