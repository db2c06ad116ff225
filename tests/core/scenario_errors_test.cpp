// Every class of bad input yields its own clear message naming file:line:column and
// the field, before the run starts.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <algorithm>

#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

std::string errorOf(const std::string& yaml) { return test::yamlErrorOf(yaml); }

const std::string& kLoad = test::kSimpleLoadYaml;

TEST(ScenarioErrors, UnknownKeySuggestsClosest) {
  std::string y = test::simpleCellYaml() + kLoad;
  y.replace(y.find("capacity_Ah"), 11, "capcity_Ah");
  const std::string e = errorOf(y);
  EXPECT_NE(e.find("test.yaml:8:5: pack.cell.capcity_Ah: unknown key; did you mean 'capacity_Ah'?"), std::string::npos) << e;
}

// Found by the campaign: a bq76952 (one device, up to 16 cells) under a 96s pack ran
// into the model's own check at the start of the run -- "bq76952: one device holds
// 1..16 cells, got 96", no file, line or key. Now the loader names the model key.
TEST(ScenarioErrors, ASingleDevicePartUnderALongerStringNamesTheModelKey) {
  const std::string e = errorOf("name: t\npack: {series: 96, cell: {capacity_Ah: 5, ocv_V: 3.7, r0_ohm: 0.01}}\n"
                                "hardware: {afe: {model: bq76952}}\nload: {current_A: 1}\nrun: {duration_s: 1}\n");
  EXPECT_NE(e.find(":3:"), std::string::npos) << e;
  EXPECT_NE(e.find("hardware.afe.model: a bq76952 monitors one stack of up to 16 series cells; this pack has 96"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("use a stacked part (bq76pl536a, bq76pl455a, ltc6811 or ltc6813)"), std::string::npos) << e;
}

// A whole-number bound is printed in all its digits: the seed's 2147483647 read
// "allowed [0, 2.14748e+09]", a bound 2147483648 is no nearer than 2147483647.
TEST(ScenarioErrors, AWholeBoundIsPrintedInAllItsDigits) {
  std::string yaml = test::simpleCellYaml(2) + test::kSimpleLoadYaml;
  yaml.replace(yaml.find("seed: 3"), 7, "seed: 2147483648");
  const std::string err = errorOf(yaml);
  EXPECT_NE(err.find("seed: 2147483648 is out of range; allowed [0, 2147483647]"), std::string::npos) << err;
}

TEST(ScenarioErrors, UnknownTopLevelSection) {
  const std::string e = errorOf(test::simpleCellYaml() + kLoad + "outptu: {interval_s: 1}\n");
  EXPECT_NE(e.find("outptu: unknown key; did you mean 'output'?"), std::string::npos) << e;
}

TEST(ScenarioErrors, ResetRequestTakesNoTarget) {
  const std::string e = errorOf(test::simpleCellYaml() + kLoad + "faults:\n  - {kind: reset_request, at_s: 1, cell: 1}\n");
  EXPECT_NE(e.find("cell: unknown key"), std::string::npos) << e;
  const std::string k = errorOf(test::simpleCellYaml() + kLoad + "faults:\n  - {kind: reset_requst, at_s: 1}\n");
  EXPECT_NE(k.find("did you mean 'reset_request'?"), std::string::npos) << k;
}

// `cell: ncr18650_3p1Ah`, the preset's name where its mapping belongs: the error shows
// the mapping that names it.
TEST(ScenarioErrors, APresetNameGivenAsTheCellShowsThePresetMapping) {
  const std::string e = errorOf("name: t\npack:\n  series: 2\n  cell: ncr18650_3p1Ah\n" + std::string(kLoad));
  EXPECT_NE(e.find("test.yaml:4:9: pack.cell: expected a mapping: a preset is given as 'cell: {preset: ncr18650_3p1Ah}'"),
            std::string::npos)
      << e;
}

TEST(ScenarioErrors, WrongType) {
  std::string y = test::simpleCellYaml() + kLoad;
  y.replace(y.find("r0_ohm: 0.02"), 12, "r0_ohm: low");
  const std::string e = errorOf(y);
  EXPECT_NE(e.find("test.yaml:10:13: pack.cell.r0_ohm: expected a number, got 'low'"), std::string::npos) << e;
}

TEST(ScenarioErrors, MissingRequiredField) {
  std::string y = test::simpleCellYaml() + kLoad;
  y.erase(y.find("    capacity_Ah: 2.0\n"), 21);
  const std::string e = errorOf(y);
  EXPECT_NE(e.find("pack.cell: missing required key 'capacity_Ah'"), std::string::npos) << e;
  EXPECT_NE(e.find("test.yaml:8:5"), std::string::npos) << e;
  // The keys given instead are named: `value:` where an over-current fault takes `current_A:`.
  const std::string f = errorOf(test::simpleCellYaml() + kLoad +
                                "faults:\n  - {kind: overcurrent, at_s: 1, duration_s: 1, value: 200}\n");
  EXPECT_NE(f.find("faults[0]: missing required key 'current_A' (given: kind, at_s, duration_s, value)"),
            std::string::npos) << f;
}

// A cell with a key far from every valid one (`fle:` for a file) and no curves is not an
// inline cell missing its OCV: the error names the keys given and the two ways to give a cell.
TEST(ScenarioErrors, CellNeitherPresetNorInlineNamesTheKeysGiven) {
  const std::string e = errorOf("pack: {series: 1, parallel: 1, initial_soc: 0.8,\n"
                                "       cell: {fle: my_cell.yaml, capacity_Ah: 2.0}}\n" + kLoad);
  EXPECT_NE(e.find("pack.cell: a cell is a preset ('preset: NAME', with overrides) or inline"), std::string::npos) << e;
  EXPECT_NE(e.find("(keys given: 'fle', 'capacity_Ah')"), std::string::npos) << e;
  EXPECT_EQ(e.find("missing required key"), std::string::npos) << e;
  // An inline cell with its curves but one missing still says which.
  const std::string o = errorOf("pack: {series: 1, parallel: 1, initial_soc: 0.8,\n"
                                "       cell: {capacity_Ah: 2.0, r0_ohm: 0.02}}\n" + kLoad);
  EXPECT_NE(o.find("pack.cell: missing required key 'ocv_V'"), std::string::npos) << o;
}

TEST(ScenarioErrors, OutOfRangeNamesAllowedRange) {
  std::string y = test::simpleCellYaml() + kLoad;
  y.replace(y.find("initial_soc: 0.8"), 16, "initial_soc: 1.3");
  const std::string e = errorOf(y);
  EXPECT_NE(e.find("test.yaml:5:16: pack.initial_soc: 1.3 is out of range; allowed [0, 1]"), std::string::npos) << e;
}

TEST(ScenarioErrors, BadChoiceSuggests) {
  const std::string e = errorOf(test::simpleCellYaml() +
                                "load: {points: {time_s: [0, 10], current_A: [1, 2]}, interpolation: linaer}\n");
  EXPECT_NE(e.find("load.interpolation: 'linaer' is not one of: step, linear (did you mean 'linear'?)"), std::string::npos) << e;
}

// run.jacobian picks CVODE's Newton matrix: a setting the fast integrator would ignore is
// refused, and a value not among the two choices is named with them.
TEST(ScenarioErrors, JacobianIsACvodeSettingWithTwoChoices) {
  const std::string fast = errorOf(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 10, solver: fast, jacobian: diagonal}\n");
  EXPECT_NE(fast.find("run.jacobian: applies to solver: cvode only (this run uses solver: fast)"), std::string::npos)
      << fast;
  const std::string bad = errorOf(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 10, jacobian: diagonl}\n");
  EXPECT_NE(bad.find("run.jacobian: 'diagonl' is not one of: sparse, diagonal (did you mean 'diagonal'?)"),
            std::string::npos)
      << bad;
  EXPECT_EQ(errorOf(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 10, jacobian: diagonal}\n"), "<no error>");
}

TEST(ScenarioErrors, YamlSyntaxError) {
  const std::string e = errorOf("name: x\npack: {series: 2\n");
  EXPECT_NE(e.find("test.yaml:3:1: YAML syntax error"), std::string::npos) << e;
}

TEST(ScenarioErrors, ThresholdBeyondSensorRange) {
  const std::string e = errorOf(test::simpleCellYaml() + kLoad + "bms: {protections: {overcurrent_discharge: {threshold_A: 90}}}\n");
  EXPECT_NE(e.find("beyond the current sensor's range"), std::string::npos) << e;
}

class CsvErrors : public ::testing::Test {
 protected:
  std::string run(const std::string& csv) {
    const fs::path dir = test::processTempDir("packsim_csv");
    fs::create_directories(dir);
    std::ofstream(dir / "p.csv") << csv;
    return errorOf(test::simpleCellYaml() + "load: {csv: " + (dir / "p.csv").string() + "}\n");
  }
};

TEST_F(CsvErrors, NotANumber) {
  const std::string e = run("time_s,current_A\n0,1\n10,abc\n");
  EXPECT_NE(e.find("p.csv:3:4: current_A: 'abc' is not a finite number"), std::string::npos) << e;
}

TEST_F(CsvErrors, TimeNotIncreasing) {
  const std::string e = run("time_s,current_A\n0,1\n10,2\n10,3\n");
  EXPECT_NE(e.find("p.csv:4:1: time_s: time must increase strictly: 10 after 10"), std::string::npos) << e;
}

TEST_F(CsvErrors, WrongHeader) {
  const std::string e = run("t,I\n0,1\n");
  EXPECT_NE(e.find("p.csv:1:1: expected the header 'time_s,current_A'"), std::string::npos) << e;
}

TEST_F(CsvErrors, WrongColumnCount) {
  const std::string e = run("time_s,current_A\n0,1,2\n");
  EXPECT_NE(e.find("p.csv:2:5: expected 2 columns"), std::string::npos) << e;
}

// issue 28, item 6: every number a scenario holds has a finite allowed range. Each
// numeric token of these scenarios (which load as they are) in turn set to an absurd
// value is one ScenarioError naming test.yaml, the token's line, its key and the range
// (or "finite"). Before, `run.duration_s: 1e18` ran 0 s with exit 0, a 1e308 A fault
// wrote inf into the result, `lsb_uV: 1e308` and a 1e9 hysteresis were taken.
const char* const kEveryNumberScenarios[] = {
    R"(name: numbers_a
seed: 3
pack:
  series: 2
  parallel: 1
  initial_soc: 0.8
  initial_temp_C: 25
  interconnect_ohm: 0.001
  cell:
    capacity_Ah: 2.0
    ocv_V: {poly: [0.8, 3.4]}
    r0_ohm: {poly: [0.02], arrhenius_K: 2000, ref_temp_C: 25}
    r0_charge_ohm: 0.03
    docv_dT_V_per_K: 0.0001
    hysteresis: {max_V: 0.01, rate_per_Ah: 10, instantaneous_V: 0.001}
    rc_pairs: [{r_ohm: 0.01, c_F: 1000}, {r_ohm: 0.005, tau_s: 100}]
    coulombic_efficiency: 0.99
    self_discharge_A: 0.0001
    heat_capacity_J_per_K: 40
    g_ambient_W_per_K: 0.1
    v_min_V: 2.5
    v_max_V: 4.2
  spread: {capacity_rel_sd: 0.01, r0_rel_sd: 0.01, initial_soc_sd: 0.01, self_discharge_A_sd: 0.00001}
  cells: [{cell: 1, capacity_Ah: 1.9, r0_scale: 1.1, initial_soc: 0.7, self_discharge_A: 0.0001}]
thermal:
  cell_to_cell_W_per_K: 0.1
  cell_to_coolant_W_per_K: 0.1
  coolant_temp_C: 25
  nodes:
    - {name: board, heat_capacity_J_per_K: 100, g_ambient_W_per_K: 0.1, to_each_cell_W_per_K: 0.01, heat_W: 0.1, to_cells: [{cell: 1, g_W_per_K: 0.1}]}
    - {name: case, heat_capacity_J_per_K: 100, to_nodes: [{node: board, g_W_per_K: 0.1}]}
hardware:
  cell_adc: {lsb_uV: 100, bits: 16, noise_mV_rms: 0, gain_error: 0.001, offset_mV: 0.1}
  thermistors: {at_groups: [1], r25_ohm: 10000, beta_K: 3435, pullup_ohm: 10000, bits: 12, noise_codes_rms: 0.5}
  current_sense: {shunt_ohm: 0.001, amp_gain: 20, noise_A_rms: 0, amp_offset_mV: 0.1, gain_error: 0.001, vref_V: 3.3, bits: 16}
  precharge: {r_ohm: 50, bus_capacitance_uF: 1000, bus_leak_ohm: 100000, close_delay_ms: 10}
  discharge_fet: {rds_on_ohm: 0.002, diode_vf_V: 0.7, diode_r_ohm: 0.01}
  fuse: {rated_A: 50, i2t_A2s: 5000, hold_ratio: 1.5}
  bus_adc: {full_scale_V: 20, bits: 12, noise_mV_rms: 1}
  relay: {close_delay_ms: 10, open_delay_ms: 5}
bms:
  tick_ms: 10
  protections:
    cell_overvoltage: {threshold_V: 4.25, hysteresis_V: 0.05, delay_ms: 500}
    cell_undervoltage: {threshold_V: 2.5, hysteresis_V: 0.05, delay_ms: 500}
    overcurrent_discharge: {threshold_A: 40, hysteresis_A: 1, delay_ms: 100}
    overtemperature: {threshold_C: 60, hysteresis_C: 5, delay_ms: 1000}
    relay_welded: {threshold_A: 1}
  comm_loss_count: 3
  weld_settle_ms: 100
  precharge: {done_delta_V: 0.5, done_current_A: 0.5, timeout_ms: 2000, pause_ms: 100, overlap_ms: 10, retries: 2}
  soc: {rest_s: 600, rest_current_A: 0.05}
  balance_time_s: 60
  charge_current_A: 1
  charge_full_cell_V: 4.1
ambient: {temp_C: 25}
load:
  segments:
    - {duration_s: 5, current_A: 2}
    - {duration_s: 5, current_A: 1}
  laps: 2
run: {duration_s: 10, stop_after_trip_s: 5, rtol: 1e-6}
output: {interval_s: 1}
faults:
  - {kind: overcurrent, current_A: 5, at_s: 2, duration_s: 1}
  - {kind: internal_short, cell: 1, resistance_ohm: 100, at_s: 3}
  - {kind: hot_cell, cell: 2, heat_W: 1, at_s: 3}
  - {kind: current_sensor_drift, offset_A: 0.1, drift_A_per_h: 1, at_s: 3}
  - {kind: channel_offset, group: 1, offset_mV: 5, at_s: 3}
expect:
  relay_open_by_s: 100
  energy_delivered_Wh_above: -1
  min_cell_V_above: 2
  max_temp_C_below: 80
)",
    R"(name: numbers_b
pack:
  series: 4
  initial_soc: 0.5
  cell: {capacity_Ah: 2.0, ocv_V: {x: [0, 0.5, 1], y: [3.0, 3.6, 4.2]}, r0_ohm: {x: [0, 1], temp_C: [0, 25], y: [[0.05, 0.04], [0.03, 0.02]]}}
thermal:
  nodes:
    - {name: bal, heat_capacity_J_per_K: 30, g_ambient_W_per_K: 0.05}
hardware:
  balancing: {resistor_ohm: 47, rds_on_ohm: 0.1, board_node: bal, board_thermistors: 1, resistor_power_rating_W: 0.25}
  current_sense: {shunt_ohm: 0.001, amp_gain: 20}
bms:
  tick_ms: 100
  balancing: {when: charging, start_delta_mV: 50, stop_delta_mV: 10, min_cell_V: 3.3, board_max_C: 70, board_resume_C: 60, rest_current_A: 0.1, rest_s: 60, period_ms: 1000}
load:
  charger: {current_A: 1, voltage_V: 16.8, end_current_A: 0.1}
run: {duration_s: 10}
ambient:
  profile: {time_s: [0, 100], temp_C: [20, 30]}
)",
    R"(name: numbers_c
pack:
  series: 1
  cell: {capacity_Ah: 2.0, ocv_V: {poly: [0.8, 3.4]}, r0_ohm: 0.02}
hardware:
  current_sense: {shunt_ohm: 0.001, amp_gain: 20}
load: {points: {time_s: [0, 5, 10], power_W: [5, 10, 0]}, interpolation: linear}
run: {solver: fast, fast: {max_substep_s: 0.5, substep_fraction: 0.5}}
)",
};

