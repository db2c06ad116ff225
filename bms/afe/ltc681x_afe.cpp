// The LTC6811-1's and LTC6813-1's entries in the driver table (bms_afe_driver.hpp): one
// driver (ltc681x_driver.hpp) for both, each table with its part. Their flashed
// settings are the driver's LtcConfig (the stack's shape filled in at init); their RAM
// the driver's state and one LtcReading per device, which stages a device's register
// groups until every group of it passed its PEC -- only then does the core's reading
// of that device change (a device that fails keeps its last good reading).
//
//   read-out     ltcReadAll: ADCV, RDCVx; RDSTATB (+ RDAUXD); ADAX, RDAUXx; ADSTAT,
//                RDSTATA
//   alert poll   ltcPollFlags: ADCV, RDSTATB (+ RDAUXD): the cells' UV / OV flags
//   clear        nothing: the parts latch no fault (CLRSTAT would *set* every flag)
//   balance      DCC bits and the discharge timer (DCTO) the devices enforce
//   thermistors  GPIO codes of VREF2 (30,000 codes of 100 uV): the core's beta model
//                with that full scale
#include <new>

#include "../bms_afe_driver.hpp"
#include "../bms_measure.hpp"
#include "ltc681x_driver.hpp"

namespace bms {

namespace {

// The driver's RAM: the flashed settings with the stack's shape filled in, its state,
// each device's staged reading.
struct Data {
  LtcConfig cfg;
  LtcState state;
  LtcReading reading[kLtcMaxDevices];
};
static_assert(sizeof(Data) <= kAfeDataBytes, "LTC681x driver state exceeds kAfeDataBytes");

Data& dataOf(void* data) { return *static_cast<Data*>(data); }

// The data sheets' normal mode (7 kHz, ADCOPT 0), balancing permitted during
// conversions, the status group read for the sum of cells and the die, a PEC failure
// read again twice; the comparators at the part's extremes until the scenario sets them.
LtcConfig defaultsOf(LtcPart part) {
  LtcConfig p{};
  p.bus = PSFW_BUS_MONITOR(0);
  p.part = part;
  p.adcMode = LTC681X_MD_NORMAL;
  p.adcopt = false;
  p.dischargePermitted = true;
  p.readStatus = true;
  p.ov_mV = 4500;
  p.uv_mV = 1000;
  p.readRetries = 2;
  return p;
}
void defaults6811(AfeSettings& s) { afeSettingsPut(s, defaultsOf(LtcPart::Ltc6811)); }
void defaults6813(AfeSettings& s) { afeSettingsPut(s, defaultsOf(LtcPart::Ltc6813)); }

bool init(const Config& c, void* data, psfw_board* b, const psfw_board_api* api) {
  Data& m = *new (data) Data{};
  m.cfg = afeSettingsGet<LtcConfig>(c.afe.settings);
  m.cfg.deviceCount = c.afe.deviceCount;
  m.cfg.cellsPerDevice = c.afe.cellsPerDevice;
  m.cfg.cellCount = c.cellCount;
  m.cfg.thermistorsPerDevice = c.afe.thermistorsPerDevice;
  m.cfg.period_us = c.readout.period_ms * 1000u;
  return ltcInit(m.cfg, m.state, b, api);
}

// Devices the driver holds: the configured chain, at most kLtcMaxDevices (a longer one
// fails ltcInit and every read-out).
uint8_t devicesOf(const Config& c) {
  const uint8_t n = afeDevices(c);
  return n < kLtcMaxDevices ? n : kLtcMaxDevices;
}

void readAll(const Config& c, void* data, psfw_board* b, const psfw_board_api* api, DeviceReading* out,
             FrameResult* res) {
  Data& m = dataOf(data);
  ltcReadAll(m.cfg, m.state, b, api, m.reading, res);
  for (uint8_t d = 0; d < devicesOf(c); ++d)
    if (res[d] == FrameResult::Ok && !ltcToDeviceReading(m.cfg, d, m.reading[d], out[d])) res[d] = FrameResult::BadLength;
  for (uint8_t d = devicesOf(c); d < afeDevices(c); ++d) res[d] = FrameResult::Timeout;
}

// The flags alone: alert (a used cell outside VUV / VOV) and the flag bytes.
void pollAlerts(const Config& c, void* data, psfw_board* b, const psfw_board_api* api, DeviceReading* io,
                FrameResult* res) {
  Data& m = dataOf(data);
  ltcPollFlags(m.cfg, m.state, b, api, m.reading, res);
  for (uint8_t d = 0; d < devicesOf(c); ++d) {
    if (res[d] != FrameResult::Ok) continue;
    DeviceReading r{};
    if (!ltcToDeviceReading(m.cfg, d, m.reading[d], r)) continue;
    io[d].alert = r.alert;
    io[d].safetyA = r.safetyA;
    io[d].safetyB = r.safetyB;
  }
  for (uint8_t d = devicesOf(c); d < afeDevices(c); ++d) res[d] = FrameResult::Timeout;
}

void clearFaults(const Config&, void*, psfw_board*, const psfw_board_api*) {}

void writeBalance(const Config&, void* data, psfw_board* b, const psfw_board_api* api, const uint32_t* mask,
                  uint32_t time_s) {
  Data& m = dataOf(data);
  ltcSetBalance(m.cfg, m.state, b, api, mask, time_s);
}

// GPIO codes are fractions of VREF2 (the divider's supply): the core's NTC model with
// VREF2's code as the full scale.
int16_t temperature_dC(const Config& c, const DeviceReading& r, uint8_t input) {
  SensorScaling s = c.scaling;
  s.thermFullScaleCode = static_cast<float>(LTC681X_VREF2_MV * 1000u / LTC681X_LSB_UV);
  return thermistorCodeToDeciCelsius(s, r.thermCode[input]);
}

const AfeDriverApi kApi = {init, readAll, pollAlerts, clearFaults, writeBalance, nullptr, temperature_dC};

}  // namespace

const AfeDriver afe_ltc6811 = {"ltc6811", &kApi, defaults6811};
const AfeDriver afe_ltc6813 = {"ltc6813", &kApi, defaults6813};

}  // namespace bms
