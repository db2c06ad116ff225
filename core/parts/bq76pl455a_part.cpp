// The BQ76PL455A as a part (monitor_parts.hpp): up to 16 cells per device on a UART
// daisy chain, a 16-bit cell ADC with hardware oversampling, up to 8 AUX thermistor
// inputs, secondary comparators and a communication timeout.
#include <bms/afe/bq76pl455a_driver.hpp>
#include <cmath>

#include "core/parts/bq76pl_secondary.hpp"
#include "core/parts/monitor_parts.hpp"
#include "core/scenario/yaml_map.hpp"
#include "models/afe/bq76pl455a.hpp"

namespace packsim {

namespace {

void defaults(MonitorConfig& a, AdcChannel& adc) {
  adc.lsb = 5.0 / 65535.0;
  adc.code_max = 65535;
  adc.noise_rms = 0.3e-3;
  a.thermistors_per_device = 2;
  a.baud = 250000.0;
  a.conversion_s_per_channel = 100e-6;
  a.measurement_period_s = 0.0;
}

void readKeys(YamlMap& afe, MonitorConfig& a) {
  if (afe.has("oversampling")) {  // the one monitor class here that averages in hardware
    a.oversampling = static_cast<int>(afe.integer("oversampling", 1, 1, 32));
    if ((a.oversampling & (a.oversampling - 1)) != 0)
      throw afe.errorAt("oversampling", "must be 1, 2, 4, 8, 16 or 32 samples");
    a.cell_adc.noise_rms /= std::sqrt(static_cast<double>(a.oversampling));
  }
  if (auto s = afe.optionalMap("secondary")) readSecondaryProtection(*s, a.secondary, true);
}

// Oversampling, comparators and the link supervision the driver writes at init.
void firmwareSettings(const MonitorConfig& a, bms::AfeSettings& s) {
  bms::Pl455Config p = bms::afeSettingsGet<bms::Pl455Config>(s);
  int log2 = 0;
  while ((1 << log2) < a.oversampling) ++log2;
  p.oversamplingLog2 = static_cast<uint8_t>(log2);
  p.comparators = a.secondary.enabled;
  p.commTimeoutCode = static_cast<uint8_t>(pl455CommTimeoutCode(a.secondary.comm_timeout_s));
  bms::afeSettingsPut(s, p);
}

}  // namespace

extern const MonitorPart part_bq76pl455a;
const MonitorPart part_bq76pl455a = {
    "bq76pl455a",
    16,
    8,
    true,
    nullptr,
    defaults,
    {{"oversampling", "average in firmware with bms.balancing.average_readings"}, {"secondary", ""}},
    readKeys,
    nullptr,
    makeBq76pl455aChain,
    &bms::afe_bq76pl455a,
    firmwareSettings};

}  // namespace packsim
