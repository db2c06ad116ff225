#include "models/afe/reply_corruption.hpp"
#include "models/afe/bq76952.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

#include <bms/bms_crc.hpp>
#include "models/pack/cell_spread.hpp"

namespace packsim {

namespace {

constexpr uint8_t kAddrW = static_cast<uint8_t>(BQ952_I2C_ADDR << 1);
constexpr uint8_t kAddrR = static_cast<uint8_t>(kAddrW | 1u);
constexpr uint16_t kScdThresholds_mV[BQ952_SCD_SETTINGS] = BQ952_SCD_THRESHOLDS_MV;
constexpr double kCcConversion_s = BQ952_CC_CONVERSION_US * 1e-6;

uint8_t i8(double v) { return static_cast<uint8_t>(static_cast<int8_t>(std::clamp(std::nearbyint(v), -128.0, 127.0))); }
uint16_t u16(double v) { return static_cast<uint16_t>(std::clamp(std::nearbyint(v), 0.0, 65535.0)); }
int16_t i16(double v) { return static_cast<int16_t>(std::clamp(std::nearbyint(v), -32768.0, 32767.0)); }
void putLe16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v & 0xFF);
  p[1] = static_cast<uint8_t>(v >> 8);
}
void putLe32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>((v >> (8 * i)) & 0xFF);
}
std::string fmt(double v) {
  std::ostringstream o;
  o << std::setprecision(5) << v;
  return o.str();
}
bool isDataMemory(uint16_t code) { return code >= BQ952_DM_FIRST && code <= BQ952_DM_LAST; }
uint8_t crcOf(std::initializer_list<uint8_t> bytes) {
  uint8_t buf[4];
  size_t n = 0;
  for (uint8_t b : bytes) buf[n++] = b;
  return bms::crcCrc8(buf, n);
}
// A thermistor divider code as the part converts it: 0.1 K, a rail reads 0 K (open)
// or the top of the register (short).
uint16_t thermistor_dK(const Thermistor& th, int64_t code) {
  if (code <= 0) return 0xFFFF;
  if (code >= th.fullScaleCode()) return 0;
  return u16(th.temperatureAt_K(static_cast<double>(code)) * 10.0);
}

// A direct command's name (the data sheet's, for the ones the part has).
std::string directName(uint8_t reg) {
  switch (reg) {
    case BQ952_CONTROL_STATUS: return "Control Status";
    case BQ952_SAFETY_ALERT_A: return "Safety Alert A";
    case BQ952_SAFETY_STATUS_A: return "Safety Status A";
    case BQ952_SAFETY_ALERT_B: return "Safety Alert B";
    case BQ952_SAFETY_STATUS_B: return "Safety Status B";
    case BQ952_SAFETY_ALERT_C: return "Safety Alert C";
    case BQ952_SAFETY_STATUS_C: return "Safety Status C";
    case BQ952_BATTERY_STATUS: return "Battery Status";
    case BQ952_STACK_VOLTAGE: return "Stack Voltage";
    case BQ952_PACK_VOLTAGE: return "PACK Pin Voltage";
    case BQ952_LD_VOLTAGE: return "LD Pin Voltage";
    case BQ952_CC2_CURRENT: return "CC2 Current";
    case BQ952_SUBCMD_LOW: return "subcommand (low byte)";
    case BQ952_SUBCMD_HIGH: return "subcommand (high byte)";
    case BQ952_RESP_CHECKSUM: return "transfer buffer checksum";
    case BQ952_RESP_LENGTH: return "transfer buffer length";
    case BQ952_ALARM_STATUS: return "Alarm Status";
    case BQ952_ALARM_RAW_STATUS: return "Alarm Raw Status";
    case BQ952_ALARM_ENABLE: return "Alarm Enable";
    case BQ952_INT_TEMPERATURE: return "Int Temperature";
    case BQ952_FET_STATUS: return "FET Status";
    default: break;
  }
  const uint8_t word = static_cast<uint8_t>(reg & ~1u);  // the low byte names a 2-byte command
  if (word >= BQ952_CELL_VOLTAGE(1) && word <= BQ952_CELL_VOLTAGE(BQ952_MAX_CELLS))
    return "Cell " + std::to_string((word - BQ952_CELL_VOLTAGE(1)) / 2 + 1) + " Voltage";
  if (word >= BQ952_TS_TEMPERATURE(0) && word <= BQ952_TS_TEMPERATURE(BQ952_MAX_TS - 1))
    return "TS" + std::to_string((word - BQ952_TS_TEMPERATURE(0)) / 2 + 1) + " Temperature";
  if (reg >= BQ952_TRANSFER_BUFFER && reg < BQ952_TRANSFER_BUFFER + BQ952_TRANSFER_BUFFER_LEN) return "transfer buffer";
  if (reg != word && (reg == BQ952_BATTERY_STATUS + 1 || reg == BQ952_ALARM_STATUS + 1 || reg == BQ952_ALARM_ENABLE + 1 ||
                      reg == BQ952_STACK_VOLTAGE + 1 || reg == BQ952_PACK_VOLTAGE + 1 || reg == BQ952_LD_VOLTAGE + 1 ||
                      reg == BQ952_CC2_CURRENT + 1 || reg == BQ952_ALARM_RAW_STATUS + 1 || reg == BQ952_INT_TEMPERATURE + 1))
    return directName(word) + " (high byte)";
  return "direct command " + hexByte(reg);
}

// A subcommand's or data-memory address's name, by its code.
std::string subcommandName(uint16_t code) {
  switch (code) {
    case BQ952_SUB_DEVICE_NUMBER: return "DEVICE_NUMBER";
    case BQ952_SUB_RESET: return "RESET";
    case BQ952_SUB_FET_ENABLE: return "FET_ENABLE";
    case BQ952_SUB_MANUFACTURING_STATUS: return "MANUFACTURINGSTATUS";
    case BQ952_SUB_DASTATUS6: return "DASTATUS6";
    case BQ952_SUB_RESET_PASSQ: return "RESET_PASSQ";
    case BQ952_SUB_CB_ACTIVE_CELLS: return "CB_ACTIVE_CELLS";
    case BQ952_SUB_CBSTATUS1: return "CBSTATUS1";
    case BQ952_SUB_SET_CFGUPDATE: return "SET_CFGUPDATE";
    case BQ952_SUB_EXIT_CFGUPDATE: return "EXIT_CFGUPDATE";
    case BQ952_SUB_DSG_PDSG_OFF: return "DSG_PDSG_OFF";
    case BQ952_SUB_CHG_PCHG_OFF: return "CHG_PCHG_OFF";
    case BQ952_SUB_ALL_FETS_OFF: return "ALL_FETS_OFF";
    case BQ952_SUB_ALL_FETS_ON: return "ALL_FETS_ON";
    default: break;
  }
  return (isDataMemory(code) ? "data memory " : "subcommand ") + hexByte(code, 4);
}

}  // namespace

std::unique_ptr<MonitorChain> makeBq76952Chain(const MonitorConfig& cfg, int cellCount, uint64_t seed) {
  return std::make_unique<Bq76952Chain>(cfg, cellCount, seed);
}

