// `expect:` turns a scenario into an executable regression test: what the BMS must
// (or must not) do and the limits the plant must stay within.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace packsim {

struct DetectionExpectation {
  std::string fault;  // BMS fault name (bms::faultName)
  double from_s = 0.0;
  double to_s = 0.0;
};

// A bound on one estimator's SOC error (issue 17); estimator "" = the reported one.
struct SocErrorBound {
  std::string estimator;  // "", coulomb or ekf
  double bound = 0.0;     // SOC fraction (0.03 = 3 %)
};

struct Expectations {
  bool present = false;
  std::optional<bool> no_trip;
  std::optional<std::string> trip_reason;       // a fault among those latched at the trip
  std::optional<std::pair<double, double>> trip_within_s;
  std::optional<double> relay_open_by_s;        // the relay is open at and after t
  std::vector<DetectionExpectation> detected;   // fault active within [from, to]
  std::optional<double> min_cell_V_above;
  std::optional<double> max_temp_C_below;
  std::optional<double> final_soc_spread_above, final_soc_spread_below;  // max - min cell SOC at the end
  std::optional<double> energy_delivered_Wh_above;
  // A vehicle on its route (docs/vehicle.md): the distance it drove, and whether it
  // finished the route.
  std::optional<double> vehicle_distance_km_above, vehicle_distance_km_below;
  std::optional<bool> vehicle_finished;
  std::vector<SocErrorBound> soc_error_max_below, soc_error_rms_below, soc_error_end_below;  // |end|
  std::optional<double> capacity_error_below;   // |SOH estimate / true - 1|; needs an estimate
  // Against the `compare:` reference run: energy delivered lost (reference − this run)
  // above this figure; this run's lowest cell below the reference's.
  std::optional<double> energy_lost_vs_compare_Wh_above;
  std::optional<bool> min_cell_V_below_compare;
  // The firmware is meant to fail (load, init, crash, hang, contract break: a
  // firmware_fault event); without it such a failure fails `run` (exit 1) and `check`.
  bool firmware_fault = false;
  // How often the MCU reset (mcu_reset events: the watchdog's or a brown-out's).
  std::optional<int> mcu_resets;
};

}  // namespace packsim
