// BMS core configuration: what the firmware is flashed with. Firmware units only
// (mV, mA, deci-degC, ms); the simulator converts the scenario's SI values once.
#pragma once
#include <cstdint>

#include "bms_afe.hpp"
#include "bms_faults.hpp"
#include "bms_limits.hpp"

namespace bms {

// One rule of the flashed protection table: the settings of a FaultRow
// (bms_faults.hpp) after the integrator's overrides. rules[i] is FaultId i.
struct ProtectionRule {
  Quantity quantity;
  bool tripAbove;
  int32_t threshold;
  int32_t hysteresis;
  uint32_t delay_ms;
  Severity severity;
  bool latch;
  uint8_t opens;  // ActuatorBits
  bool enabled;
  FaultAction action;  // what a fatal fault does (bms_faults.hpp)
};

// Conversion from monitor-IC codes to firmware units (the nominal datasheet values:
// the firmware does not know the simulated part's gain error).
struct SensorScaling {
  float cellLsb_uV;            // cell voltage per ADC code
  float currentZeroCode;       // current-sense ADC code at 0 A
  float currentLsb_mA;         // mA per current-sense ADC code
  float thermFullScaleCode;    // ADC code at the reference (ratio 1.0)
  float thermPullup_ohm;       // divider: reference - pullup - NTC - ground
  float thermR25_ohm;
  float thermBeta_K;
  int32_t currentCodeMax;      // full-scale code of the current-sense ADC
  float busLsb_mV;             // load-bus voltage per divider-ADC code
};

// Contactor + precharge sequencing (foxBMS-like): close precharge, wait until the bus
// is within `doneDelta_mV` of the pack and |I| < `doneCurrent_mA`, close the main
// relay, keep precharge closed `overlap_ms` longer, then open it. An attempt that has
// not finished after `timeout_ms` opens precharge for `pause_ms` and is retried up
// to `retries` times; then PrechargeFailed latches.
struct PrechargeConfig {
  bool enabled;
  uint32_t doneDelta_mV;
  int32_t doneCurrent_mA;
  uint32_t timeout_ms;
  uint32_t pause_ms;
  uint32_t overlap_ms;
  uint8_t retries;
};

// State estimation (bms_soc, bms_ekf, bms_soh): both estimators run every tick; the
// configured one is reported as Telemetry::soc_permille.
enum class SocEstimator : uint8_t { CoulombCounting = 0, Ekf = 1 };

// The EKF's 1-RC model of one series group, as flashed (not the plant's truth):
//   v = OCV(soc) - v1 - R0(soc)·I,   dv1/dt = (r1·I - v1) / tau1,   dsoc/dt = -I / capacity
// with the OCV table and capacity of SocConfig; R0 is a table on the OCV table's SOC
// points (r0_mOhm[i] at SOC i/(ocvPoints-1)), valid at r0RefTemp_C and scaled by an
// Arrhenius factor on the group's measured temperature (bms_ekf.hpp). Noise: voltage
// reading (measurement), SOC and v1 random walks per second (process).
struct EkfConfig {
  float r0_mOhm[kMaxOcvPoints];
  float r1_mOhm;
  float tau1_s;
  float voltageSd_mV;       // measurement noise + model error of one group reading
  float socSdPerSqrtS;      // SOC process noise, 1 sigma per sqrt(second)
  float v1SdPerSqrtS_mV;    // v1 process noise, 1 sigma per sqrt(second)
  float initialSoc;         // < 0: from the OCV table at the first reading
  float initialSocSd;       // 1 sigma of the initial SOC
  // Temperature correction of R0: r0_mOhm × exp(r0ArrheniusK · (1/T_K − 1/T_ref_K)).
  float r0ArrheniusK;       // 0: R0 does not depend on temperature (no expf per tick)
  float r0RefTemp_C;        // the temperature the r0_mOhm table is valid at
};

// SOC estimate: coulomb counting, anchored to the OCV table at start-up and again
// after |I| < restCurrent_mA for rest_ms. The table is OCV (mean cell) at SOC
// 0, 1/(n-1), … 1, increasing.
struct SocConfig {
  float capacity_mAh;
  uint16_t ocv_mV[kMaxOcvPoints];
  uint8_t ocvPoints;
  int32_t restCurrent_mA;
  uint32_t rest_ms;
  SocEstimator estimator;       // which estimate the telemetry reports (both always run)
  EkfConfig ekf;                // the EKF's own model of one series group
  float sohMinDeltaSoc;         // capacity estimate only across rested OCV points this far apart
  uint16_t displayBars_mV[kDisplayBars - 1];  // SOC display: bars = 1 + thresholds at or below the cell mV
};

// Where each thermistor channel sits, as the hardware is wired (the simulator's loader
// builds the table once; the image carries it). A cell channel is a cell temperature
// (the temperature rules, the EKF's R0), a FET one is judged by fet_overtemperature
// alone, a board one pauses balancing on its board (bms_balance). A channel in no mask
// is unwired.
struct ThermistorMap {
  uint64_t cell;                  // bit k: channel k sits on a cell
  uint64_t fet;                   // bit k: on the power FETs
  uint64_t board;                 // bit k: on a balancing board: in channel order perBoard on
  uint8_t perBoard;               //        the first board, perBoard on the next, ...
  uint8_t nearest[kMaxCells];     // per series group the nearest cell channel (kMaxThermistors: none)
};
static_assert(kMaxThermistors <= 64, "ThermistorMap holds a channel per mask bit");

inline bool thermOn(uint64_t mask, uint8_t k) { return ((mask >> k) & 1u) != 0; }

// Passive balancing policy (bms_balance.hpp). Firmware units.
enum class BalanceWhen : uint8_t { Charging = 0, Rest = 1, ChargingOrRest = 2, Always = 3 };
struct BalanceConfig {
  bool enabled;
  BalanceWhen when;          // when balancing is allowed at all
  uint16_t startDelta_mV;    // start when max - min cell rises above this
  uint16_t stopDelta_mV;     // stop when max - min falls below; a cell within this of the minimum is not balanced
  uint16_t minCell_mV;       // a cell below this is never balanced
  int16_t boardMax_dC;       // pause when the balancing board is hotter than this
  int16_t boardResume_dC;    // resume once it is below this again
  bool noAdjacent;           // never two neighbouring cells at once
  int32_t restCurrent_mA;    // |I| below this counts as rest
  uint32_t rest_ms;          // ... for at least this long
  uint32_t period_ms;        // the mask is re-decided at this period and held in between
  uint8_t averageReadings;   // decide on the mean of this many readings per cell (1 = each reading; ≤ kMaxBalanceAverage)
  uint8_t boardCount;        // > 1: boards of cellsPerBoard cells, each board's thermistors (ThermistorMap)
  uint16_t cellsPerBoard;    //      pausing only its own cells (≤ kMaxBoards)
};

// How often the firmware reads its monitor ICs (bms_firmware.hpp schedules the tasks).
// Protections on the MCU's own inputs (current, E-switches, relay feedback) act at the
// control tick; cell voltages and temperatures are as fresh as the last read-out.
struct ReadoutConfig {
  uint32_t period_ms;       // full read-out of every device: cells, temperatures, protection flags
  uint32_t alertPeriod_ms;  // the devices' protection flags alone, between read-outs (0: not polled)
};

// Which monitor board this host serves in a pack of several (bms_pack.hpp): board 0 is
// the pack host; boards = 1 is a pack with one host.
struct PackConfig {
  uint8_t board;
  uint8_t boards;
};

// Current that still counts as flowing through a relay commanded open (RelayWelded).
constexpr int32_t kDefaultWeldCurrent_mA = 500;

struct Config {
  uint16_t cellCount;
  uint8_t thermistorCount;
  uint32_t tickPeriod_ms;
  SensorScaling scaling;
  AfeConfig afe;                // the monitor stack: its part (driver), shape and the part's settings
  ReadoutConfig readout;
  PackConfig pack;
  PrechargeConfig precharge;
  SocConfig soc;
  uint32_t weldSettle_ms;       // relay release time allowed before current means "welded"
  int32_t weldCurrent_mA;       // current that counts as "still flowing" after the release time
  bool relayAuxFeedback;        // the relay's auxiliary contact is wired (a closed aux = welded)
  uint16_t balanceTime_s;       // balancing timer written with a mask (1 s … 63 min)
  BalanceConfig balance;
  int32_t chargeRequest_mA;     // charger current requested while charging (0: the charger stays off)
  uint16_t chargeFullCell_mV;   // charge ends once any cell reads this (0: leave the end to the charger)
  ThermistorMap therm;          // where each thermistor channel sits
  ProtectionRule rules[kFaultCount];
};

// Defaults for a LiPo/NMC pack with a stack of the registry's first part (its default
// settings; bms_afe_driver.hpp) at up to 6 cells per device; callers overwrite
// thresholds and hardware from the scenario.
Config defaultConfig(uint16_t cellCount, uint8_t thermistorCount);

// Thermistor channels read by the monitor ICs (the rest are on the MCU's ADC). Inline:
// the control tick asks it twice.
inline uint8_t afeThermistorChannels(const Config& c) {
  const uint32_t inputs = static_cast<uint32_t>(c.afe.deviceCount) * c.afe.thermistorsPerDevice;
  return static_cast<uint8_t>(inputs < c.thermistorCount ? inputs : c.thermistorCount);
}

}  // namespace bms