Bq76952Chain::Bq76952Chain(const MonitorConfig& cfg, int cellCount, uint64_t seed)
    : cfg_(cfg),
      cells_(cellCount),
      errors_(cellCount, cfg.channel_gain_sd, cfg.channel_offset_sd_V, seed),
      noise_(deriveSeed(seed, 0x952)),
      comm_(deriveSeed(seed, 0x952C)) {
  if (cellCount < 1 || cellCount > static_cast<int>(BQ952_MAX_CELLS))
    throw std::invalid_argument("bq76952: one device holds 1.." + std::to_string(BQ952_MAX_CELLS) + " cells, got " +
                                std::to_string(cellCount));
  if (cfg.thermistors_per_device < 0 || cfg.thermistors_per_device > static_cast<int>(BQ952_MAX_TS))
    throw std::invalid_argument("bq76952: thermistors_per_device must be 0..3");
  analog_.size(cellCount, cfg.thermistors_per_device);
  powerOn(0.0);
}

DeviceAnalog& Bq76952Chain::analog(int d) {
  if (d != 0) throw std::out_of_range("bq76952: one device per bus");
  return analog_;
}

void Bq76952Chain::setCommFault(int d, const MonitorDeviceFault& f) {
  if (d != 0) throw std::out_of_range("bq76952: one device per bus");
  fault_ = f;
}

// One device on its own bus: no link between devices can break below it (a broken
// bus wire is a silent device).
bool Bq76952Chain::replies() const { return !fault_.silent; }

// --- data memory -------------------------------------------------------------

uint8_t Bq76952Chain::dataMemory(uint16_t address) const {
  return isDataMemory(address) ? dm_[address - BQ952_DM_FIRST] : 0;
}

uint16_t Bq76952Chain::dm16(uint16_t address) const {
  return static_cast<uint16_t>(dataMemory(address) | (dataMemory(static_cast<uint16_t>(address + 1)) << 8));
}

// The values the part is programmed with at power-up (its OTP): MonitorConfig::bq in
// the data-memory units.
void Bq76952Chain::initDataMemory() {
  dm_.fill(0);
  const Bq952Protection& p = cfg_.bq;
  auto put16 = [&](uint16_t a, uint16_t v) {
    putDm(a, static_cast<uint8_t>(v & 0xFF));
    putDm(static_cast<uint16_t>(a + 1), static_cast<uint8_t>(v >> 8));
  };
  const uint8_t userAmps = bq952_user_amps_field(static_cast<uint32_t>(std::lround(p.user_amps_A * 1e4)));
  putDm(BQ952_DM_DA_CONFIG, static_cast<uint8_t>(0x04u | userAmps));
  putDm(BQ952_DM_ENABLED_PROT_A, BQ952_SA_CUV | BQ952_SA_COV | BQ952_SA_OCC | BQ952_SA_OCD1 | BQ952_SA_SCD);
  putDm(BQ952_DM_ENABLED_PROT_B, BQ952_SB_UTC | BQ952_SB_UTD | BQ952_SB_OTC | BQ952_SB_OTD | BQ952_SB_OTF);
  // Which faults open which FET (the part's defaults).
  putDm(BQ952_DM_CHG_FET_PROT_A, BQ952_SA_SCD | BQ952_SA_OCC | BQ952_SA_COV);
  putDm(BQ952_DM_CHG_FET_PROT_B, BQ952_SB_OTF | BQ952_SB_OTINT | BQ952_SB_OTC | BQ952_SB_UTINT | BQ952_SB_UTC);
  putDm(BQ952_DM_DSG_FET_PROT_A, BQ952_SA_SCD | BQ952_SA_OCD2 | BQ952_SA_OCD1 | BQ952_SA_CUV);
  putDm(BQ952_DM_DSG_FET_PROT_B, BQ952_SB_OTF | BQ952_SB_OTINT | BQ952_SB_OTD | BQ952_SB_UTINT | BQ952_SB_UTD);
  putDm(BQ952_DM_ENABLED_PROT_C, p.ocd3_A > 0.0 ? BQ952_SC_OCD3 : 0u);
  putDm(BQ952_DM_DSG_FET_PROT_C, BQ952_SC_OCD3);
  const double mvStep = BQ952_COV_CUV_LSB_MV, msStep = BQ952_PROT_DELAY_LSB_MS;
  // A setting the part cannot hold is an error, never a silent clamp.
  auto setting = [](const char* name, double value, double unit, double step, int offset, int lo, int hi) {
    const int n = static_cast<int>(std::nearbyint(value / step)) - offset;
    if (n < lo || n > hi)
      throw std::invalid_argument("bq76952: protection " + std::string(name) + " = " + fmt(value * unit) +
                                  " is outside what the part holds (" + fmt((lo + offset) * step * unit) + " .. " +
                                  fmt((hi + offset) * step * unit) + ")");
    return n;
  };
  putDm(BQ952_DM_CUV_THRESHOLD, static_cast<uint8_t>(setting("cuv_V", p.cuv_V * 1e3, 1e-3, mvStep, 0, BQ952_CUV_MIN, BQ952_CUV_MAX)));
  put16(BQ952_DM_CUV_DELAY, static_cast<uint16_t>(setting("cuv_delay_ms", p.cuv_delay_s * 1e3, 1, msStep, 0, 1, 2047)));
  putDm(BQ952_DM_CUV_RECOVERY_HYST, static_cast<uint8_t>(setting("cuv_recovery_V", p.cuv_recovery_V * 1e3, 1e-3, mvStep, 0, 0, 20)));
  putDm(BQ952_DM_COV_THRESHOLD, static_cast<uint8_t>(setting("cov_V", p.cov_V * 1e3, 1e-3, mvStep, 0, BQ952_COV_MIN, BQ952_COV_MAX)));
  put16(BQ952_DM_COV_DELAY, static_cast<uint16_t>(setting("cov_delay_ms", p.cov_delay_s * 1e3, 1, msStep, 0, 1, 2047)));
  putDm(BQ952_DM_COV_RECOVERY_HYST, static_cast<uint8_t>(setting("cov_recovery_V", p.cov_recovery_V * 1e3, 1e-3, mvStep, 0, 0, 20)));
  const double ocStep = BQ952_OC_THRESHOLD_LSB_MV;
  const int off = BQ952_OC_DELAY_OFFSET;
  putDm(BQ952_DM_OCC_THRESHOLD, static_cast<uint8_t>(setting("occ_mV", p.occ_mV, 1, ocStep, 0, BQ952_OCC_MIN, BQ952_OCC_MAX)));
  putDm(BQ952_DM_OCC_DELAY, static_cast<uint8_t>(setting("occ_delay_ms", p.occ_delay_s * 1e3, 1, msStep, off,
                                                         BQ952_OC_DELAY_MIN, BQ952_OC_DELAY_MAX)));
  putDm(BQ952_DM_OCD1_THRESHOLD, static_cast<uint8_t>(setting("ocd1_mV", p.ocd1_mV, 1, ocStep, 0, BQ952_OCD1_MIN, BQ952_OCD1_MAX)));
  putDm(BQ952_DM_OCD1_DELAY, static_cast<uint8_t>(setting("ocd1_delay_ms", p.ocd1_delay_s * 1e3, 1, msStep, off,
                                                          BQ952_OC_DELAY_MIN, BQ952_OC_DELAY_MAX)));
  const double userA_A = BQ952_USER_AMPS_TENTHS_MA(userAmps) * 1e-4;
  put16(BQ952_DM_OCD3_THRESHOLD, static_cast<uint16_t>(-setting("ocd3_A", p.ocd3_A, 1, userA_A, 0, 0, 32768)));
  putDm(BQ952_DM_OCD3_DELAY, static_cast<uint8_t>(setting("ocd3_delay_ms", p.ocd3_delay_s * 1e3, 1, 1e3, 0, 0, 255)));
  uint8_t scd = 0;  // the nearest setting
  for (uint8_t k = 1; k < BQ952_SCD_SETTINGS; ++k)
    if (std::fabs(kScdThresholds_mV[k] - p.scd_mV) < std::fabs(kScdThresholds_mV[scd] - p.scd_mV)) scd = k;
  putDm(BQ952_DM_SCD_THRESHOLD, scd);
  const uint8_t recovery = static_cast<uint8_t>(setting("current_recovery_ms", p.current_recovery_s * 1e3, 1, 1e3, 0, 0, 255));
  putDm(BQ952_DM_SCD_RECOVERY_TIME, recovery);
  putDm(BQ952_DM_PROT_RECOVERY_TIME, recovery);
  const double h = p.temp_recovery_C;
  const struct {
    uint16_t at;
    double threshold_C, delay_s, recovery_C;
  } temps[] = {
      {BQ952_DM_OTC_THRESHOLD, p.otc_C, p.ot_delay_s, p.otc_C - h}, {BQ952_DM_OTD_THRESHOLD, p.otd_C, p.ot_delay_s, p.otd_C - h},
      {BQ952_DM_OTF_THRESHOLD, p.otf_C, p.ot_delay_s, p.otf_C - h}, {BQ952_DM_UTC_THRESHOLD, p.utc_C, p.ut_delay_s, p.utc_C + h},
      {BQ952_DM_UTD_THRESHOLD, p.utd_C, p.ut_delay_s, p.utd_C + h},
  };
  for (const auto& r : temps) {  // threshold, delay, recovery: three consecutive bytes
    putDm(r.at, static_cast<uint8_t>(setting("temperature threshold (degC)", r.threshold_C, 1, 1, 0, -40, 120)));
    putDm(static_cast<uint16_t>(r.at + 1), static_cast<uint8_t>(setting("ot/ut_delay_ms", r.delay_s * 1e3, 1, 1e3, 0, 0, 255)));
    putDm(static_cast<uint16_t>(r.at + 2), static_cast<uint8_t>(setting("temperature recovery (degC)", r.recovery_C, 1, 1, 0, -40, 120)));
  }
  putDm(BQ952_DM_CB_INTERVAL, 20);
  // Autonomous balancing as configured (the part's defaults: off), one set of
  // thresholds for the charging and the relax case.
  const Bq952AutoBalance& ab = cfg_.bq_balance;
  putDm(BQ952_DM_CB_CONFIG, static_cast<uint8_t>((ab.charging ? BQ952_CB_CHG : 0) | (ab.relax ? BQ952_CB_RLX : 0)));
  putDm(BQ952_DM_CB_MIN_CELL_TEMP, i8(ab.min_cell_temp_C));
  putDm(BQ952_DM_CB_MAX_CELL_TEMP, i8(ab.max_cell_temp_C));
  putDm(BQ952_DM_CB_MAX_INT_TEMP, i8(ab.max_internal_C));
  putDm(BQ952_DM_CB_MAX_CELLS, static_cast<uint8_t>(ab.max_cells));
  const uint16_t minCell_mV = static_cast<uint16_t>(std::lround(ab.min_cell_V * 1e3));
  const uint8_t start_mV = static_cast<uint8_t>(std::lround(ab.start_delta_mV));
  const uint8_t stop_mV = static_cast<uint8_t>(std::lround(ab.stop_delta_mV));
  put16(BQ952_DM_CB_CHG_MIN_CELL_V, minCell_mV);
  putDm(BQ952_DM_CB_CHG_MIN_DELTA, start_mV);
  putDm(BQ952_DM_CB_CHG_STOP_DELTA, stop_mV);
  put16(BQ952_DM_CB_RLX_MIN_CELL_V, minCell_mV);
  putDm(BQ952_DM_CB_RLX_MIN_DELTA, start_mV);
  putDm(BQ952_DM_CB_RLX_STOP_DELTA, stop_mV);
  put16(BQ952_DM_DSG_CURRENT_THRESHOLD, 100);  // userA (1 mA)
  put16(BQ952_DM_CHG_CURRENT_THRESHOLD, 50);
  put16(BQ952_DM_MFG_STATUS_INIT, 0);  // FET test mode until the host sends FET_ENABLE
}

