// Configuration of a simulated monitor-IC stack (constant during a run). Which part
// is `model`, a name in the part registry (core/parts/monitor_parts.hpp,
// docs/monitor-parts.md); the fields below are common to every part, then the settings
// of the TI parts packsim began with (their own structs, read by their part files):
//   bq76pl536a: 3-6 cells/device, 14-bit ADC (6250/16383 mV LSB), 2 thermistors,
//               SPI frames with CRC-8, secondary COV/CUV/OT comparators latching FAULT
//   bq76pl455a: up to 16 cells/device, 5 V/65535 LSB, 2 aux thermistors, UART
//               frames with CRC-16, fault summary, comparator UV/OV
//   bq76952:    up to 16 cells, mV readings (±5 mV), 3 thermistors reported in 0.1 K,
//               own protections with delays and recovery, CHG/DSG/PCHG/PDSG FETs,
//               coulomb counter; optional CRC-8
// A part added since keeps its settings in its own struct behind `part_settings`.
// Units SI (V, A, s, °C) with suffixes.
#pragma once
#include <memory>
#include <string>

#include "models/sensors/adc.hpp"
#include "models/sensors/thermistor.hpp"

namespace packsim {

// BQ76PL536A / BQ76PL455A secondary protection: comparators independent of the ADC,
// each with its own threshold and delay; a trip latches FAULT (COV, CUV) or ALERT
// (OT) until the host clears it and the condition is gone.
struct SecondaryProtection {
  bool enabled = true;
  double cov_V = 4.35;       // 2.0–5.0 V in 50 mV steps
  double cov_delay_s = 1.0;  // 0–3.1 s
  double cuv_V = 2.5;        // 0.7–3.3 V in 100 mV steps
  double cuv_delay_s = 1.0;
  double ot_C = 65.0;        // 40–90 °C in 5 °C steps
  double ot_delay_s = 1.0;   // 0–2.55 s in 10 ms steps
  double comm_timeout_s = 0.0;  // BQ76PL455A link supervision (its CTO fault timer); 0 off
};

// BQ76952 protections (datasheet defaults): an alert bit sets at once, the safety
// status only after the delay; recovery by hysteresis (voltage, temperature) or time
// (current).
struct Bq952Protection {
  double cov_V = 4.35, cov_delay_s = 0.244, cov_recovery_V = 0.1;
  double cuv_V = 2.53, cuv_delay_s = 0.244, cuv_recovery_V = 0.1;
  double occ_mV = 4.0, occ_delay_s = 0.02;     // across the shunt
  double ocd1_mV = 8.0, ocd1_delay_s = 0.01;
  double scd_mV = 100.0;                         // 15 µs delay: within one read-out
  double ocd3_A = 0.0, ocd3_delay_s = 2.0;       // slow discharge limit on the coulomb counter; 0 A: off
  double user_amps_A = 0.001;                    // DA Configuration USER_AMPS: 0.1, 1, 10 or 100 mA
  double current_recovery_s = 5.0;
  double otc_C = 55.0, otd_C = 60.0, otf_C = 80.0, ot_delay_s = 2.0;
  double utc_C = 0.0, utd_C = 0.0, ut_delay_s = 2.0;
  double temp_recovery_C = 5.0;
};

// BQ76952 autonomous balancing as its data memory holds it (Balancing Configuration
// CB_CHG / CB_RLX and the thresholds, one set for both cases); the part's defaults: off.
struct Bq952AutoBalance {
  bool charging = false, relax = false;  // balance while charging / at rest
  double min_cell_V = 3.9;               // only cells at or above this
  double start_delta_mV = 40.0, stop_delta_mV = 20.0;  // above the lowest cell
  int max_cells = 1;                     // at once (never two neighbours)
  double min_cell_temp_C = -20.0, max_cell_temp_C = 60.0, max_internal_C = 70.0;
};

// The settings of one part of its own (derive, and cast back in the part's model).
struct MonitorPartSettings {
  virtual ~MonitorPartSettings() = default;
};

struct MonitorConfig {
  std::string model;                // the part: its name in the registry (hardware.afe.model)
  int devices = 1;
  int devices_per_board = 0;        // > 0: boards of this many devices, each its own stack and host MCU (core/scenario/monitor_boards.hpp)
  int cells_per_device = 6;
  int thermistors_per_device = 2;   // AFE inputs in use (BQ76952: up to 3)
  uint32_t fet_inputs = 1u << 2;    // bit i: input i sits on the power FETs (BQ76952: its FET
                                    // over-temperature, OTF; the others its cell temperatures)
  AdcChannel cell_adc;              // volts: lsb, gain/offset error (whole part), noise
  double channel_gain_sd = 0.0;     // per-channel gain error, drawn once from the seed
  double channel_offset_sd_V = 0.0; // per-channel offset, drawn once from the seed
  double module_noise_V = 0.0;      // noise of the module/stack channel
  Thermistor thermistor;            // NTC + divider on the thermistor inputs
  bool crc = true;                  // BQ76952 only (the others always carry a CRC)
  double die_rise_C = 5.0;          // die above its board (own dissipation)
  double thermistor_bias_A = 0.0;   // drawn from each device's top cell while its thermistor inputs are biased
  double measurement_period_s = 0.0;  // BQ76952 loop (≈ 0.06 s): readings refresh at this rate; 0 = every read
  int oversampling = 1;             // BQ76PL455A only: conversions averaged in hardware per reading (cell_adc noise / √n)
  double shunt_ohm = 0.005;         // BQ76952 current input
  SecondaryProtection secondary;
  Bq952Protection bq;
  Bq952AutoBalance bq_balance;
  double baud = 250000.0;           // link speed for the read-out time
  double conversion_s_per_channel = 6e-6;
  std::shared_ptr<const MonitorPartSettings> part_settings;  // a part's own settings (its part file reads them)
};

}  // namespace packsim