TEST(ScenarioErrors, EveryNumberHasAFiniteRange) {
  const std::regex number(R"((^|[\s\[,:{])(-?[0-9]+(\.[0-9]+)?(e-?[0-9]+)?)(?=[\s,\]}]|$))");
  const std::regex keyBefore(R"(([A-Za-z_][A-Za-z0-9_]*):[^:]*$)");
  int tokens = 0;
  for (const char* scenario : kEveryNumberScenarios) {
    const std::string text = scenario;
    ASSERT_EQ(errorOf(text), "<no error>") << text.substr(0, 20);
    std::istringstream lines(text);
    std::string line;
    size_t lineStart = 0;
    for (int lineNo = 1; std::getline(lines, line); ++lineNo, lineStart += line.size() + 1) {
      for (auto it = std::sregex_iterator(line.begin(), line.end(), number); it != std::sregex_iterator(); ++it) {
        const size_t at = static_cast<size_t>(it->position(2));
        std::smatch key;
        const std::string before = line.substr(0, at);
        ASSERT_TRUE(std::regex_search(before, key, keyBefore)) << line;
        ++tokens;
        for (const char* absurd : {"1e308", "-1e308", ".nan", ".inf", "-.inf"}) {
          std::string bad = text;
          bad.replace(lineStart + at, static_cast<size_t>(it->length(2)), absurd);
          const std::string e = errorOf(bad);
          SCOPED_TRACE(line + "  <-  " + absurd);
          EXPECT_NE(e.find("test.yaml:" + std::to_string(lineNo) + ":"), std::string::npos) << e;
          EXPECT_NE(e.find(key[1].str()), std::string::npos) << e;
          EXPECT_TRUE(e.find("allowed") != std::string::npos || e.find("finite") != std::string::npos) << e;
        }
      }
    }
  }
  EXPECT_GT(tokens, 150);
}