void Bq76952Chain::decodeSettings() {
  Settings& s = s_;
  s.enabledA = dataMemory(BQ952_DM_ENABLED_PROT_A);
  s.enabledC = dataMemory(BQ952_DM_ENABLED_PROT_C);
  s.dsgFetC = dataMemory(BQ952_DM_DSG_FET_PROT_C);
  s.enabledB = dataMemory(BQ952_DM_ENABLED_PROT_B);
  s.chgFetA = dataMemory(BQ952_DM_CHG_FET_PROT_A);
  s.chgFetB = dataMemory(BQ952_DM_CHG_FET_PROT_B);
  s.dsgFetA = dataMemory(BQ952_DM_DSG_FET_PROT_A);
  s.dsgFetB = dataMemory(BQ952_DM_DSG_FET_PROT_B);
  const double mvStep = BQ952_COV_CUV_LSB_MV * 1e-3, sStep = BQ952_PROT_DELAY_LSB_MS * 1e-3;
  s.cuv_V = dataMemory(BQ952_DM_CUV_THRESHOLD) * mvStep;
  s.cuv_delay_s = dm16(BQ952_DM_CUV_DELAY) * sStep;
  s.cuv_recovery_V = dataMemory(BQ952_DM_CUV_RECOVERY_HYST) * mvStep;
  s.cov_V = dataMemory(BQ952_DM_COV_THRESHOLD) * mvStep;
  s.cov_delay_s = dm16(BQ952_DM_COV_DELAY) * sStep;
  s.cov_recovery_V = dataMemory(BQ952_DM_COV_RECOVERY_HYST) * mvStep;
  s.occ_mV = dataMemory(BQ952_DM_OCC_THRESHOLD) * BQ952_OC_THRESHOLD_LSB_MV;
  s.occ_delay_s = (dataMemory(BQ952_DM_OCC_DELAY) + BQ952_OC_DELAY_OFFSET) * sStep;
  s.ocd1_mV = dataMemory(BQ952_DM_OCD1_THRESHOLD) * BQ952_OC_THRESHOLD_LSB_MV;
  s.ocd1_delay_s = (dataMemory(BQ952_DM_OCD1_DELAY) + BQ952_OC_DELAY_OFFSET) * sStep;
  s.scd_mV = kScdThresholds_mV[dataMemory(BQ952_DM_SCD_THRESHOLD) % BQ952_SCD_SETTINGS];
  s.ocd3_delay_s = dataMemory(BQ952_DM_OCD3_DELAY);
  s.current_recovery_s = dataMemory(BQ952_DM_PROT_RECOVERY_TIME);
  s.scd_recovery_s = dataMemory(BQ952_DM_SCD_RECOVERY_TIME);
  auto temp = [&](uint16_t at, double& thr, double& delay, double& rec) {
    thr = dmI8(at);
    delay = dataMemory(static_cast<uint16_t>(at + 1));
    rec = dmI8(static_cast<uint16_t>(at + 2));
  };
  temp(BQ952_DM_OTC_THRESHOLD, s.otc_C, s.otc_delay_s, s.otc_recovery_C);
  temp(BQ952_DM_OTD_THRESHOLD, s.otd_C, s.otd_delay_s, s.otd_recovery_C);
  temp(BQ952_DM_OTF_THRESHOLD, s.otf_C, s.otf_delay_s, s.otf_recovery_C);
  temp(BQ952_DM_UTC_THRESHOLD, s.utc_C, s.utc_delay_s, s.utc_recovery_C);
  temp(BQ952_DM_UTD_THRESHOLD, s.utd_C, s.utd_delay_s, s.utd_recovery_C);
  s.userA_A = BQ952_USER_AMPS_TENTHS_MA(dataMemory(BQ952_DM_DA_CONFIG) & 0x03u) * 1e-4;
  s.cb_interval_s = dataMemory(BQ952_DM_CB_INTERVAL);
  s.cbConfig = dataMemory(BQ952_DM_CB_CONFIG);
  s.cbMinCell_C = dmI8(BQ952_DM_CB_MIN_CELL_TEMP);
  s.cbMaxCell_C = dmI8(BQ952_DM_CB_MAX_CELL_TEMP);
  s.cbMaxInt_C = dmI8(BQ952_DM_CB_MAX_INT_TEMP);
  s.cbMaxCells = dataMemory(BQ952_DM_CB_MAX_CELLS);
  const uint16_t minV[2] = {BQ952_DM_CB_CHG_MIN_CELL_V, BQ952_DM_CB_RLX_MIN_CELL_V};
  const uint16_t start[2] = {BQ952_DM_CB_CHG_MIN_DELTA, BQ952_DM_CB_RLX_MIN_DELTA};
  const uint16_t stop[2] = {BQ952_DM_CB_CHG_STOP_DELTA, BQ952_DM_CB_RLX_STOP_DELTA};
  for (int m = 0; m < 2; ++m) {
    s.cbMinCell_mV[m] = static_cast<int16_t>(dm16(minV[m]));
    s.cbStartDelta_mV[m] = dataMemory(start[m]);
    s.cbStopDelta_mV[m] = dataMemory(stop[m]);
  }
  s.ocd3_A = -static_cast<int16_t>(dm16(BQ952_DM_OCD3_THRESHOLD)) * s.userA_A;
  s.chgThreshold_A = static_cast<int16_t>(dm16(BQ952_DM_CHG_CURRENT_THRESHOLD)) * s.userA_A;
  s.dsgThreshold_A = static_cast<int16_t>(dm16(BQ952_DM_DSG_CURRENT_THRESHOLD)) * s.userA_A;
}

