#include "bms_monitor.hpp"

namespace bms {

namespace {

uint8_t devices(const Config& c) { return c.afe.deviceCount < kMaxDevices ? c.afe.deviceCount : kMaxDevices; }

// The stack's shape from AfeConfig into the part's driver settings.
void fillShape(const Config& c, MonitorDriverConfig& d) {
  const AfeConfig& a = c.afe;
  d.pl536.bus = PSFW_BUS_MONITOR(0);
  d.pl536.deviceCount = a.deviceCount;
  d.pl536.cellsPerDevice = a.cellsPerDevice;
  d.pl536.cellCount = c.cellCount;
  d.pl536.thermistorsPerDevice = a.thermistorsPerDevice;
  d.pl536.cellLsb_uV = c.scaling.cellLsb_uV;
  d.pl455.bus = PSFW_BUS_MONITOR(0);
  d.pl455.deviceCount = a.deviceCount;
  d.pl455.cellsPerDevice = a.cellsPerDevice;
  d.pl455.cellCount = c.cellCount;
  d.pl455.thermistorsPerDevice = a.thermistorsPerDevice;
  d.pl455.cellLsb_uV = c.scaling.cellLsb_uV;
  d.bq952.deviceCount = a.deviceCount;
  d.bq952.firstBus = PSFW_BUS_MONITOR(0);
  d.bq952.cellsPerDevice = a.cellsPerDevice;
  d.bq952.cellCount = c.cellCount;
  d.bq952.thermistorsPerDevice = a.thermistorsPerDevice;
  d.bq952.crc = a.crcEnabled;
}

}  // namespace

bool monitorInit(const Config& c, MonitorDrivers& m, AcquisitionState& a, psfw_board* b, const psfw_board_api* api) {
  m.cfg = c.drivers;
  fillShape(c, m.cfg);
  switch (c.afe.model) {
    case AfeModel::Bq76pl536a: m.configured = bq536Init(m.cfg.pl536, m.pl536, b, api); break;
    case AfeModel::Bq76pl455a: m.configured = pl455Init(m.cfg.pl455, m.pl455, b, api) == c.afe.deviceCount; break;
    case AfeModel::Bq76952:
      bq952Init(m.bq952, b, api);
      m.configured = true;
      for (uint8_t d = 0; d < devices(c); ++d)
        m.configured = bq952Configure(m.bq952, m.cfg.bq952, d) == FrameResult::Ok && m.configured;
      break;
  }
  monitorReadAll(c, m, a, b, api);
  return m.configured;
}

void monitorReadAll(const Config& c, MonitorDrivers& m, AcquisitionState& a, psfw_board* b, const psfw_board_api* api) {
  FrameResult res[kMaxDevices];
  switch (c.afe.model) {
    case AfeModel::Bq76pl536a: bq536ReadAll(m.cfg.pl536, m.pl536, b, api, a.device, res); break;
    case AfeModel::Bq76pl455a: pl455ReadAll(m.cfg.pl455, m.pl455, b, api, a.device, res); break;
    case AfeModel::Bq76952:
      for (uint8_t d = 0; d < devices(c); ++d) {
        res[d] = bq952Read(m.bq952, m.cfg.bq952, d, a.device[d]);
        if (res[d] == FrameResult::Ok) bq952ServiceBalance(m.bq952, m.cfg.bq952, d);
      }
      break;
  }
  acquireResults(c, a, res, true);
}

void monitorPollAlerts(const Config& c, MonitorDrivers& m, AcquisitionState& a, psfw_board* b,
                       const psfw_board_api* api) {
  FrameResult res[kMaxDevices];
  switch (c.afe.model) {
    case AfeModel::Bq76pl536a: bq536PollFlags(m.cfg.pl536, m.pl536, b, api, a.device, res); break;
    case AfeModel::Bq76pl455a: pl455PollFaults(m.cfg.pl455, m.pl455, b, api, a.device, res); break;
    case AfeModel::Bq76952:
      for (uint8_t d = 0; d < devices(c); ++d) res[d] = bq952PollSafety(m.bq952, m.cfg.bq952, d, a.device[d]);
      break;
  }
  acquireResults(c, a, res, false);
}

void monitorClearFaults(const Config& c, MonitorDrivers& m, psfw_board* b, const psfw_board_api* api) {
  switch (c.afe.model) {
    case AfeModel::Bq76pl536a: bq536ClearFaults(m.cfg.pl536, b, api); break;
    case AfeModel::Bq76pl455a: pl455ClearFaults(m.cfg.pl455, b, api); break;
    case AfeModel::Bq76952:
      for (uint8_t d = 0; d < devices(c); ++d) bq952ClearFaults(m.bq952, m.cfg.bq952, d);
      break;
  }
}

void monitorWriteBalance(const Config& c, MonitorDrivers& m, psfw_board* b, const psfw_board_api* api,
                         const uint32_t* mask, uint32_t time_s) {
  switch (c.afe.model) {
    case AfeModel::Bq76pl536a: bq536SetBalance(m.cfg.pl536, b, api, mask, time_s); break;
    case AfeModel::Bq76pl455a: pl455WriteBalance(m.cfg.pl455, b, api, mask, time_s); break;
    case AfeModel::Bq76952:
      for (uint8_t d = 0; d < devices(c); ++d) {
        uint16_t bits = 0;
        for (uint8_t i = 0; i < afeCellsOf(c.afe, c.cellCount, d); ++i) {
          const uint16_t cell = static_cast<uint16_t>(d * c.afe.cellsPerDevice + i);
          if (mask[cell / 32u] & (1u << (cell % 32u))) bits = static_cast<uint16_t>(bits | (1u << i));
        }
        bq952SetBalance(m.bq952, m.cfg.bq952, d, bits, time_s);
      }
      break;
  }
}

void monitorWriteFets(const Config& c, MonitorDrivers& m, psfw_board*, const psfw_board_api*, bool chargeOn,
                      bool dischargeOn) {
  if (c.afe.model != AfeModel::Bq76952) return;
  for (uint8_t d = 0; d < devices(c); ++d) bq952SetFets(m.bq952, m.cfg.bq952, d, chargeOn, dischargeOn);
}

}  // namespace bms