// A value in a CSV load beyond any load's range, and one the pack's cells cannot carry
// (mA under a current_A header): one error naming file, line, column and the column's
// name; the C-rate error suggests the mA -> A scale.
TEST_F(CsvErrors, ValueOutOfRangeAndImplausibleCRate) {
  const std::string huge = run("time_s,current_A\n0,1\n10,1e308\n");
  EXPECT_NE(huge.find("p.csv:3:4: current_A: '1e308' is out of range; allowed [-100000, 100000] A"), std::string::npos)
      << huge;
  const std::string late = run("time_s,current_A\n0,1\n1e18,1\n");
  EXPECT_NE(late.find("p.csv:3:1: time_s: '1e18' s is out of range; allowed [0, 2.592e+06]"), std::string::npos) << late;
  // simpleCellYaml: one 2 Ah cell. 1500 mA logged as A is 750C.
  const std::string mA = run("time_s,current_A\n0,0\n5,1500\n10,-800\n");
  EXPECT_NE(mA.find("p.csv:3:3: current_A: 1500 A is 750C for the 1 parallel cell of 2 Ah; allowed at most 100C (200 A)"),
            std::string::npos)
      << mA;
  EXPECT_NE(mA.find("scale: 0.001"), std::string::npos) << mA;
  EXPECT_EQ(run("time_s,current_A\n0,0\n5,1.5\n10,-0.8\n"), "<no error>");  // the same in A
}

