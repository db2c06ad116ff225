// A scenario as typed configuration in SI units with defaults: pack, hardware, BMS
// settings, load, ambient, run and output options. core/scenario/load_scenario.cpp
// fills it strictly from YAML; everything downstream trusts it.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/scenario/expect_config.hpp"
#include "core/scenario/faults_config.hpp"
#include "models/cell/ecm.hpp"
#include "models/load/load_profile.hpp"
#include "models/load/time_series.hpp"
#include "models/pack/cell_spread.hpp"
#include "models/sensors/adc.hpp"
#include "models/sensors/current_sense.hpp"
#include "models/sensors/thermistor.hpp"

namespace packsim {

struct PackConfig {
  int series = 1;
  int parallel = 1;
  CellParams cell;
  double initial_soc = 1.0;
  double initial_temp_C = 25.0;
  double interconnect_ohm = 0.0;
  CellSpread spread;
  std::vector<CellOverride> cell_overrides;
};

// Thermal network beyond each cell's own conductance to ambient.
struct ThermalNodeConfig {
  std::string name;
  double heat_capacity_J_per_K = 100.0;
  double g_ambient_W_per_K = 0.0;
  double g_each_cell_W_per_K = 0.0;         // link to every cell
  std::vector<std::pair<int, double>> cell_links;  // (0-based cell, W/K)
};

struct ThermalConfig {
  double cell_to_cell_W_per_K = 0.0;  // between neighbouring cells (storage order)
  double coolant_C = 25.0;
  double g_coolant_W_per_K = 0.0;     // each cell to the coolant
  std::vector<ThermalNodeConfig> nodes;
};

struct HardwareConfig {
  AdcChannel cell_adc;             // in volts: lsb, gain, offset, noise
  Thermistor thermistor;           // one part type for all channels
  std::vector<int> thermistor_cells;  // 0-based cell index each thermistor sits on
  CurrentSense current_sense;
};

struct ProtectionConfig {
  bool enabled = true;
  double threshold = 0.0;   // V, A or °C by protection
  double hysteresis = 0.0;  // same unit
  double delay_s = 0.0;
};

struct BmsSettings {
  double tick_s = 0.01;
  ProtectionConfig cell_overvoltage{true, 4.25, 0.05, 0.5};
  ProtectionConfig cell_undervoltage{true, 3.0, 0.1, 0.5};
  ProtectionConfig overcurrent_discharge{true, 30.0, 1.0, 0.1};
  ProtectionConfig overcurrent_charge{true, 5.0, 0.5, 0.1};
  ProtectionConfig overtemperature{true, 60.0, 5.0, 1.0};
};

struct RunConfig {
  double duration_s = 0.0;          // 0: the load profile's duration
  double stop_after_trip_s = 60.0;  // keep simulating this long after the relay opens on a fault
  double rtol = 1e-6;
  double atol_soc = 1e-9;
  double atol_V = 1e-7;
  double atol_C = 1e-6;
  uint64_t seed = 1;
};

struct OutputConfig {
  double interval_s = 1.0;
};

struct Scenario {
  std::string name;
  std::string description;
  std::string file;   // path it was loaded from ("" for inline text)
  std::string text;   // the YAML as given, stored with the results
  PackConfig pack;
  HardwareConfig hardware;
  BmsSettings bms;
  LoadProfile load;
  TimeSeries ambient_C = TimeSeries::constant(25.0);
  ThermalConfig thermal;
  RunConfig run;
  OutputConfig output;
  std::vector<FaultInjection> faults;
  Expectations expect;

  double endTime_s() const;
};

}  // namespace packsim
