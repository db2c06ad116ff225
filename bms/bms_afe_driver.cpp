#include "bms_afe_driver.hpp"

#include "bms_measure.hpp"

namespace bms {

const AfeDriver* const kAfeDrivers[] = {
#define MONITOR_PART(name) &afe_##name,
#include "afe/monitor_parts.def"
#undef MONITOR_PART
};
const uint8_t kAfeDriverCount = static_cast<uint8_t>(sizeof kAfeDrivers / sizeof kAfeDrivers[0]);

bool afeSelect(Config& c, uint8_t part) {
  const AfeDriver* d = afeDriver(part);
  if (d == nullptr) return false;
  c.afe.part = part;
  c.afe.settings = AfeSettings{};
  d->defaults(c.afe.settings);
  return true;
}

int16_t afeRatiometricTemp_dC(const Config& c, const DeviceReading& r, uint8_t input) {
  return thermistorCodeToDeciCelsius(c.scaling, r.thermCode[input]);
}

uint8_t afeDevices(const Config& c) { return c.afe.deviceCount < kMaxDevices ? c.afe.deviceCount : kMaxDevices; }

}  // namespace bms
