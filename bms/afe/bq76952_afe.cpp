// The BQ76952's entry in the driver table (bms_afe_driver.hpp): its flashed settings
// (Bq952DriverConfig) with the defaults of its OTP, its state in RAM, and the API calls
// on the driver (bq76952_driver.hpp): one device per I2C bus, each configured, read,
// balanced (re-armed at every read-out) and switching its own FETs.
#include <new>

#include "../bms_afe_driver.hpp"
#include "../bms_measure.hpp"
#include "bq76952_driver.hpp"

namespace bms {

namespace {

// The driver's RAM: the flashed settings with the stack's shape filled in, its state.
struct Data {
  Bq952DriverConfig cfg;
  Bq952Driver drv;
};
static_assert(sizeof(Data) <= kAfeDataBytes, "BQ76952 driver state exceeds kAfeDataBytes");

Data& dataOf(void* data) { return *static_cast<Data*>(data); }

// A CRC failure is read again twice; the part keeps the protections its OTP holds and
// balances only on the host's command.
void defaults(AfeSettings& s) {
  Bq952DriverConfig p{};
  p.crc = true;
  p.crcRetries = 2;
  p.waitForScan = false;
  p.scanTimeout_us = 100000;
  p.userAmps = 1;  // 1 mA
  p.writeProtections = false;
  p.balanceInterval_s = 20;
  p.balancingConfig = 0;
  afeSettingsPut(s, p);
}

bool init(const Config& c, void* data, psfw_board* b, const psfw_board_api* api) {
  Data& m = *new (data) Data{};
  m.cfg = afeSettingsGet<Bq952DriverConfig>(c.afe.settings);
  m.cfg.deviceCount = c.afe.deviceCount;
  m.cfg.firstBus = PSFW_BUS_MONITOR(0);
  m.cfg.cellsPerDevice = c.afe.cellsPerDevice;
  m.cfg.cellCount = c.cellCount;
  m.cfg.thermistorsPerDevice = c.afe.thermistorsPerDevice;
  bq952Init(m.drv, b, api);
  bool configured = true;
  for (uint8_t d = 0; d < afeDevices(c); ++d)
    configured = bq952Configure(m.drv, m.cfg, d) == FrameResult::Ok && configured;
  return configured;
}

// Every device in turn; a good read services its balancing (re-arms it).
void readAll(const Config& c, void* data, psfw_board*, const psfw_board_api*, DeviceReading* out, FrameResult* res) {
  Data& m = dataOf(data);
  for (uint8_t d = 0; d < afeDevices(c); ++d) {
    res[d] = bq952Read(m.drv, m.cfg, d, out[d]);
    if (res[d] == FrameResult::Ok) bq952ServiceBalance(m.drv, m.cfg, d);
  }
}

void pollAlerts(const Config& c, void* data, psfw_board*, const psfw_board_api*, DeviceReading* io,
                FrameResult* res) {
  Data& m = dataOf(data);
  for (uint8_t d = 0; d < afeDevices(c); ++d) res[d] = bq952PollSafety(m.drv, m.cfg, d, io[d]);
}

void clearFaults(const Config& c, void* data, psfw_board*, const psfw_board_api*) {
  Data& m = dataOf(data);
  for (uint8_t d = 0; d < afeDevices(c); ++d) bq952ClearFaults(m.drv, m.cfg, d);
}

// The stack's mask cut into each device's cells.
void writeBalance(const Config& c, void* data, psfw_board*, const psfw_board_api*, const uint32_t* mask,
                  uint32_t time_s) {
  Data& m = dataOf(data);
  for (uint8_t d = 0; d < afeDevices(c); ++d) {
    uint16_t bits = 0;
    for (uint8_t i = 0; i < afeCellsOf(c.afe, c.cellCount, d); ++i) {
      const uint16_t cell = static_cast<uint16_t>(d * c.afe.cellsPerDevice + i);
      if (mask[cell / 32u] & (1u << (cell % 32u))) bits = static_cast<uint16_t>(bits | (1u << i));
    }
    bq952SetBalance(m.drv, m.cfg, d, bits, time_s);
  }
}

void writeFets(const Config& c, void* data, psfw_board*, const psfw_board_api*, bool chargeOn, bool dischargeOn) {
  Data& m = dataOf(data);
  for (uint8_t d = 0; d < afeDevices(c); ++d) bq952SetFets(m.drv, m.cfg, d, chargeOn, dischargeOn);
}

// The part converts its thermistors itself; a reading far outside any battery's range
// is a sensor at a rail.
int16_t temperature_dC(const Config&, const DeviceReading& r, uint8_t input) {
  const int16_t dC = r.temp_dC[input];
  return (dC < -500 || dC > 2000) ? kTempInvalid_dC : dC;
}

const AfeDriverApi kApi = {init, readAll, pollAlerts, clearFaults, writeBalance, writeFets, temperature_dC};

}  // namespace

const AfeDriver afe_bq76952 = {"bq76952", &kApi, defaults};

}  // namespace bms
