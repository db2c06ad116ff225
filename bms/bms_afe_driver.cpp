#include "bms_afe_driver.hpp"

#include "bms_measure.hpp"

namespace bms {

namespace {

const AfeDriver* const kDrivers[] = {
#define MONITOR_PART(name) &afe_##name,
#include "afe/monitor_parts.def"
#undef MONITOR_PART
};
constexpr uint8_t kDriverCount = static_cast<uint8_t>(sizeof kDrivers / sizeof kDrivers[0]);

}  // namespace

uint8_t afeDriverCount() { return kDriverCount; }

const AfeDriver* afeDriver(uint8_t part) { return part < kDriverCount ? kDrivers[part] : nullptr; }

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