// --- power-up ------------------------------------------------------------------

void Bq76952Chain::powerOn(double t) {
  initDataMemory();
  decodeSettings();
  cfgUpdate_ = false;
  fetEnabled_ = (dm16(BQ952_DM_MFG_STATUS_INIT) & BQ952_MFG_FET_EN) != 0;
  hostChgOff_ = hostDsgOff_ = false;
  por_ = true;
  alarmStatus_ = BQ952_AL_INITCOMP;
  alarmEnable_ = BQ952_AL_ENABLE_DEFAULT;
  alertA_ = alertB_ = alertC_ = statusA_ = statusB_ = statusC_ = 0;
  cov_ = cuv_ = occ_ = ocd1_ = ocd3_ = otc_ = otd_ = otf_ = utc_ = utd_ = DebounceTimer{};
  currentTrip_s = -1.0;
  heldAt_s = -1.0;
  cc_As = 0.0;
  ccLast_s = ccSince_s = t;
  balanceMask_ = autoMask_ = 0;
  autoEval_s = -1.0;
  subLo_ = subHi_ = checksum_ = length_ = 0;
  buffer_.fill(0);
  subReady_s = t;
}

// --- measurement loop and protections ----------------------------------------------

void Bq76952Chain::measure(double t) {
  const double lsb = cfg_.cell_adc.lsb;
  // The loop pauses a cell's balancing while it converts that cell (TRM 10.2): each cell
  // reads without its I_bal·R drop; the stack slot pauses only the top cell.
  const std::vector<double>& unloaded = analog_.cellsSeen(true);
  // Noise is drawn in a fixed order: cells, stack, thermistors.
  for (int c = 0; c < cells_; ++c) {
    const size_t i = static_cast<size_t>(c);
    const double v = unloaded[i];
    heldPin_V[i] = v * (1.0 + analog_.cell_gain_error[i]) + analog_.cell_offset_V[i];
    cell_mV[i] = i16(static_cast<double>(errors_.convert(cfg_.cell_adc, i, analog_, i, v, noise_)) * lsb * 1e3);
  }
  stackCells_V_ = analog_.cell_V;
  stackCells_V_.back() = unloaded.back();
  const double stack_V = moduleVoltage(stackCells_V_, cfg_.module_noise_V, noise_);
  stack_userV = u16(stack_V * 1e3 / BQ952_USERV_MV);
  pack_userV = ld_userV = stack_userV;
  for (int k = 0; k < static_cast<int>(BQ952_MAX_TS); ++k) {
    const size_t i = static_cast<size_t>(k);
    if (k >= cfg_.thermistors_per_device) {
      ts_dK[i] = 2982;  // unused input: 25 degC
      heldTs_C[i] = 25.0;
      continue;
    }
    const ThermistorFault f = analog_.therm_fault[i];
    // The protections compare the device's own reading: a shorted NTC looks
    // infinitely hot, an open one infinitely cold.
    heldTs_C[i] = f == ThermistorFault::Open ? -273.0 : f == ThermistorFault::Short ? 1000.0 : analog_.therm_C[i];
    ts_dK[i] = thermistor_dK(cfg_.thermistor, thermistorCode(cfg_.thermistor, f, analog_.therm_C[i], noise_));
  }
  intTemp_dK = u16((analog_.die_C + 273.15) * 10.0);
  heldCurrent_A = analog_.current_A;
  cc2_userA = i16(-analog_.current_A / s_.userA_A);
  heldAt_s = t;
  alarmStatus_ |= BQ952_AL_FULLSCAN | BQ952_AL_ADSCAN;
}

