// A scenario as typed configuration in SI units with defaults: pack, hardware, BMS
// settings, load, ambient, run and output options. core/scenario/load_scenario.cpp
// fills it strictly from YAML; everything downstream trusts it.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <bms/bms_config.hpp>

#include "core/scenario/expect_config.hpp"
#include "core/scenario/faults_config.hpp"
#include "core/scenario/protection_table.hpp"
#include "core/scenario/thermistor_table.hpp"
#include "core/scenario/vehicle_config.hpp"
#include "core/scenario/firmware_config.hpp"
#include "models/afe/monitor_config.hpp"
#include "models/balance/active_balancer.hpp"
#include "models/balance/passive_balancer.hpp"
#include "models/cell/ecm.hpp"
#include "models/hw/charger.hpp"
#include "models/hw/fuse.hpp"
#include "models/hw/mosfet.hpp"
#include "models/hw/precharge.hpp"
#include "models/hw/relay.hpp"
#include "models/load/load_profile.hpp"
#include "models/load/time_series.hpp"
#include "models/pack/cell_spread.hpp"
#include "models/sensors/adc.hpp"
#include "models/sensors/current_sense.hpp"
#include "models/sensors/thermistor.hpp"

namespace packsim {

class Provenance;  // core/scenario/provenance.hpp

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
  double heat_W = 0.0;                      // a constant heat input from outside the pack (sun, a motor)
  std::vector<std::pair<int, double>> cell_links;  // (0-based cell, W/K)
  std::vector<std::pair<std::string, double>> node_links;  // (other node's name, W/K), e.g. an enclosure
};

struct ThermalConfig {
  double cell_to_cell_W_per_K = 0.0;  // between neighbouring cells (storage order)
  double coolant_C = 25.0;
  double g_coolant_W_per_K = 0.0;     // each cell to the coolant
  std::vector<ThermalNodeConfig> nodes;
};

// A data frame the vehicle / charger sends on a board alone's CAN bus (hardware.can.frames):
// ready at at_s, and again every period_s (> 0) up to until_s.
struct ScriptedCanFrame {
  double at_s = 0.0;
  uint32_t id = 0;            // 11-bit identifier
  std::vector<uint8_t> data;  // 0-8 bytes
  double period_s = 0.0;
  double until_s = 0.0;       // with a period: the last instant a copy may be ready
};

struct HardwareConfig {
  AdcChannel cell_adc;             // in volts: lsb, gain, offset, noise
  Thermistor thermistor;           // one part type for all channels
  std::vector<ThermistorSite> thermistor_sites;  // hardware.thermistors, in channel (wiring) order
  CurrentSense current_sense;
  // Monitor ICs and switching hardware (issue 3; docs/scenario.md `hardware.afe` …).
  MonitorConfig afe;                  // cell_adc above is its cell channel
  RelayConfig relay;                  // main normally-open relay
  RelayConfig precharge_relay;        // precharge path switch
  PrechargePathConfig precharge;      // resistor into the load-bus capacitance
  MosfetConfig discharge_fet;         // with the diode that carries charge current
  MosfetConfig charge_fet;            // absent unless configured
  FetPaths fet_paths = FetPaths::Series;  // hardware.fet_paths
  FetControl fet_control = FetControl::Mcu;  // hardware.fet_control (the loader: Afe with a part with FETs)
  FuseConfig fuse;                    // absent unless configured
  AdcChannel bus_adc;                 // load-bus voltage divider into an ADC (volts)
  bool fault_line_opens_relay = true; // monitor FAULT line in series with the relay coil drive
  // Balancing (issue 5; docs/scenario.md `hardware.balancing`, `hardware.active_balancer`).
  PassiveBalancerConfig balancing;     // resistor + FET per cell, heat into a board node
  ActiveBalancerConfig active_balancer;  // converters per module to a supercap bus
  double can_bitrate_bps = 500000.0;  // the CAN bus between the monitor boards' MCUs (hardware.can)
  bool can_alone = false;             // hardware.can on a board alone: a bus to the vehicle / charger
  std::vector<ScriptedCanFrame> can_frames;  // hardware.can.frames: what the vehicle / charger sends
  // The BMS board's supply (hardware.mcu_supply): its 12 V rail, and the rail voltage
  // below which the MCU is held in brown-out reset (a supply_brownout fault).
  double supply_nominal_V = 12.0;
  double supply_brownout_V = 4.0;
  // Every thermistor channel: the sites above, then the balancing boards'. Built once by
  // the loader from those (thermistor_table.hpp); everyone reads the channels here.
  ThermistorTable thermistors;
};

// The host's balancing measurement (not a firmware setting: the simulated monitor ICs).
struct BalanceMeasurement {
  bool measure_paused = true;  // switches open for each conversion (no I_bal·R0 in the readings)
};

