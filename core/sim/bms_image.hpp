// The firmware image builder: the configuration packsim's core firmware is flashed with,
// from the scenario (nominal datasheet scaling, the settings rows already in firmware
// units, SI protection thresholds -> firmware units, read-out rates and monitor-driver
// settings, OCV table and capacity for the SOC). The hardware around the MCU is
// HardwareSim (core/sim/bms_bridge.hpp).
#pragma once
#include <bms/bms_config.hpp>

#include <cstdint>
#include <vector>

#include "core/scenario/scenario.hpp"

namespace packsim {

bms::Config makeBmsConfig(const Scenario& s);
// The configuration blob of packsim's core firmware: a bms::CoreImage of cfg.
std::vector<uint8_t> coreImage(const bms::Config& cfg);
// The state-estimation part of it (core/sim/soc_config.cpp): the firmware's own OCV
// table, capacity and 1-RC model per series group, EKF tuning, SOH and display tables.
void setSocConfig(bms::SocConfig& c, const Scenario& s);

}  // namespace packsim