void Bq76952Chain::protect(double t) {
  const Settings& p = s_;
  double vmax = -1e9, vmin = 1e9;
  for (int c = 0; c < cells_; ++c) {
    vmax = std::max(vmax, heldPin_V[static_cast<size_t>(c)]);
    vmin = std::min(vmin, heldPin_V[static_cast<size_t>(c)]);
  }
  double tmax = -1e9, tmin = 1e9, tfet = -1e9;
  for (int k = 0; k < cfg_.thermistors_per_device; ++k) {
    const double T = heldTs_C[static_cast<size_t>(k)];
    if ((cfg_.fet_inputs >> k) & 1u) {
      tfet = std::max(tfet, T);  // an input on the FETs
      continue;
    }
    tmax = std::max(tmax, T);
    tmin = std::min(tmin, T);
  }
  const double shunt_mV = heldCurrent_A * cfg_.shunt_ohm * 1e3;  // + discharge
  const uint8_t enA = p.enabledA, enB = p.enabledB, enC = p.enabledC;
  uint8_t alertA = 0, alertB = 0, alertC = 0, A = statusA_, B = statusB_, C = statusC_;
  // One row per protection: alert condition, debounce, set and recovery.
  auto row = [&](uint8_t& alert, uint8_t& reg, uint8_t en, uint8_t bit, bool cond, DebounceTimer& timer, double delay_s,
                 bool recovered) {
    if (!(en & bit)) {
      timer = DebounceTimer{};
      reg = static_cast<uint8_t>(reg & ~bit);
      return;
    }
    if (cond) alert = static_cast<uint8_t>(alert | bit);
    if (timer.held(t, cond, delay_s)) reg = static_cast<uint8_t>(reg | bit);
    if (recovered) reg = static_cast<uint8_t>(reg & ~bit);
  };
  // Voltage: recovery by hysteresis.
  row(alertA, A, enA, BQ952_SA_COV, vmax > p.cov_V, cov_, p.cov_delay_s, vmax < p.cov_V - p.cov_recovery_V);
  row(alertA, A, enA, BQ952_SA_CUV, vmin < p.cuv_V, cuv_, p.cuv_delay_s, vmin > p.cuv_V + p.cuv_recovery_V);
  // Current: recovery after a time with the condition gone (handled below).
  const uint8_t currentBits = BQ952_SA_OCC | BQ952_SA_OCD1 | BQ952_SA_SCD;
  const uint8_t before = A & currentBits;
  row(alertA, A, enA, BQ952_SA_OCC, -shunt_mV > p.occ_mV, occ_, p.occ_delay_s, false);
  row(alertA, A, enA, BQ952_SA_OCD1, shunt_mV > p.ocd1_mV, ocd1_, p.ocd1_delay_s, false);
  if ((enA & BQ952_SA_SCD) && shunt_mV > p.scd_mV) A = static_cast<uint8_t>(A | BQ952_SA_SCD), alertA |= BQ952_SA_SCD;
  // OCD3: the slow discharge limit, on the coulomb counter's current in userA.
  const bool before3 = (C & BQ952_SC_OCD3) != 0;
  row(alertC, C, enC, BQ952_SC_OCD3, heldCurrent_A > p.ocd3_A, ocd3_, p.ocd3_delay_s, false);
  const bool tripped = (A & currentBits) != 0 || (C & BQ952_SC_OCD3) != 0;
  if (tripped && before == 0 && !before3) currentTrip_s = t;
  const double recovery_s = (A & BQ952_SA_SCD) ? p.scd_recovery_s : p.current_recovery_s;
  if (tripped && t - currentTrip_s >= recovery_s - 1e-9 && std::fabs(shunt_mV) < std::min(p.occ_mV, p.ocd1_mV) &&
      !(heldCurrent_A > p.ocd3_A && (enC & BQ952_SC_OCD3))) {
    A = static_cast<uint8_t>(A & ~currentBits);
    C = static_cast<uint8_t>(C & ~BQ952_SC_OCD3);
  }
  // Temperature: recovery by hysteresis (absolute recovery thresholds).
  row(alertB, B, enB, BQ952_SB_OTC, tmax > p.otc_C, otc_, p.otc_delay_s, tmax < p.otc_recovery_C);
  row(alertB, B, enB, BQ952_SB_OTD, tmax > p.otd_C, otd_, p.otd_delay_s, tmax < p.otd_recovery_C);
  row(alertB, B, enB, BQ952_SB_OTF, tfet > p.otf_C, otf_, p.otf_delay_s, tfet < p.otf_recovery_C);
  row(alertB, B, enB, BQ952_SB_UTC, tmin < p.utc_C, utc_, p.utc_delay_s, tmin > p.utc_recovery_C);
  row(alertB, B, enB, BQ952_SB_UTD, tmin < p.utd_C, utd_, p.utd_delay_s, tmin > p.utd_recovery_C);
  alertA_ = alertA;
  alertB_ = alertB;
  alertC_ = alertC;
  statusA_ = A;
  statusB_ = B;
  statusC_ = C;
}

void Bq76952Chain::advance(double t) {
  now_s = t;
  if (cfgUpdate_) return;  // CONFIG_UPDATE: the loop, protections and FETs stop
  // Readings refresh once per measurement loop.
  if (heldAt_s < 0.0 || t - heldAt_s >= cfg_.measurement_period_s - 1e-9) measure(t);
  protect(t);
  // Coulomb counter: one conversion every 250 ms.
  if (t - ccLast_s >= kCcConversion_s - 1e-9) {
    cc_As += heldCurrent_A * (t - ccLast_s);
    ccLast_s = t;
  }
  // Host balancing ends on the device when the host stops re-arming it.
  if (balanceMask_ != 0 && t - balanceArmed_s >= s_.cb_interval_s - 1e-9) balanceMask_ = 0;
  balanceAutonomously(t);
  alarmStatus_ |= alarmRaw();
}

void Bq76952Chain::balanceAutonomously(double t) {
  const Settings& p = s_;
  if (!(p.cbConfig & (BQ952_CB_CHG | BQ952_CB_RLX)) || balanceMask_ != 0) {
    autoMask_ = 0;
    return;
  }
  if (autoEval_s >= 0.0 && t - autoEval_s < p.cb_interval_s - 1e-9) return;
  autoEval_s = t;
  // Which case: charging (current into the pack above its threshold) or at rest.
  const double charge_A = -heldCurrent_A;
  const bool charging = charge_A > p.chgThreshold_A;
  const bool relaxed = !charging && heldCurrent_A <= p.dsgThreshold_A;
  const int m = charging && (p.cbConfig & BQ952_CB_CHG) ? 0 : relaxed && (p.cbConfig & BQ952_CB_RLX) ? 1 : -1;
  bool tempsOk = (analog_.die_C <= p.cbMaxInt_C);
  for (int k = 0; k < cfg_.thermistors_per_device; ++k)  // the cell thermistors
    if (((cfg_.fet_inputs >> k) & 1u) == 0)
      tempsOk = tempsOk && heldTs_C[static_cast<size_t>(k)] >= p.cbMinCell_C && heldTs_C[static_cast<size_t>(k)] <= p.cbMaxCell_C;
  if (m < 0 || !tempsOk) {
    autoMask_ = 0;
    return;
  }
  // The device's own readings: start above Min Delta, keep until Stop Delta.
  int vmin = 1 << 20;
  for (int c = 0; c < cells_; ++c) vmin = std::min<int>(vmin, cell_mV[static_cast<size_t>(c)]);
  std::array<int, BQ952_MAX_CELLS> order{};
  for (int c = 0; c < cells_; ++c) order[static_cast<size_t>(c)] = c;
  // Highest first, the lower cell first on a tie (a total order: no temporary buffer).
  std::sort(order.begin(), order.begin() + cells_, [&](int a, int b) {
    const int va = cell_mV[static_cast<size_t>(a)], vb = cell_mV[static_cast<size_t>(b)];
    return va != vb ? va > vb : a < b;
  });
  uint16_t pick = 0;
  int picked = 0;
  for (int i = 0; i < cells_ && picked < p.cbMaxCells; ++i) {
    const int c = order[static_cast<size_t>(i)];
    const int v = cell_mV[static_cast<size_t>(c)];
    const bool was = (autoMask_ >> c) & 1u;
    const double delta = v - vmin;
    const bool wanted = v >= p.cbMinCell_mV[m] && (delta >= p.cbStartDelta_mV[m] || (was && delta > p.cbStopDelta_mV[m]));
    const uint16_t neighbours = static_cast<uint16_t>((c > 0 ? 1u << (c - 1) : 0u) | (1u << (c + 1)));
    if (!wanted || (pick & neighbours)) continue;
    pick = static_cast<uint16_t>(pick | (1u << c));
    ++picked;
  }
  autoMask_ = pick;
}

