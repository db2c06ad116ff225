#include "core/parts/monitor_parts.hpp"

#include <stdexcept>

namespace packsim {

#define MONITOR_PART(name) extern const MonitorPart part_##name;
#include <bms/afe/monitor_parts.def>
#undef MONITOR_PART

const std::vector<const MonitorPart*>& monitorParts() {
  static const std::vector<const MonitorPart*> parts = {
#define MONITOR_PART(name) &part_##name,
#include <bms/afe/monitor_parts.def>
#undef MONITOR_PART
  };
  return parts;
}

const MonitorPart& monitorPart(const std::string& name) {
  std::string known;
  for (const MonitorPart* p : monitorParts()) {
    if (name == p->name) return *p;
    known += (known.empty() ? "" : ", ") + std::string(p->name);
  }
  throw std::invalid_argument("unknown monitor part '" + name + "' (hardware.afe.model); registered: " + known);
}

uint8_t firmwarePartIndex(const MonitorPart& p) {
  for (uint8_t i = 0; i < bms::afeDriverCount(); ++i)
    if (bms::afeDriver(i) == p.driver) return i;
  throw std::logic_error(std::string("monitor part ") + p.name + ": its driver is not in the firmware's registry");
}

}  // namespace packsim