TEST(ScenarioErrors, LoadBeyondTheCellsCRateNamesKeyAndLine) {
  // 5 Ah cells, 1s2p: 10 Ah; 17 kA is 1700C.
  std::string y = test::simpleCellYaml();
  y.replace(y.find("  series: 1\n"), 12, "  series: 1\n  parallel: 2\n");
  y.replace(y.find("capacity_Ah: 2.0"), 16, "capacity_Ah: 5.0");
  const int line = static_cast<int>(std::count(y.begin(), y.end(), '\n')) + 1;
  const std::string seg = errorOf(y + "load: {segments: [{duration_s: 10, current_A: 5}, {duration_s: 5, current_A: 17000}]}\nrun: {duration_s: 10}\n");
  EXPECT_NE(seg.find("test.yaml:" + std::to_string(line) + ":"), std::string::npos) << seg;
  EXPECT_NE(seg.find("load.segments[1].current_A: 17000 A is 1700C for the 2 parallel cells of 5 Ah; allowed at most "
                     "100C (1000 A)"),
            std::string::npos)
      << seg;
  const std::string pts = errorOf(y + "load: {points: {time_s: [0, 10], current_A: [5, -2000]}}\nrun: {duration_s: 10}\n");
  EXPECT_NE(pts.find("load.points.current_A[1]: -2000 A is 200C"), std::string::npos) << pts;
  // A power: 50 kW on one 3.8 V series cell pair is 13 kA.
  const std::string power = errorOf(y + "load: {power_W: 50000}\nrun: {duration_s: 10}\n");
  EXPECT_NE(power.find("load.power_W: 50000 W ("), std::string::npos) << power;
  // 100C itself is allowed: 1000 A on 10 Ah.
  EXPECT_EQ(errorOf(y + "load: {current_A: 1000}\nrun: {duration_s: 10}\n"), "<no error>");
}