uint16_t Bq76952Chain::alarmRaw() const {
  uint16_t raw = 0;
  if (statusA_) raw |= BQ952_AL_SSA;
  if (statusB_ || statusC_) raw |= BQ952_AL_SSBC;
  if (balanceMask_ | autoMask_) raw |= BQ952_AL_CB;
  if (!chargeFetOn()) raw |= BQ952_AL_XCHG;
  if (!dischargeFetOn()) raw |= BQ952_AL_XDSG;
  return raw;
}

// --- outputs -------------------------------------------------------------------------

bool Bq76952Chain::faultLine() const { return (alarmStatus_ & alarmEnable_) != 0; }

std::string Bq76952Chain::faultCause() const {
  if (!faultLine()) return "";
  const std::string latched = latchedProtections(0xFF, 0xFF, 0xFF);
  return latched.empty() ? "" : "Safety Status " + latched;
}

std::string Bq76952Chain::latchedProtections(uint8_t maskA, uint8_t maskB, uint8_t maskC) const {
  // Safety Status A, B, C (TRM), by register: OTC and UTC are judged whether or not a
  // charge flows.
  const uint8_t latched[3] = {static_cast<uint8_t>(statusA_ & maskA), static_cast<uint8_t>(statusB_ & maskB),
                              static_cast<uint8_t>(statusC_ & maskC)};
  static const struct {
    int reg;  // 0: A, 1: B, 2: C
    uint8_t bit;
    const char* name;
  } kBits[] = {
      {0, BQ952_SA_COV, "COV (cell over-voltage)"},
      {0, BQ952_SA_CUV, "CUV (cell under-voltage)"},
      {0, BQ952_SA_OCC, "OCC (over-current in charge)"},
      {0, BQ952_SA_OCD1, "OCD1 (over-current in discharge)"},
      {0, BQ952_SA_OCD2, "OCD2 (over-current in discharge, second level)"},
      {0, BQ952_SA_SCD, "SCD (short circuit in discharge)"},
      {1, BQ952_SB_OTC, "OTC (over-temperature in charge, judged at any current)"},
      {1, BQ952_SB_OTD, "OTD (over-temperature in discharge)"},
      {1, BQ952_SB_OTF, "OTF (FET over-temperature)"},
      {1, BQ952_SB_OTINT, "OTINT (die over-temperature)"},
      {1, BQ952_SB_UTC, "UTC (under-temperature in charge, judged at any current)"},
      {1, BQ952_SB_UTD, "UTD (under-temperature in discharge)"},
      {1, BQ952_SB_UTINT, "UTINT (die under-temperature)"},
      {2, BQ952_SC_OCD3, "OCD3 (sustained over-current in discharge)"},
  };
  std::string out;
  for (const auto& b : kBits)
    if (latched[b.reg] & b.bit) appendListed(out, b.name);
  return out;
}

bool Bq76952Chain::balancing(int d, int cell) const {
  return d == 0 && cell >= 0 && cell < cells_ && !cfgUpdate_ && ((balanceMask_ | autoMask_) & (1u << cell)) != 0;
}

// Each loop the cell's switch is open for the slots of the cell and its neighbours, the
// top cell's also for the stack slot (one loop in three: VC16, PACK and LD take turns).
// The loop is 18 slots + one per thermistor (up to 3) of 3 ms, or measurement_period_s
// when that is longer (the part's idle slots).
double Bq76952Chain::balancingDuty(int, int cell, double, double) const {
  const int therms = std::min(cfg_.thermistors_per_device, static_cast<int>(BQ952_MAX_TS));
  const double slot_s = BQ952_LOOP_SLOT_US * 1e-6;
  const double loop_s = std::max(cfg_.measurement_period_s, (BQ952_LOOP_BASE_SLOTS + therms) * slot_s);
  double open = 1.0 + (cell > 0 ? 1.0 : 0.0) + (cell < cells_ - 1 ? 1.0 : 0.0);
  if (cell == cells_ - 1) open += 1.0 / 3.0;
  return 1.0 - open * slot_s / loop_s;
}

bool Bq76952Chain::chargeFetOn() const {
  return fetEnabled_ && !cfgUpdate_ && !hostChgOff_ && !(statusA_ & s_.chgFetA) && !(statusB_ & s_.chgFetB);
}

bool Bq76952Chain::dischargeFetOn() const {
  return fetEnabled_ && !cfgUpdate_ && !hostDsgOff_ && !(statusA_ & s_.dsgFetA) && !(statusB_ & s_.dsgFetB) &&
         !(statusC_ & s_.dsgFetC);
}

std::string Bq76952Chain::fetOffCause(bool discharge) const {
  if (discharge ? dischargeFetOn() : chargeFetOn()) return "";
  if (!fetEnabled_) return "FET_EN clear: FET test mode, no FET_ENABLE since power-up or RESET";
  if (cfgUpdate_) return "in CONFIG_UPDATE mode";
  if (discharge ? hostDsgOff_ : hostChgOff_)
    return discharge ? "turned off by the host: DSG_PDSG_OFF or ALL_FETS_OFF" : "turned off by the host: CHG_PCHG_OFF or ALL_FETS_OFF";
  const std::string latched = discharge ? latchedProtections(s_.dsgFetA, s_.dsgFetB, s_.dsgFetC)
                                        : latchedProtections(s_.chgFetA, s_.chgFetB, 0);
  return "a protection in Safety Status" + (latched.empty() ? std::string(" A/B/C") : ": " + latched);
}

uint8_t Bq76952Chain::fetStatus() const {
  return static_cast<uint8_t>((chargeFetOn() ? BQ952_FET_CHG : 0) | (dischargeFetOn() ? BQ952_FET_DSG : 0) |
                              (faultLine() ? BQ952_FET_ALRT_PIN : 0));
}

// --- the bus ---------------------------------------------------------------------------

double Bq76952Chain::transferTime_s(size_t txLen, size_t rxLen) const {
  double bits = static_cast<double>(txLen) * BQ952_I2C_BITS_PER_BYTE + BQ952_I2C_FRAME_BITS;
  if (rxLen > 0) bits += static_cast<double>(1 + rxLen) * BQ952_I2C_BITS_PER_BYTE + 1;  // repeated start + address
  return bits / cfg_.baud;
}