// The firmware's state estimation (docs/state-estimation.md): its own cell model, as
// flashed, where it comes from the pack's cell. Negative / empty values mean "from the
// pack's cell" (the datasheet a firmware engineer would copy); bms.soc's other keys
// (estimator, the EKF's noise, the rest) are rows of bms/bms_settings.def.
struct SocEstimationSettings {
  double cell_capacity_Ah = -1.0;
  std::vector<double> ocv_V;           // OCV at SOC 0 .. 1, evenly spaced (2..16 points)
  std::vector<double> cell_r0_ohm;     // one value, or one per OCV point; empty: the cell's R0 at those points
  double cell_r1_ohm = -1.0;
  double tau1_s = -1.0;
  double r0_arrhenius_K = -1.0;        // R0's temperature factor; < 0: the cell's (0: none)
  double r0_ref_temp_C = 25.0;         // where cell_r0_ohm (given or the cell's) holds
  double initial_soc = -1.0;           // EKF start; < 0: from the first reading's OCV
  std::vector<double> display_bars_V;  // 7 thresholds; empty: reference system C's table
};

// How often packsim's core reads its monitor ICs (bms::ReadoutConfig). 0: every tick.
struct ReadoutSettings {
  double period_s = 0.0;        // full read-out: cells, temperatures, the devices' flags
  double alert_period_s = 0.0;  // the devices' protection flags alone, between read-outs (0: none)
};

struct BmsSettings {
  double tick_s = 0.01;
  ReadoutSettings readout;
  // One per bms::FaultId, defaults from the firmware table (core/scenario/protection_table.hpp).
  std::array<ProtectionConfig, bms::kFaultCount> protections = defaultProtections();
  // The scalar firmware settings (bms/bms_settings.def: comm loss, weld detection,
  // precharge, SOC rest and estimator, balancing policy, ...) in firmware units, as the
  // loader read them; only those rows' fields of this image are meaningful
  // (core/scenario/bms_setting_table.hpp). The bridge fills the rest from the pack.
  bms::Config image = bms::defaultConfig(0, 0);
  SocEstimationSettings soc_estimation;
  bool run_request = true;          // GPIO levels held for the run
  bool charger_present = false;
  BalanceMeasurement balancing;
  double charge_current_A = 0.0;    // charger current request; 0: the charger's own current_A

  ProtectionConfig& protection(bms::FaultId id) { return protections[static_cast<size_t>(id)]; }
  const ProtectionConfig& protection(bms::FaultId id) const { return protections[static_cast<size_t>(id)]; }
  FirmwareSettings firmware;        // absent: packsim's own core (bms/)
};

struct RunConfig {
  double duration_s = 0.0;          // 0: the load profile's duration
  double stop_after_trip_s = 60.0;  // keep simulating this long after the relay opens on a fault
  double rtol = 1e-6;
  double atol_soc = 1e-9;
  double atol_V = 1e-7;
  double atol_C = 1e-6;
  uint64_t seed = 1;
  // Integrator (core/sim/integrator.hpp): CVODE is the reference; fast takes fixed
  // sub-steps per tick (core/sim/fast_integrator.hpp).
  enum class Solver { Cvode, Fast };
  Solver solver = Solver::Cvode;
  // CVODE's Newton matrix (core/sim/cvode_integrator.hpp): the sparse Jacobian through
  // KLU, or only its diagonal (CVDiag) for runs whose inputs switch every few steps.
  enum class Jacobian { Sparse, Diagonal };
  Jacobian jacobian = Jacobian::Sparse;  // run.jacobian (solver cvode only)
  double fast_max_substep_s = 0.0;      // run.fast.max_substep_s; 0: no cap beyond the rule
  double fast_substep_fraction = 0.1;   // run.fast.substep_fraction of the smallest time constant
};

struct OutputConfig {
  double interval_s = 1.0;
  bool bus_trace = false;  // every monitor-bus transaction to the result file's /bus_trace
};

struct Scenario {
  std::string name;
  std::string description;
  std::string file;   // path it was loaded from ("" for inline text)
  std::string text;   // the YAML as given, stored with the results
  // Every file the loader read for it (the given file itself only when it read that:
  // loadScenarioFile; core/scenario/files_read.hpp)
  std::vector<std::string> files_read;
  PackConfig pack;
  HardwareConfig hardware;
  BmsSettings bms;
  LoadProfile load;
  ChargerConfig charger;  // `load: {charger: {...}}`: the pack sits on a CC-CV charger
  VehicleConfig vehicle;  // `load: {vehicle: {...}, route: {...}}`: a vehicle drives the load (docs/vehicle.md)
  TimeSeries ambient_C = TimeSeries::constant(25.0);
  ThermalConfig thermal;
  RunConfig run;
  OutputConfig output;
  std::vector<FaultInjection> faults;
  Expectations expect;
  // `compare: {scenario: other.yaml}`: a reference scenario (path resolved) run as well,
  // so the summary states what this run lost or gained against it (core/sim/comparison).
  std::string compare_scenario;
  // Where each value came from and what looks wrong (`packsim show`, docs/scenario.md):
  // set by the loader; warnings are `config_warning` events at the start of a run.
  std::shared_ptr<const Provenance> provenance;
  std::vector<std::string> warnings;

  double endTime_s() const;
};

}  // namespace packsim