// An over-current fault draws at most what the pack drives into a dead short (one
// 2 Ah cell, OCV up to 4.2 V, R0 20 mOhm: 210 A); a 100 kA fault on a 12s pack put its
// cells at -840 V. A charger is held to the loads' 100C.
TEST(ScenarioErrors, FaultCurrentBeyondTheShortCircuitCurrent) {
  const std::string y = test::simpleCellYaml() + kLoad;
  const int line = static_cast<int>(std::count(y.begin(), y.end(), '\n')) + 2;
  const std::string e = errorOf(y + "faults:\n  - {kind: overcurrent, current_A: 1000, at_s: 1}\n");
  EXPECT_NE(e.find("test.yaml:" + std::to_string(line) + ":"), std::string::npos) << e;
  EXPECT_NE(e.find("faults[0].current_A: 1000 A is more than the pack can drive into a dead short: allowed [-210, 210] A"),
            std::string::npos)
      << e;
  EXPECT_EQ(errorOf(y + "faults:\n  - {kind: overcurrent, current_A: 200, at_s: 1}\n"), "<no error>");
  const std::string c = errorOf(test::simpleCellYaml() + "load: {charger: {current_A: 500, voltage_V: 4.2}}\n");
  EXPECT_NE(c.find("load.charger.current_A: 500 A is 250C"), std::string::npos) << c;
}