void Bq76952Chain::buildImage(std::array<uint8_t, BQ952_DIRECT_SPACE>& r) const {
  r.fill(0);
  r[BQ952_SAFETY_ALERT_A] = alertA_;
  r[BQ952_SAFETY_STATUS_A] = statusA_;
  r[BQ952_SAFETY_ALERT_B] = alertB_;
  r[BQ952_SAFETY_STATUS_B] = statusB_;
  r[BQ952_SAFETY_ALERT_C] = alertC_;
  r[BQ952_SAFETY_STATUS_C] = statusC_;
  uint16_t battery = static_cast<uint16_t>(BQ952_BS_SEC_FULLACCESS << BQ952_BS_SEC_SHIFT);
  if (cfgUpdate_) battery |= BQ952_BS_CFGUPDATE;
  if (por_) battery |= BQ952_BS_POR;
  if (statusA_ || statusB_ || statusC_) battery |= BQ952_BS_SS;
  putLe16(&r[BQ952_BATTERY_STATUS], battery);
  for (int c = 0; c < cells_; ++c)
    putLe16(&r[BQ952_CELL_VOLTAGE(c + 1)], static_cast<uint16_t>(cell_mV[static_cast<size_t>(c)]));
  putLe16(&r[BQ952_STACK_VOLTAGE], stack_userV);
  putLe16(&r[BQ952_PACK_VOLTAGE], pack_userV);
  putLe16(&r[BQ952_LD_VOLTAGE], ld_userV);
  putLe16(&r[BQ952_CC2_CURRENT], static_cast<uint16_t>(cc2_userA));
  const bool ready = now_s >= subReady_s - 1e-12;
  r[BQ952_SUBCMD_LOW] = ready ? subLo_ : 0xFF;
  r[BQ952_SUBCMD_HIGH] = ready ? subHi_ : 0xFF;
  for (size_t i = 0; i < BQ952_TRANSFER_BUFFER_LEN; ++i) r[BQ952_TRANSFER_BUFFER + i] = buffer_[i];
  r[BQ952_RESP_CHECKSUM] = checksum_;
  r[BQ952_RESP_LENGTH] = length_;
  putLe16(&r[BQ952_ALARM_STATUS], alarmStatus_);
  putLe16(&r[BQ952_ALARM_RAW_STATUS], alarmRaw());
  putLe16(&r[BQ952_ALARM_ENABLE], alarmEnable_);
  putLe16(&r[BQ952_INT_TEMPERATURE], intTemp_dK);
  for (size_t k = 0; k < BQ952_MAX_TS; ++k) putLe16(&r[BQ952_TS_TEMPERATURE(k)], ts_dK[k]);
  r[BQ952_FET_STATUS] = fetStatus();
}

BusTransfer Bq76952Chain::transfer(double t, const uint8_t* tx, size_t txLen, uint8_t* rx, size_t rxLen) {
  BusTransfer r;
  r.duration_s = transferTime_s(txLen, rxLen);
  now_s = std::max(now_s, t);
  // Nobody acknowledges the address: a silent device, a broken bus, another address.
  if (txLen < 2 || !replies() || tx[0] != kAddrW) return r;
  const uint8_t cmd = tx[1];
  const uint8_t* data = tx + 2;
  const size_t n = txLen - 2;
  // Write phase: with CRC each data byte is followed by its CRC; a wrong one (or a
  // missing one) drops the whole write and ends the transaction.
  bool ok = true;
  uint8_t values[2 * BQ952_DIRECT_SPACE];
  size_t count = 0;
  if (cfg_.crc) {
    ok = n % 2 == 0 && n / 2 <= sizeof(values);
    for (size_t k = 0; ok && k < n / 2; ++k) {
      const uint8_t v = data[2 * k];
      const uint8_t want = k == 0 ? crcOf({kAddrW, cmd, v}) : crcOf({v});
      ok = data[2 * k + 1] == want;
      values[count++] = v;
    }
  } else {
    ok = n <= sizeof(values);
    for (size_t k = 0; ok && k < n; ++k) values[count++] = data[k];
  }
  if (!ok) {
    if (receives()) misuse_.note(t, 0, directName(cmd), cfg_.crc ? "write with a bad or missing CRC (dropped)" : "write too long");
    r.received = 0;
    return r;
  }
  if (receives())
    for (size_t k = 0; k < count; ++k) writeRegister(t, static_cast<uint8_t>(cmd + k), values[k]);
  if (rxLen == 0) {
    r.received = 0;
    return r;
  }
  // Read phase from cmd on, the address auto-incrementing.
  {
    const size_t bytes = cfg_.crc ? rxLen / 2 : rxLen;  // with CRC each data byte is followed by its CRC
    noteRead(0, wordsCovered(cmd, bytes, BQ952_CELL_VOLTAGE(1), BQ952_MAX_CELLS),
             wordsCovered(cmd, bytes, BQ952_TS1_TEMPERATURE, BQ952_MAX_TS));
  }
  std::array<uint8_t, BQ952_DIRECT_SPACE> regs;
  buildImage(regs);
  auto at = [&](size_t k) -> uint8_t {
    const size_t a = cmd + k;
    return a < BQ952_DIRECT_SPACE ? regs[a] : 0xFF;
  };
  if (cfg_.crc) {
    for (size_t k = 0; 2 * k + 1 < rxLen; ++k) {
      const uint8_t v = at(k);
      rx[2 * k] = v;
      rx[2 * k + 1] = k == 0 ? crcOf({kAddrW, cmd, kAddrR, v}) : crcOf({v});
    }
    if (rxLen % 2) rx[rxLen - 1] = 0xFF;
  } else {
    for (size_t k = 0; k < rxLen; ++k) rx[k] = at(k);
  }
  // Comm faults act on the bytes.
  corruptReply(fault_, comm_, rx, rxLen);
  r.received = static_cast<int>(rxLen);
  return r;
}

std::string Bq76952Chain::describe(const uint8_t* tx, size_t txLen, size_t rxLen) const {
  if (txLen < 2) return "no command";
  if (tx[0] != kAddrW) return "address " + hexByte(tx[0] >> 1u) + " (not this part's)";
  const uint8_t cmd = tx[1];
  const size_t step = cfg_.crc ? 2 : 1;  // a data byte and, with CRC, its CRC
  const size_t n = (txLen - 2) / step;
  auto data = [&](size_t k) { return tx[2 + k * step]; };
  if (n == 0 && cmd == BQ952_SUBCMD_LOW && rxLen > 2) return "read subcommand reply";
  if (n == 0) return rxLen > 0 ? "read " + directName(cmd) : "address " + directName(cmd);
  if (cmd == BQ952_SUBCMD_LOW && n >= 2) {
    const uint16_t code = static_cast<uint16_t>(data(0) | (data(1) << 8));
    return n > 2 ? "write " + subcommandName(code) + " data (" + std::to_string(n - 2) + " bytes)" : "subcommand " + subcommandName(code);
  }
  if (cmd == BQ952_RESP_CHECKSUM && n >= 2)
    return "transfer checksum and length " + std::to_string(data(1)) + " (apply)";
  return "write " + directName(cmd) + (n > 1 ? " (" + std::to_string(n) + " bytes)" : " = " + hexByte(data(0)));
}

