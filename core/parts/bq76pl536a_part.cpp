// The BQ76PL536A as a part (monitor_parts.hpp): 3-6 cells per device on a vertical SPI
// bus, a 14-bit cell ADC, two thermistor inputs, secondary COV/CUV/OT comparators.
#include <bms/afe/bq76pl536a_driver.hpp>
#include <cmath>

#include "core/parts/bq76pl_secondary.hpp"
#include "core/parts/monitor_parts.hpp"
#include "core/scenario/yaml_map.hpp"
#include "models/afe/bq76pl536a.hpp"

namespace packsim {

namespace {

void defaults(MonitorConfig& a, AdcChannel& adc) {
  adc.lsb = 6.25 / 16383.0;
  adc.code_max = (1 << 14) - 1;
  adc.noise_rms = 0.5e-3;
  a.thermistors_per_device = 2;
  a.baud = 1e6;  // SPI
  a.measurement_period_s = 0.0;
}

void readKeys(YamlMap& afe, MonitorConfig& a) {
  if (auto s = afe.optionalMap("secondary")) readSecondaryProtection(*s, a.secondary, false);
}

// The comparators the driver writes at init, and the ADC timing it waits for.
void firmwareSettings(const MonitorConfig& a, bms::AfeSettings& s) {
  bms::Bq536Config p = bms::afeSettingsGet<bms::Bq536Config>(s);
  const SecondaryProtection& sp = a.secondary;
  p.conversionPerChannel_us = static_cast<uint16_t>(std::lround(a.conversion_s_per_channel * 1e6));
  p.protectionEnabled = sp.enabled;
  p.cov_mV = static_cast<uint16_t>(std::lround(sp.cov_V * 1e3));
  p.covDelay_us = static_cast<uint32_t>(std::lround(sp.cov_delay_s * 1e6));
  p.cuv_mV = static_cast<uint16_t>(std::lround(sp.cuv_V * 1e3));
  p.cuvDelay_us = static_cast<uint32_t>(std::lround(sp.cuv_delay_s * 1e6));
  p.ot_C = static_cast<int16_t>(std::lround(sp.ot_C));
  p.otDelay_ms = static_cast<uint16_t>(static_cast<uint32_t>(std::lround(sp.ot_delay_s * 1e3)));
  bms::afeSettingsPut(s, p);
}

}  // namespace

extern const MonitorPart part_bq76pl536a;
const MonitorPart part_bq76pl536a = {
    "bq76pl536a", 6, 2, true, nullptr, defaults, {{"secondary", ""}}, readKeys, nullptr, makeBq76pl536aChain,
    &bms::afe_bq76pl536a, firmwareSettings};

}  // namespace packsim