// A device fault names one of the pack's own monitor devices. `device: 2` on a 16s pack of
// one BQ76952 (here: 3 on two BQ76PL536A) was taken (anything up to 64), ran as "injected device_silent device 2" and
// did nothing; a broken link above a stack's (or board's) top device cuts off nothing.
TEST(ScenarioErrors, ADeviceFaultNamesADeviceOfThePack) {
  auto withAfe = [](int series, const std::string& afe) {
    std::string y = test::simpleCellYaml(series) + kLoad;
    return y.replace(y.find("hardware:\n"), 10, "hardware:\n  afe: " + afe + "\n");
  };
  const std::string y = withAfe(12, "{model: bq76pl536a, cells_per_device: 6}");
  const std::string e = errorOf(y + "faults:\n  - {kind: device_silent, device: 3, at_s: 1}\n");
  EXPECT_NE(e.find("faults[0].device: 3 is not a device of this pack: it has 2 monitor devices (hardware.afe: 6 series "
                   "groups a device); allowed [1, 2]"),
            std::string::npos)
      << e;
  EXPECT_NE(errorOf(y + "faults:\n  - {kind: crc_errors, device: 0, rate: 0.5, at_s: 1}\n").find("allowed [1, 2]"),
            std::string::npos);
  EXPECT_EQ(errorOf(y + "faults:\n  - {kind: device_stuck, device: 2, byte: 255, at_s: 1}\n"), "<no error>");
  const std::string top = errorOf(y + "faults:\n  - {kind: broken_link, above_device: 2, at_s: 1}\n");
  EXPECT_NE(top.find("faults[0].above_device: device 2 is the top device of its stack (devices 1-2): a broken link "
                     "above it cuts off nothing"),
            std::string::npos)
      << top;
  EXPECT_EQ(errorOf(y + "faults:\n  - {kind: broken_link, above_device: 1, at_s: 1}\n"), "<no error>");
  // Boards of two BQ76PL536A devices: device 2 tops board 1, device 3 sits under device 4.
  const std::string boards = withAfe(24, "{model: bq76pl536a, cells_per_device: 6, devices_per_board: 2}");
  EXPECT_NE(errorOf(boards + "faults:\n  - {kind: broken_link, above_device: 2, at_s: 1}\n")
                .find("device 2 is the top device of its board (devices 1-2)"),
            std::string::npos);
  EXPECT_EQ(errorOf(boards + "faults:\n  - {kind: broken_link, above_device: 3, at_s: 1}\n"), "<no error>");
}

