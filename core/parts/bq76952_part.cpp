// The BQ76952 as a part (monitor_parts.hpp): up to 16 cells reported in mV, one device
// per I2C bus, three thermistor inputs it converts itself, its own protections, FETs,
// coulomb counter and autonomous balancing, an optional CRC.
#include <bms/afe/bq76952_driver.hpp>
#include <cmath>

#include "core/parts/monitor_parts.hpp"
#include "core/scenario/value_ranges.hpp"
#include "core/scenario/yaml_map.hpp"
#include "models/afe/bq76952.hpp"

namespace packsim {

namespace {

void defaults(MonitorConfig& a, AdcChannel& adc) {
  adc.lsb = 1e-3;  // reports mV
  adc.code_max = 32767;
  adc.noise_rms = 1.0e-3;
  a.thermistors_per_device = 3;
  a.baud = 400000.0;  // I2C fast mode
  a.conversion_s_per_channel = 3e-3;
  a.measurement_period_s = 0.06;
}

// The part's autonomous balancing, in the ranges its data memory holds.
void readBalancing(YamlMap& m, Bq952AutoBalance& b) {
  const std::string when = m.choice("when", "charging", {"charging", "rest", "charging_or_rest"});
  b.charging = when != "rest";
  b.relax = when != "charging";
  b.min_cell_V = m.number("min_cell_V", b.min_cell_V, Range::closed(0.0, 5.0));
  b.start_delta_mV = m.number("start_delta_mV", b.start_delta_mV, Range::closed(0.0, 255.0));
  b.stop_delta_mV = m.number("stop_delta_mV", b.stop_delta_mV, Range::closed(0.0, 255.0));
  if (!(b.stop_delta_mV <= b.start_delta_mV)) throw m.errorAt("stop_delta_mV", "must not exceed start_delta_mV");
  b.max_cells = static_cast<int>(m.integer("max_cells", b.max_cells, 1, 16));
  const Range temp = Range::closed(-40.0, 120.0);
  b.min_cell_temp_C = m.number("min_cell_temp_C", b.min_cell_temp_C, temp);
  b.max_cell_temp_C = m.number("max_cell_temp_C", b.max_cell_temp_C, temp);
  if (!(b.min_cell_temp_C < b.max_cell_temp_C)) throw m.errorAt("max_cell_temp_C", "must be above min_cell_temp_C");
  b.max_internal_C = m.number("max_internal_C", b.max_internal_C, temp);
  m.finish();
}

// The part's own protections, in the ranges and steps its data memory holds (the
// register-level model refuses a value between steps' ends; these ranges catch the rest
// with the scenario's file and line).
void readProtection(YamlMap& m, Bq952Protection& p) {
  const Range temp = Range::closed(-40.0, 120.0);
  const Range seconds = Range::closed(0.0, 255000.0);        // U1, 1 s steps
  const Range voltageDelay = Range::closed(3.3, 6755.1);     // U2 1..2047 x 3.3 ms
  const Range currentDelay = Range::closed(9.9, 425.7);      // U1 1..127: (n + 2) x 3.3 ms
  p.cov_V = m.number("cov_V", p.cov_V, Range::closed(1.012, 5.566));
  p.cov_delay_s = m.number("cov_delay_ms", p.cov_delay_s * 1e3, voltageDelay) * 1e-3;
  p.cov_recovery_V = m.number("cov_recovery_V", p.cov_recovery_V, Range::closed(0.0, 1.012));
  p.cuv_V = m.number("cuv_V", p.cuv_V, Range::closed(1.012, 4.554));
  p.cuv_delay_s = m.number("cuv_delay_ms", p.cuv_delay_s * 1e3, voltageDelay) * 1e-3;
  p.cuv_recovery_V = m.number("cuv_recovery_V", p.cuv_recovery_V, Range::closed(0.0, 1.012));
  p.occ_mV = m.number("occ_mV", p.occ_mV, Range::closed(4.0, 124.0));
  p.occ_delay_s = m.number("occ_delay_ms", p.occ_delay_s * 1e3, currentDelay) * 1e-3;
  p.ocd1_mV = m.number("ocd1_mV", p.ocd1_mV, Range::closed(4.0, 200.0));
  p.ocd1_delay_s = m.number("ocd1_delay_ms", p.ocd1_delay_s * 1e3, currentDelay) * 1e-3;
  p.scd_mV = m.number("scd_mV", p.scd_mV, Range::closed(10.0, 500.0));
  // USER_AMPS: the unit of the part's current readings and of OCD3's threshold.
  const std::string ua = m.choice("user_amps_mA", "1", {"0.1", "1", "10", "100"});
  p.user_amps_A = std::stod(ua) * 1e-3;
  p.ocd3_A = m.number("ocd3_A", p.ocd3_A, Range::closed(0.0, 32767.0 * p.user_amps_A));
  p.ocd3_delay_s = m.number("ocd3_delay_ms", p.ocd3_delay_s * 1e3, seconds) * 1e-3;
  p.current_recovery_s = m.number("current_recovery_ms", p.current_recovery_s * 1e3, seconds) * 1e-3;
  p.otc_C = m.number("otc_C", p.otc_C, temp);
  p.otd_C = m.number("otd_C", p.otd_C, temp);
  p.otf_C = m.number("otf_C", p.otf_C, temp);
  p.ot_delay_s = m.number("ot_delay_ms", p.ot_delay_s * 1e3, seconds) * 1e-3;
  p.utc_C = m.number("utc_C", p.utc_C, temp);
  p.utd_C = m.number("utd_C", p.utd_C, temp);
  p.ut_delay_s = m.number("ut_delay_ms", p.ut_delay_s * 1e3, seconds) * 1e-3;
  p.temp_recovery_C = m.number("temp_recovery_C", p.temp_recovery_C, Range::closed(0.0, 50.0));
  m.finish();
}

void readKeys(YamlMap& afe, MonitorConfig& a) {
  if (afe.has("crc")) a.crc = afe.boolean("crc", true);
  if (auto p = afe.optionalMap("protection")) readProtection(*p, a.bq);
  if (auto b = afe.optionalMap("autonomous_balancing")) readBalancing(*b, a.bq_balance);
}

bool balancesOnItsOwn(const MonitorConfig& a) { return a.bq_balance.charging || a.bq_balance.relax; }

// The unit of the current readings and the CRC mode (the protections are the part's
// OTP: the model holds them).
void firmwareSettings(const MonitorConfig& a, bms::AfeSettings& s) {
  bms::Bq952DriverConfig p = bms::afeSettingsGet<bms::Bq952DriverConfig>(s);
  p.userAmps = bq952_user_amps_field(static_cast<uint32_t>(std::lround(a.bq.user_amps_A * 1e4)));
  p.crc = a.crc;
  bms::afeSettingsPut(s, p);
}

}  // namespace

extern const MonitorPart part_bq76952;
const MonitorPart part_bq76952 = {
    "bq76952",
    16,
    3,
    false,
    "reports cells in mV",
    defaults,
    {{"crc", "the others always carry a CRC"}, {"protection", ""}, {"autonomous_balancing", "use bms.balancing"}},
    readKeys,
    balancesOnItsOwn,
    makeBq76952Chain,
    &bms::afe_bq76952,
    firmwareSettings};

}  // namespace packsim
