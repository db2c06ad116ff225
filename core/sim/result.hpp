// What a run produces: the recorded time series (truth, what the BMS measured, what
// it decided), the events table, the summary and solver statistics.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/sim/balance_summary.hpp"
#include "core/sim/charge_summary.hpp"
#include "core/sim/cvode_integrator.hpp"
#include "core/sim/soc_error.hpp"
#include "core/sim/vehicle_summary.hpp"

namespace packsim {

struct Event {
  double time_s = 0.0;
  std::string kind;    // bms_state, fault_active, fault_latched, relay, run
  std::string detail;
};

// One direction of a monitor-bus transaction (output.bus_trace; core/sim/bus_trace.hpp).
struct BusTraceRow {
  double time_s = 0.0;     // out: when the MCU started it; in: when the reply ended
  int bus = 0;             // the monitor board whose bus it is (its host's monitor bus 0)
  bool out = true;         // true: MCU -> part; false: part -> MCU
  int count = 0;           // bytes; in: -1 when nothing answered (a time-out)
  std::string bytes;       // hex, space-separated
  std::string what;        // the part's decoding (MonitorChain::describe)
};

// One frame on a board alone's CAN bus to the vehicle / charger (hardware.can;
// core/firmware/can_bus.hpp), as it went on the wire.
struct CanTraceRow {
  double time_s = 0.0;  // its start of frame
  double end_s = 0.0;   // its end: the receivers have it
  bool out = true;      // true: the firmware sent it; false: the scenario's (hardware.can.frames)
  int id = 0;
  int dlc = 0;
  std::string data;     // hex, space-separated
  bool lost = false;    // in: the MCU's receive FIFO was full
};

// Per-sample arrays are row-major [sample][channel]. Each vector is one row of the
// result-channel table (core/sim/result_channels.hpp), which fills and writes it.
struct Recording {
  int cells = 0;        // series·parallel
  int groups = 0;       // series positions the monitor ICs read
  int thermistors = 0;
  std::vector<double> time_s;
  // truth
  std::vector<double> cell_voltage_V, cell_current_A, cell_soc, cell_temp_C;
  std::vector<double> pack_voltage_V, pack_current_A;
  // measured: exactly what the BMS core saw, in its own units
  std::vector<uint16_t> meas_cell_voltage_mV;
  std::vector<int16_t> meas_temperature_dC;  // -32768: sensor open/short
  std::vector<int32_t> meas_current_mA;
  // BMS decisions
  std::vector<uint8_t> bms_state;
  std::vector<uint32_t> fault_active, fault_latched;
  std::vector<uint8_t> relay_closed, discharge_fet_on, charge_fet_on;
  // firmware internals and telemetry (issue 3)
  int devices = 0;                            // monitor ICs
  std::vector<uint8_t> precharge_closed, precharge_phase, monitor_fault;
  std::vector<uint16_t> soc_estimate_permille;
  std::vector<uint32_t> meas_bus_voltage_mV;
  std::vector<uint8_t> comm_bad;              // [sample][device] consecutive bad replies
  std::vector<uint8_t> telemetry;             // [sample][bms::kTelemetryFrameBytes]
  // switching hardware as it actually is
  std::vector<uint8_t> hw_relay_closed, hw_precharge_closed, hw_fuse_blown, hw_discharge_fet_on, hw_charge_fet_on,
      hw_fault_line;
  std::vector<double> hw_bus_voltage_V, hw_fet_loss_W;
  // balancing and charging (issue 5): only filled when the scenario has the hardware
  bool has_hardware = false;  // the switching hardware and monitors are recorded (/hardware)
  bool has_balancing = false, has_active_balancer = false, has_charger = false, has_board = false;
  std::vector<double> balance_current_A;      // [sample][series]: passive I_bal, or converter current (+ from the module)
  std::vector<uint8_t> balance_mask;          // [sample][series]: what the BMS commanded
  std::vector<uint8_t> hw_balancing;          // [sample][series]: switch actually on (monitor timer)
  std::vector<uint8_t> balance_status;        // bms::BalanceStatus
  std::vector<double> board_temp_C;           // balancing-board thermal node
  std::vector<double> balancer_bus_V;         // active balancer supercap bus
  std::vector<double> charger_current_A;      // into the pack
  std::vector<uint8_t> charger_enable;        // BMS enable
  std::vector<int32_t> charger_request_mA;
  // state estimation (issue 17): both firmware estimates and the truth they are judged against
  std::vector<double> soc_truth_mean;          // mean cell SOC
  std::vector<double> soc_coulomb, soc_ekf;    // firmware estimates (0 before their first reading)
  std::vector<uint16_t> soc_ekf_group_permille;  // [sample][series]
  std::vector<double> capacity_estimate_Ah;    // SOH: series-group capacity (0: none yet)
  std::vector<uint8_t> soc_display_bars;       // what the SOC display shows (mean measured cell)
  std::vector<uint8_t> soc_display_bars_truth; // what it would show from the true OCV
  // a vehicle on its route (docs/vehicle.md): only filled for `load: {vehicle: ...}`
  bool has_vehicle = false;
  std::vector<double> vehicle_distance_m, vehicle_speed_m_per_s, vehicle_pack_request_W, vehicle_array_W,
      vehicle_array_available_W;
  std::vector<uint8_t> vehicle_limit;