void Bq76952Chain::writeRegister(double t, uint8_t reg, uint8_t v) {
  if (reg == BQ952_SUBCMD_LOW) {
    subLo_ = v;
  } else if (reg == BQ952_SUBCMD_HIGH) {
    subHi_ = v;
    subcommandAddressed(t);
  } else if (reg >= BQ952_TRANSFER_BUFFER && reg < BQ952_TRANSFER_BUFFER + BQ952_TRANSFER_BUFFER_LEN) {
    buffer_[reg - BQ952_TRANSFER_BUFFER] = v;
  } else if (reg == BQ952_RESP_CHECKSUM) {
    checksum_ = v;
  } else if (reg == BQ952_RESP_LENGTH) {
    length_ = v;
    commitTransfer(t);
  } else if (reg == BQ952_ALARM_STATUS || reg == BQ952_ALARM_STATUS + 1) {
    // Write 1 to clear: a bit clears only if its condition is gone.
    const uint16_t mask = static_cast<uint16_t>(reg == BQ952_ALARM_STATUS ? v : v << 8);
    alarmStatus_ = static_cast<uint16_t>(alarmStatus_ & ~(mask & ~alarmRaw()));
  } else if (reg == BQ952_ALARM_ENABLE) {
    alarmEnable_ = static_cast<uint16_t>((alarmEnable_ & 0xFF00) | v);
  } else if (reg == BQ952_ALARM_ENABLE + 1) {
    alarmEnable_ = static_cast<uint16_t>((alarmEnable_ & 0x00FF) | (v << 8));
  } else {
    // Other direct commands are read-only: writes are ignored.
    misuse_.note(t, 0, directName(reg), "read-only direct command written");
  }
}

void Bq76952Chain::setResponse(const uint8_t* data, int len) {
  buffer_.fill(0);
  int sum = subLo_ + subHi_;
  for (int i = 0; i < len; ++i) {
    buffer_[static_cast<size_t>(i)] = data[i];
    sum += data[i];
  }
  checksum_ = static_cast<uint8_t>(~sum & 0xFF);
  length_ = static_cast<uint8_t>(len + 4);
}

void Bq76952Chain::subcommandAddressed(double t) {
  const uint16_t code = static_cast<uint16_t>(subLo_ | (subHi_ << 8));
  subReady_s = t + BQ952_SUBCMD_US * 1e-6;
  uint8_t out[BQ952_TRANSFER_BUFFER_LEN] = {};
  int len = 0;
  if (isDataMemory(code)) {
    len = static_cast<int>(std::min<size_t>(BQ952_TRANSFER_BUFFER_LEN, BQ952_DM_LAST - code + 1u));
    for (int i = 0; i < len; ++i) out[i] = dataMemory(static_cast<uint16_t>(code + i));
    setResponse(out, len);
    return;
  }
  switch (code) {
    case BQ952_SUB_DEVICE_NUMBER:
      putLe16(out, BQ952_DEVICE_NUMBER);
      len = 2;
      break;
    case BQ952_SUB_RESET:
      powerOn(t);
      subLo_ = static_cast<uint8_t>(code & 0xFF), subHi_ = static_cast<uint8_t>(code >> 8);
      subReady_s = t + BQ952_SUBCMD_US * 1e-6;
      break;
    case BQ952_SUB_FET_ENABLE:
      fetEnabled_ = !fetEnabled_;
      break;
    case BQ952_SUB_MANUFACTURING_STATUS:
      putLe16(out, fetEnabled_ ? BQ952_MFG_FET_EN : 0);
      len = 2;
      break;
    case BQ952_SUB_DASTATUS6: {
      // Charge in userAh, positive in charge: integer part, 32-bit fraction, time (s).
      const double q = -cc_As / 3600.0 / s_.userA_A;
      const double whole = std::floor(q);
      putLe32(out, static_cast<uint32_t>(static_cast<int32_t>(whole)));
      putLe32(out + 4, static_cast<uint32_t>(std::min(4294967295.0, std::floor((q - whole) * 4294967296.0))));
      putLe32(out + 8, static_cast<uint32_t>(std::max(0.0, std::floor(now_s - ccSince_s))));
      len = 12;
      break;
    }
    case BQ952_SUB_RESET_PASSQ:
      cc_As = 0.0;
      ccSince_s = t;
      break;
    case BQ952_SUB_CB_ACTIVE_CELLS:
      putLe16(out, static_cast<uint16_t>(balanceMask_ | autoMask_));
      len = 2;
      break;
    case BQ952_SUB_CBSTATUS1:
      putLe16(out, balanceMask_ ? u16(t - balanceStarted_s) : 0);
      len = 2;
      break;
    case BQ952_SUB_SET_CFGUPDATE:
      cfgUpdate_ = true;
      balanceMask_ = autoMask_ = 0;
      break;
    case BQ952_SUB_EXIT_CFGUPDATE:
      if (cfgUpdate_) {
        cfgUpdate_ = false;
        por_ = false;
        decodeSettings();
      }
      break;
    case BQ952_SUB_DSG_PDSG_OFF: hostDsgOff_ = true; break;
    case BQ952_SUB_CHG_PCHG_OFF: hostChgOff_ = true; break;
    case BQ952_SUB_ALL_FETS_OFF: hostChgOff_ = hostDsgOff_ = true; break;
    case BQ952_SUB_ALL_FETS_ON: hostChgOff_ = hostDsgOff_ = false; break;
    default: break;  // not modelled: no data
  }
  setResponse(out, len);
}

void Bq76952Chain::commitTransfer(double t) {
  const int dataLen = static_cast<int>(length_) - 4;
  const uint16_t code = static_cast<uint16_t>(subLo_ | (subHi_ << 8));
  if (dataLen < 1 || dataLen > static_cast<int>(BQ952_TRANSFER_BUFFER_LEN)) {
    misuse_.note(t, 0, subcommandName(code), "transfer length " + std::to_string(length_) + " outside 5..36");
    return;
  }
  int sum = subLo_ + subHi_;
  for (int i = 0; i < dataLen; ++i) sum += buffer_[static_cast<size_t>(i)];
  if (static_cast<uint8_t>(~sum & 0xFF) != checksum_) {  // a corrupted write is not applied
    misuse_.note(t, 0, subcommandName(code), "transfer checksum wrong (write not applied)");
    return;
  }
  if (isDataMemory(code)) {
    // Protected: data memory takes writes only in CONFIG_UPDATE mode.
    if (!cfgUpdate_) return misuse_.note(t, 0, subcommandName(code), "data-memory write outside CONFIG_UPDATE");
    if (code + dataLen - 1 > static_cast<int>(BQ952_DM_LAST))
      return misuse_.note(t, 0, subcommandName(code), "data-memory write past its end");
    for (int i = 0; i < dataLen; ++i) putDm(static_cast<uint16_t>(code + i), buffer_[static_cast<size_t>(i)]);
    return;
  }
  if (code == BQ952_SUB_CB_ACTIVE_CELLS && (dataLen != 2 || cfgUpdate_ || (s_.cbConfig & BQ952_CB_NO_CMD))) {
    misuse_.note(t, 0, subcommandName(code),
                 dataLen != 2 ? "takes 2 bytes, got " + std::to_string(dataLen)
                 : cfgUpdate_ ? "written in CONFIG_UPDATE mode"
                              : "host balancing commands disabled (Balancing Configuration CB_NO_CMD)");
    return;
  }
  if (code == BQ952_SUB_CB_ACTIVE_CELLS) {
    autoMask_ = 0;  // host-controlled balancing takes over
    const unsigned all = (1u << cells_) - 1u, written = buffer_[0] | (buffer_[1] << 8);
    if (written & ~all) misuse_.note(t, 0, subcommandName(code), balanceBitsPastCells(written & ~all, cells_, 4));
    const uint16_t mask = static_cast<uint16_t>(written & all);
    if (mask != 0 && balanceMask_ == 0) balanceStarted_s = t;
    balanceMask_ = mask;
    balanceArmed_s = t;
  }
}

}  // namespace packsim
