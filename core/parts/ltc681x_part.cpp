// The LTC6811-1 (12 cells, 5 GPIOs) and LTC6813-1 (18 cells, 9 GPIOs) as parts
// (monitor_parts.hpp): an isoSPI daisy chain through the MCU's isoSPI master, cells in
// 100 uV codes, NTCs on the GPIOs biased from VREF2, UV / OV comparators setting flags
// (nothing latches, no FAULT line), DCC balancing switches with the discharge timer.
// One model (models/afe/ltc681x) and one driver (bms/afe/ltc681x_*) serve both.
#include <bms/afe/ltc681x_driver.hpp>
#include <cmath>
#include <string>

#include "core/parts/monitor_parts.hpp"
#include "core/scenario/yaml_map.hpp"
#include "models/afe/ltc681x.hpp"

namespace packsim {

namespace {

// The part's own settings (MonitorConfig::part_settings): the ADC mode and the UV / OV
// comparators of CFGRA.
struct LtcSettings final : MonitorPartSettings {
  uint8_t md = LTC681X_MD_NORMAL;  // MD of ADCV / ADAX / ADSTAT
  bool adcopt = false;             // CFGRA ADCOPT
  double uv_V = 1.0, ov_V = 4.5;
};

// hardware.afe.adc_mode: the data sheets' names of (MD, ADCOPT).
struct AdcMode {
  const char* name;
  uint8_t md;
  bool adcopt;
};
constexpr AdcMode kModes[] = {{"27kHz", LTC681X_MD_FAST, false},  {"14kHz", LTC681X_MD_FAST, true},
                              {"7kHz", LTC681X_MD_NORMAL, false}, {"3kHz", LTC681X_MD_NORMAL, true},
                              {"2kHz", LTC681X_MD_FILTERED, true}, {"26Hz", LTC681X_MD_FILTERED, false}};

const LtcSettings& settingsOf(const MonitorConfig& a) {
  static const LtcSettings kDefault{};
  const auto* s = dynamic_cast<const LtcSettings*>(a.part_settings.get());
  return s != nullptr ? *s : kDefault;
}

// 100 uV codes (16 bit); the isoSPI link at 1 Mb/s; two NTCs a device. The noise is a
// choice (0.1 mV rms), not a data-sheet figure: set hardware.cell_adc.noise_mV_rms.
void defaults(MonitorConfig& a, AdcChannel& adc) {
  adc.lsb = LTC681X_LSB_UV * 1e-6;
  adc.code_max = 65535;
  adc.noise_rms = 0.1e-3;
  a.thermistors_per_device = 2;
  a.baud = 1e6;
  a.measurement_period_s = 0.0;
  a.part_settings = std::make_shared<LtcSettings>();
}

void readKeys(YamlMap& afe, MonitorConfig& a) {
  auto s = std::make_shared<LtcSettings>(settingsOf(a));
  std::vector<std::string> names;
  for (const AdcMode& m : kModes) names.emplace_back(m.name);
  const std::string mode = afe.choice("adc_mode", "7kHz", names);
  for (const AdcMode& m : kModes)
    if (mode == m.name) s->md = m.md, s->adcopt = m.adcopt;
  // VUV = (code + 1) * 1.6 mV, VOV = code * 1.6 mV, 12-bit codes.
  s->uv_V = afe.number("uv_V", s->uv_V, Range::closed(0.0016, 6.5536));
  s->ov_V = afe.number("ov_V", s->ov_V, Range::closed(0.0, 6.552));
  if (!(s->uv_V < s->ov_V)) throw afe.errorAt("ov_V", "must be above uv_V");
  // isoSPI runs at up to 1 Mb/s.
  if (a.baud > 1e6) throw afe.errorAt("baud", "the LTC681x's isoSPI link runs at most 1000000 (1 Mb/s)");
  // One host drives at most kLtcMaxDevices devices (its RAM for their readings).
  const int chain = a.devices_per_board > 0 ? a.devices_per_board : a.devices;
  if (chain > bms::kLtcMaxDevices) {
    const char* key = afe.has("devices_per_board") ? "devices_per_board" : afe.has("devices") ? "devices" : "model";
    throw afe.errorAt(key, std::to_string(chain) + " devices on one isoSPI chain (hardware.afe.devices " +
                               std::to_string(a.devices) + "); packsim's LTC681x driver drives at most " +
                               std::to_string(bms::kLtcMaxDevices) + " a host: split them with devices_per_board");
  }
  a.part_settings = s;
}

Ltc681xPart partOf(const MonitorConfig& a) { return a.model == "ltc6811" ? Ltc681xPart::Ltc6811 : Ltc681xPart::Ltc6813; }

// The chain: the shared settings, the thermistor inputs' noise carried over from the
// scenario's thermistor channel (codes of its full scale -> volts of VREF2).
std::unique_ptr<MonitorChain> makeChain(const MonitorConfig& a, int cellCount, uint64_t seed) {
  Ltc681xConfig c = ltc681xConfigFrom(a, partOf(a));
  c.gpio_noise_V = a.thermistor.noise_codes_rms * (LTC681X_VREF2_MV * 1e-3) /
                   static_cast<double>(a.thermistor.fullScaleCode());
  return makeLtc681xChain(c, cellCount, seed);
}

// The ADC mode and comparators the driver writes at init.
void firmwareSettings(const MonitorConfig& a, bms::AfeSettings& s) {
  bms::LtcConfig p = bms::afeSettingsGet<bms::LtcConfig>(s);
  const LtcSettings& ls = settingsOf(a);
  p.adcMode = ls.md;
  p.adcopt = ls.adcopt;
  p.uv_mV = static_cast<uint16_t>(std::lround(ls.uv_V * 1e3));
  p.ov_mV = static_cast<uint16_t>(std::lround(ls.ov_V * 1e3));
  bms::afeSettingsPut(s, p);
}

const std::vector<PartKey> kKeys = {{"adc_mode", ""}, {"uv_V", ""}, {"ov_V", ""}};

}  // namespace

extern const MonitorPart part_ltc6811;
const MonitorPart part_ltc6811 = {
    "ltc6811", static_cast<int>(LTC6811_CELLS), static_cast<int>(LTC6811_GPIOS), true, "reports cells in 100 uV codes",
    defaults, kKeys, readKeys, nullptr, makeChain, &bms::afe_ltc6811, firmwareSettings};

// 18 cells; 8 of its 9 GPIOs take thermistors (the core's kMaxThermPerDevice).
extern const MonitorPart part_ltc6813;
const MonitorPart part_ltc6813 = {
    "ltc6813", static_cast<int>(LTC6813_CELLS), static_cast<int>(bms::kMaxThermPerDevice), true,
    "reports cells in 100 uV codes", defaults, kKeys, readKeys, nullptr, makeChain, &bms::afe_ltc6813,
    firmwareSettings};

}  // namespace packsim