  size_t samples() const { return time_s.size(); }
};

// A reference run of the `compare:` scenario (core/sim/comparison). Losses are the
// chemical energy the cells gave minus the energy delivered (heat, RC charge): the
// energy lost against the reference is this run's losses minus the reference's — for a
// power load (same energy out) the extra energy drawn, for a current load the energy
// out that went missing.
struct Comparison {
  bool present = false;
  std::string name;
  double energy_delivered_Wh = 0.0;
  double losses_Wh = 0.0;       // reference's chemical energy drawn - energy delivered
  double min_cell_V = 0.0;
  double this_losses_Wh = 0.0;  // the same for this run
  double lostWh() const { return this_losses_Wh - losses_Wh; }
};

struct Summary {
  std::string scenario;
  double duration_s = 0.0;
  double charge_delivered_Ah = 0.0;
  double energy_delivered_Wh = 0.0;  // net: out at the terminals less in
  double energy_in_Wh = 0.0;         // in at the terminals (regeneration, a charger), >= 0
  double heat_Wh = 0.0;
  double min_cell_V = 0.0;
  int min_cell = 0;  // 1-based
  double min_cell_time_s = 0.0;
  double max_temp_C = 0.0;
  int hottest_cell = 0;  // 1-based
  double hottest_time_s = 0.0;
  bool tripped = false;
  double trip_time_s = 0.0;
  std::string trip_reason;
  double final_soc_min = 0.0;
  double final_soc_max = 0.0;
  // Energy accounting at the moment the first cell reached its limit (its v_min, or
  // the BMS under-voltage trip); at the end of the run if none did.
  bool limit_reached = false;
  double limit_time_s = 0.0;
  int limit_cell = 0;  // 1-based
  bool limit_by_bms_trip = false;  // the BMS's under-voltage trip came first (limit_cell: the lowest cell then)
  double energy_start_Wh = 0.0;
  double energy_left_Wh = 0.0;
  double energy_stranded_Wh = 0.0;
  // State estimation against the truth (mean cell SOC), per estimator (soc_error.hpp).
  std::string soc_estimator;        // the one the telemetry reports: coulomb | ekf
  SocErrorStats soc_error_coulomb, soc_error_ekf;
  double soc_error_ekf_group_max = 0.0;  // worst |EKF group SOC - the group's true mean SOC|
  int soc_error_ekf_group = 0;           // 1-based series group where it happened
  double capacity_estimate_Ah = 0.0;  // firmware SOH estimate of a series group; 0: none
  double capacity_true_Ah = 0.0;      // mean series-group capacity of the plant
  int display_bars_hidden_max = 0;    // most bars the display showed below the truth's
  int display_bars_extra_max = 0;     // most bars it showed above the truth's
  const SocErrorStats& socErrorSelected() const { return soc_estimator == "ekf" ? soc_error_ekf : soc_error_coulomb; }
  Comparison compare;  // against the `compare:` scenario, when the scenario names one
  // The longest time a cell stayed past a protection limit unseen by the BMS (truth
  // against the protection table; core/sim/limit_watch.hpp), and its event's text.
  double limit_unseen_longest_s = 0.0;
  std::string limit_unseen_longest;
  std::vector<std::string> fet_notes;  // a FET that never conducted although asked for (core/sim/hw_fet_watch.hpp)
  bool relay_closed = false;    // the relay contact closed at some time in the run (a relay_contact event)
  int unmonitored_groups = 0;   // series groups whose cell voltage the firmware never read (monitor_unread)
  std::string firmware_status;  // a library firmware (bms.firmware): ran to the end, or its firmware_fault
  std::vector<std::string> firmware_target;  // target mode: per task instructions and cycles, CPU load, stack, resets
  // target mode: the same figures by name, the result file's /summary attributes target_*
  std::vector<std::pair<std::string, double>> firmware_target_figures;
  VehicleSummary vehicle;       // `load: {vehicle: ...}`: laps, the pack's limits on the vehicle
  BalanceSummary balance;       // hardware.balancing: what the resistors bled, when the pack was balanced
  ChargeSummary charge;         // load.charger: when the BMS enabled the charger and switched it off
};

struct RunResult {
  Recording rec;
  std::vector<Event> events;
  std::vector<BusTraceRow> bus_trace;  // empty unless output.bus_trace
  std::vector<CanTraceRow> can_trace;  // a board alone with hardware.can: every frame on its bus
  Summary summary;
  CvodeStats solver;
  double quad[8] = {0, 0, 0, 0, 0, 0, 0, 0};  // Plant Quadrature order (kQuadCount)
};

}  // namespace packsim
