// The BQ76PL536A's entry in the driver table (bms_afe_driver.hpp): its flashed settings
// (Bq536Config) with the datasheet's defaults, its state in RAM, and the API calls on
// the driver (bq76pl536a_driver.hpp): one vertical SPI bus, every device read in turn.
#include <new>

#include "../bms_afe_driver.hpp"
#include "bq76pl536a_driver.hpp"

namespace bms {

namespace {

// The driver's RAM: the flashed settings with the stack's shape filled in, its state.
struct Data {
  Bq536Config cfg;
  Bq536State state;
};
static_assert(sizeof(Data) <= kAfeDataBytes, "BQ76PL536A driver state exceeds kAfeDataBytes");

Data& dataOf(void* data) { return *static_cast<Data*>(data); }

// A CRC failure is read again twice; the comparators written at init as the datasheet
// ships them.
void defaults(AfeSettings& s) {
  Bq536Config p{};
  p.crcRetries = 2;
  p.conversionPerChannel_us = 6;
  p.protectionEnabled = true;
  p.cov_mV = 4350;
  p.covDelay_us = 1000000;
  p.cuv_mV = 2500;
  p.cuvDelay_us = 1000000;
  p.ot_C = 65;
  p.otDelay_ms = 1000;
  afeSettingsPut(s, p);
}

bool init(const Config& c, void* data, psfw_board* b, const psfw_board_api* api) {
  Data& m = *new (data) Data{};
  m.cfg = afeSettingsGet<Bq536Config>(c.afe.settings);
  m.cfg.bus = PSFW_BUS_MONITOR(0);
  m.cfg.deviceCount = c.afe.deviceCount;
  m.cfg.cellsPerDevice = c.afe.cellsPerDevice;
  m.cfg.cellCount = c.cellCount;
  m.cfg.thermistorsPerDevice = c.afe.thermistorsPerDevice;
  m.cfg.cellLsb_uV = c.scaling.cellLsb_uV;
  return bq536Init(m.cfg, m.state, b, api);
}

void readAll(const Config&, void* data, psfw_board* b, const psfw_board_api* api, DeviceReading* out,
             FrameResult* res) {
  Data& m = dataOf(data);
  bq536ReadAll(m.cfg, m.state, b, api, out, res);
}

void pollAlerts(const Config&, void* data, psfw_board* b, const psfw_board_api* api, DeviceReading* io,
                FrameResult* res) {
  Data& m = dataOf(data);
  bq536PollFlags(m.cfg, m.state, b, api, io, res);
}

void clearFaults(const Config&, void* data, psfw_board* b, const psfw_board_api* api) {
  bq536ClearFaults(dataOf(data).cfg, b, api);
}

void writeBalance(const Config&, void* data, psfw_board* b, const psfw_board_api* api, const uint32_t* mask,
                  uint32_t time_s) {
  bq536SetBalance(dataOf(data).cfg, b, api, mask, time_s);
}

const AfeDriverApi kApi = {init, readAll, pollAlerts, clearFaults, writeBalance, nullptr, afeRatiometricTemp_dC};

}  // namespace

const AfeDriver afe_bq76pl536a = {"bq76pl536a", &kApi, defaults};

}  // namespace bms
