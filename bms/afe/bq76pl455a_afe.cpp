// The BQ76PL455A's entry in the driver table (bms_afe_driver.hpp): its flashed settings
// (Pl455Config) with the defaults of its EEPROM, its state in RAM, and the API calls on
// the driver (bq76pl455a_driver.hpp): one UART daisy chain, auto-addressed.
#include <new>

#include "../bms_afe_driver.hpp"
#include "bq76pl455a_driver.hpp"

namespace bms {

namespace {

// The driver's RAM: the flashed settings with the stack's shape filled in, its state.
struct Data {
  Pl455Config cfg;
  Pl455State state;
};
static_assert(sizeof(Data) <= kAfeDataBytes, "BQ76PL455A driver state exceeds kAfeDataBytes");

Data& dataOf(void* data) { return *static_cast<Data*>(data); }

// A CRC failure is read again twice; the device keeps the thresholds its EEPROM holds.
void defaults(AfeSettings& s) {
  Pl455Config p{};
  p.oversamplingLog2 = 0;
  p.comparators = true;
  p.commTimeoutCode = 0;
  p.crcRetries = 2;
  afeSettingsPut(s, p);
}

bool init(const Config& c, void* data, psfw_board* b, const psfw_board_api* api) {
  Data& m = *new (data) Data{};
  m.cfg = afeSettingsGet<Pl455Config>(c.afe.settings);
  m.cfg.bus = PSFW_BUS_MONITOR(0);
  m.cfg.deviceCount = c.afe.deviceCount;
  m.cfg.cellsPerDevice = c.afe.cellsPerDevice;
  m.cfg.cellCount = c.cellCount;
  m.cfg.thermistorsPerDevice = c.afe.thermistorsPerDevice;
  m.cfg.cellLsb_uV = c.scaling.cellLsb_uV;
  return pl455Init(m.cfg, m.state, b, api) == c.afe.deviceCount;
}

void readAll(const Config&, void* data, psfw_board* b, const psfw_board_api* api, DeviceReading* out,
             FrameResult* res) {
  Data& m = dataOf(data);
  pl455ReadAll(m.cfg, m.state, b, api, out, res);
}

void pollAlerts(const Config&, void* data, psfw_board* b, const psfw_board_api* api, DeviceReading* io,
                FrameResult* res) {
  Data& m = dataOf(data);
  pl455PollFaults(m.cfg, m.state, b, api, io, res);
}

void clearFaults(const Config&, void* data, psfw_board* b, const psfw_board_api* api) {
  pl455ClearFaults(dataOf(data).cfg, b, api);
}

void writeBalance(const Config&, void* data, psfw_board* b, const psfw_board_api* api, const uint32_t* mask,
                  uint32_t time_s) {
  pl455WriteBalance(dataOf(data).cfg, b, api, mask, time_s);
}

const AfeDriverApi kApi = {init, readAll, pollAlerts, clearFaults, writeBalance, nullptr, afeRatiometricTemp_dC};

}  // namespace

const AfeDriver afe_bq76pl455a = {"bq76pl455a", &kApi, defaults};

}  // namespace bms
