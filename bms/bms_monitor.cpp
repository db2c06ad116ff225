#include "bms_monitor.hpp"

namespace bms {

bool monitorPartKnown(const Config& c) { return apiOf(c) != nullptr; }

bool monitorInit(const Config& c, MonitorDrivers& m, AcquisitionState& a, psfw_board* b, const psfw_board_api* api) {
  const AfeDriverApi* p = apiOf(c);
  m.configured = p != nullptr && p->init(c, m.data, b, api);
  monitorReadAll(c, m, a, b, api);
  return m.configured;
}

void monitorReadAll(const Config& c, MonitorDrivers& m, AcquisitionState& a, psfw_board* b, const psfw_board_api* api) {
  FrameResult res[kMaxDevices];
  const AfeDriverApi* p = apiOf(c);
  if (p == nullptr) return;
  p->readAll(c, m.data, b, api, a.device, res);
  acquireResults(c, a, res, true);
}

void monitorPollAlerts(const Config& c, MonitorDrivers& m, AcquisitionState& a, psfw_board* b,
                       const psfw_board_api* api) {
  FrameResult res[kMaxDevices];
  const AfeDriverApi* p = apiOf(c);
  if (p == nullptr) return;
  p->pollAlerts(c, m.data, b, api, a.device, res);
  acquireResults(c, a, res, false);
}

void monitorClearFaults(const Config& c, MonitorDrivers& m, psfw_board* b, const psfw_board_api* api) {
  const AfeDriverApi* p = apiOf(c);
  if (p != nullptr) p->clearFaults(c, m.data, b, api);
}

void monitorWriteBalance(const Config& c, MonitorDrivers& m, psfw_board* b, const psfw_board_api* api,
                         const uint32_t* mask, uint32_t time_s) {
  const AfeDriverApi* p = apiOf(c);
  if (p != nullptr) p->writeBalance(c, m.data, b, api, mask, time_s);
}

void monitorWriteFets(const Config& c, MonitorDrivers& m, psfw_board* b, const psfw_board_api* api, bool chargeOn,
                      bool dischargeOn) {
  const AfeDriverApi* p = apiOf(c);
  if (p != nullptr && p->writeFets != nullptr) p->writeFets(c, m.data, b, api, chargeOn, dischargeOn);
}

}  // namespace bms
