// Readers for the sections of a scenario file, one file each (load_pack.cpp,
// load_hardware.cpp, load_bms.cpp, load_load.cpp); load_scenario.cpp assembles them.
#pragma once
#include <optional>
#include <string>

#include "core/scenario/scenario.hpp"
#include "core/scenario/yaml_map.hpp"

namespace packsim {



// A curve is a number (constant), {poly: [...], axis}, {x: [...], y: [...], axis}, or a
// 2-D table over temp_C; 1-D forms may add {arrhenius_K, ref_temp_C}.
Curve readCurve(YamlMap& parent, const std::string& key, Range yRange);
// axis_capacity_Ah: what curves over discharged Ah refer to (a preset's capacity); 0:
// the cell's own capacity_Ah. Every curve is checked over SOC 0..1 (curve_domain.hpp).
CellParams readCell(YamlMap m, double axis_capacity_Ah = 0.0);
PackConfig readPack(YamlMap m, const std::string& baseDir);
ThermalConfig readThermal(std::optional<YamlMap> m, int cells);
TimeSeries readAmbient(std::optional<YamlMap> m);
HardwareConfig readHardware(std::optional<YamlMap> hw, const PackConfig& pack);
BmsSettings readBms(std::optional<YamlMap> m);
// load_firmware.cpp: `bms.firmware` (library path resolved against baseDir)
FirmwareSettings readFirmware(std::optional<YamlMap> m, const std::string& baseDir);
// The pack bounds a load: at most load_load.cpp's C-rate per parallel cell.
LoadProfile readLoad(YamlMap m, const std::string& baseDir, const PackConfig& pack);
// Why a load value (A, or W if power) is beyond that C-rate for this pack; "" if it is not.
std::string loadCRateError(const PackConfig& pack, double value, bool power);
// The most current the pack can drive into a dead short: parallel x the highest OCV over
// the lowest R0 of its cell (SOC 0..1, 25 C). No fault current can exceed it.
double shortCircuitCurrent_A(const PackConfig& pack);
RunConfig readRun(std::optional<YamlMap> m, uint64_t seed);
// load_vehicle.cpp: `load: {vehicle, route, driver, sun, standstill_end_s}` (the caller finishes `load`)
VehicleConfig readVehicle(YamlMap& load, const PackConfig& pack, const std::string& baseDir);
// afe: the monitor devices a device fault may name, and the boards (each with its MCU)
// a host_dead may name.
std::vector<FaultInjection> readFaults(YamlMap& root, int series, int parallel, int thermistors, const MonitorConfig& afe);
Expectations readExpect(std::optional<YamlMap> m);
// load_balancing.cpp
PassiveBalancerConfig readPassiveBalancer(YamlMap m);
ActiveBalancerConfig readActiveBalancer(YamlMap m);
// bms.balancing (bal absent: the section is not stated): the firmware's rows and the host's measure_paused
void readBalanceSettings(YamlMap* bal, BmsSettings& b);
ChargerConfig readCharger(YamlMap m);
// load_estimation.cpp: the estimator keys of `bms.soc` (soc absent: not stated; the
// caller finishes the map): the cell-derived ones, and bms.soc.ekf's rows into `image`
SocEstimationSettings readSocEstimation(YamlMap* soc, bms::Config& image);
// ... and the SOC-error keys of `expect` (soc_error_max_below …, capacity_error_below)
void readSocExpectations(YamlMap& expect, Expectations& e);

}  // namespace packsim