// The CLI turns a bad scenario into exit status 2 and leaves no result file.
TEST(CliErrors, BadScenarioExitsTwoAndWritesNothing) {
  const fs::path dir = test::processTempDir("packsim_cli_bad");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "bad.yaml") << "name: bad\npack: {series: 2, cell: {capacity_Ah: -1, ocv_V: 3.7, r0_ohm: 0.01}}\n"
                                     "load: {current_A: 1}\nrun: {duration_s: 1}\n";
  const std::string cmd = std::string(PACKSIM_BINARY) + " run " + (dir / "bad.yaml").string() + " -o " +
                          (dir / "out.h5").string() + " 2> " + (dir / "err.txt").string();
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  EXPECT_FALSE(fs::exists(dir / "out.h5"));
  EXPECT_FALSE(test::temporaryOfExists(dir / "out.h5"));
  std::ifstream err(dir / "err.txt");
  const std::string msg((std::istreambuf_iterator<char>(err)), {});
  EXPECT_NE(msg.find("bad.yaml:2:39: pack.cell.capacity_Ah: -1 is out of range; allowed (0, 10000]"), std::string::npos) << msg;
  fs::remove_all(dir);
}

TEST(ScenarioErrors, ATabIndentIsNamed) {
  // Was: "test.yaml:2:8: YAML syntax error: illegal map value", naming no tab.
  const std::string e = errorOf("pack:\n\tseries: 4\n");
  EXPECT_NE(e.find("test.yaml:2:8: YAML syntax error: illegal map value (line 2 is indented with a tab; YAML indents "
                   "with spaces)"),
            std::string::npos) << e;
}

// A charger without run.duration_s was "a constant load needs run.duration_s": a user
// whose run is a charge read that as a different mistake. Now the message says a charger
// needs the longest the charge may run, and when the run ends before it.
TEST(ScenarioErrors, AChargerWithoutADurationSaysWhatTheDurationIs) {
  const std::string pack = "pack: {series: 4, initial_soc: 0.3, cell: {preset: ncr18650_3p1Ah}}\n";
  EXPECT_NE(errorOf(pack + "load: {charger: {current_A: 2, voltage_V: 16.8}}\n")
                .find("load: a charger needs run.duration_s: the longest the charge may run (the run ends earlier "
                      "once the charger ends its taper)"),
            std::string::npos);
  EXPECT_NE(errorOf(pack + "load: {charger: {current_A: 2, voltage_V: 16.8, stop_run_when_done: false}}\n")
                .find("stop_run_when_done is false: the run goes on after the charge"),
            std::string::npos);
  EXPECT_NE(errorOf(pack + "load: {current_A: 2}\n").find("a constant load needs run.duration_s"), std::string::npos);
}

// A result file, an FMU, a firmware library or other binary data given where a scenario
// belongs (`packsim check r.h5`) is named for what it is; it read as a YAML syntax error
// at some line of its bytes ("r.h5:3:6: YAML syntax error: unknown escape character").
TEST(ScenarioErrors, AFileThatIsNoTextSaysWhatItIs) {
  const fs::path dir = test::processTempDir("packsim_not_text");
  fs::create_directories(dir);
  // A real result: a short run written as packsim writes it.
  const fs::path result = dir / "r.h5";
  const std::string cmd = std::string(PACKSIM_BINARY) + " run " + test::scenarioDir() +
                          "/eco_marathon_12s.yaml --set run.duration_s=1 -q -o " + result.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  EXPECT_NE(test::fileErrorOf(result).find("r.h5: this scenario file is an HDF5 file (a packsim result?), not a "
                                           "scenario, which is YAML text: read a result with `packsim report FILE`"),
            std::string::npos)
      << test::fileErrorOf(result);
  const auto bytes = [&](const std::string& name, const std::string& data) {
    std::ofstream(dir / name, std::ios::binary) << data;
    return test::fileErrorOf(dir / name);
  };
  EXPECT_NE(bytes("m.fmu", std::string("PK\x03\x04rest", 8)).find("a ZIP archive (an FMU?)"), std::string::npos);
  EXPECT_NE(bytes("fw.so", std::string("\x7f" "ELF\x02\x01", 6)).find("shared library (a firmware?)"), std::string::npos);
  EXPECT_NE(bytes("x.yaml", std::string("name: x\n\0zz", 10)).find("binary data (a NUL byte at byte 9)"),
            std::string::npos);
  EXPECT_EQ(bytes("ok.yaml", "name: x\n").find("binary"), std::string::npos);  // text reads as YAML
}

}  // namespace
}  // namespace packsim
