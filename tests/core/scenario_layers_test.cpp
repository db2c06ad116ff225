// One layer over another (an extends: child over its base, --set over the file, a preset
// field over the preset): `key: null` removes the key beneath; a curve given in part
// keeps the rest of the curve beneath; alternatives of one choice replace each other
// (core/scenario/yaml_layers.hpp, docs/scenario.md "Layers").
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/scenario/load_scenario.hpp"
#include "core/scenario/overrides.hpp"
#include "core/scenario/provenance.hpp"
#include "models/cell/ecm.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;
using ecm::ocv;
using ecm::r0;

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

// A 2s pack of the bundled NCR18650 preset (OCV over discharged Ah, R0 with an
// Arrhenius factor) at 25 C.
const std::string kPresetPack =
    "pack: {series: 2, cell: {preset: ncr18650_3p1Ah}}\n"
    "ambient: {temp_C: 25}\n"
    "load: {current_A: 1}\nrun: {duration_s: 10}\n";

Scenario presetWith(const Overrides& o) {
  return loadScenarioWithOverrides(kPresetPack, o, "p.yaml", test::scenarioDir());
}

const char* kNcrOcvY =  // the preset's 16 OCV values, each 0.1 V lower
    "[4.10, 4.08, 3.96, 3.86, 3.76, 3.615, 3.561, 3.500, 3.458, 3.410, 3.330, 3.230, 3.080, 2.850, 2.500, 1.700]";

TEST(ScenarioLayers, PresetCurveGivenInPartKeepsTheGridAndAxis) {
  // Was: "pack.cell.ocv_V.y: unknown key; did you mean 'x'?" -- the part replaced the
  // preset's whole curve, which then had no x.
  const Scenario ref = presetWith({});
  const Scenario s = presetWith({{"pack.cell.ocv_V.y", kNcrOcvY}});
  for (const double soc : {0.95, 0.6, 0.3, 0.1})
    EXPECT_NEAR(ocv(s.pack.cell, soc), ocv(ref.pack.cell, soc) - 0.1, 1e-12) << soc;
  // show names the parts: the x grid is the preset's, y the override's.
  ASSERT_TRUE(s.provenance);
  EXPECT_EQ(s.provenance->originOf("pack.cell.ocv_V.x").rfind("preset ncr18650_3p1Ah", 0), 0u)
      << s.provenance->originOf("pack.cell.ocv_V.x");
  EXPECT_EQ(s.provenance->originOf("pack.cell.ocv_V.y").rfind("--set", 0), 0u);
  // The same written in the scenario file.
  const std::string text = "pack: {series: 2, cell: {preset: ncr18650_3p1Ah, ocv_V: {y: " + std::string(kNcrOcvY) +
                           "}}}\nambient: {temp_C: 25}\nload: {current_A: 1}\nrun: {duration_s: 10}\n";
  const Scenario f = loadScenarioText(text, "f.yaml", test::scenarioDir());
  EXPECT_NEAR(ocv(f.pack.cell, 0.3), ocv(ref.pack.cell, 0.3) - 0.1, 1e-12);
}

TEST(ScenarioLayers, PresetCurveLawSwitchedOffAloneKeepsItsShape) {
  // Was: "expected 'poly: [...]' ..." -- `r0_ohm: {arrhenius_K: 0}` replaced the whole curve.
  const Scenario ref = presetWith({});
  const Scenario s = presetWith({{"pack.cell.r0_ohm.arrhenius_K", "0"}});
  EXPECT_NEAR(r0(s.pack.cell, 0.5, 25.0), r0(ref.pack.cell, 0.5, 25.0), 1e-15);  // same curve at 25 C
  EXPECT_NEAR(r0(s.pack.cell, 0.5, 0.0), r0(ref.pack.cell, 0.5, 25.0), 1e-15);   // no longer doubles at 0 C
  EXPECT_GT(r0(ref.pack.cell, 0.5, 0.0), 1.9 * r0(ref.pack.cell, 0.5, 25.0));
}

TEST(ScenarioLayers, PresetCurveGivenWholeIsReadAsWrittenWithThePresetsLaw) {
  // A whole table on the default SOC axis (not the preset's discharged_Ah axis): at SOC 0.5
  // it reads 3.7 V; R0 given as a polynomial keeps the preset's Arrhenius factor.
  const Scenario s = presetWith({{"pack.cell.ocv_V", "{x: [0, 1], y: [3.2, 4.2]}"}, {"pack.cell.r0_ohm.poly", "[0.03]"}});
  EXPECT_NEAR(ocv(s.pack.cell, 0.5), 3.7, 1e-12);
  EXPECT_NEAR(r0(s.pack.cell, 0.5, 25.0), 0.03, 1e-15);
  EXPECT_NEAR(r0(s.pack.cell, 0.5, 0.0), 0.03 * std::exp(2250.0 * (1.0 / 273.15 - 1.0 / 298.15)), 1e-12);
}

TEST(ScenarioLayers, ExtendsChildCurveOnItsOwnAxisAndForm) {
  const fs::path d = test::freshTempDir("packsim_layers_", "axis");
  // The base's OCV is over discharged Ah; the child's is a table over SOC (the default
  // axis) and its R0 a polynomial where the base had a table.
  write(d / "base.yaml",
        "pack:\n  series: 1\n  cell:\n    capacity_Ah: 2.0\n"
        "    ocv_V: {axis: discharged_Ah, x: [0, 2], y: [4.2, 3.0]}\n"
        "    r0_ohm: {x: [0, 1], y: [0.02, 0.02], arrhenius_K: 1000, ref_temp_C: 25}\n"
        "load: {current_A: 1}\nrun: {duration_s: 10}\n");
  write(d / "child.yaml", "extends: base.yaml\npack:\n  cell:\n    ocv_V: {x: [0, 1], y: [3.0, 4.0]}\n"
                          "    r0_ohm: {poly: [0.05]}\n");
  // Was: the child's SOC grid silently read on the base's discharged_Ah axis (SOC 0.25
  // is 1.5 Ah discharged, beyond the grid's 1: 4.0 V, not 3.25 V), and `poly` beside the
  // base's x/y an error.
  const Scenario s = loadScenarioFile((d / "child.yaml").string());
  EXPECT_NEAR(ocv(s.pack.cell, 0.25), 3.25, 1e-12);
  EXPECT_NEAR(r0(s.pack.cell, 0.5, 25.0), 0.05, 1e-15);
  EXPECT_NEAR(r0(s.pack.cell, 0.5, 0.0), 0.05 * std::exp(1000.0 * (1.0 / 273.15 - 1.0 / 298.15)), 1e-12);  // base's law kept
}

TEST(ScenarioLayers, NullRemovesTheKeyBeneath) {
  const fs::path d = test::freshTempDir("packsim_layers_", "null");
  write(d / "base.yaml", test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 10, stop_after_trip_s: 2}\n"
                         "expect: {no_trip: true}\n");
  // ambient.temp_C -> a profile: `temp_C: null` (or just giving profile) over the base's temp_C.
  write(d / "explicit.yaml", "extends: base.yaml\nambient: {temp_C: null, profile: {time_s: [0, 10], temp_C: [0, 10]}}\n"
                             "run: {stop_after_trip_s: null}\nexpect: null\n");
  write(d / "implicit.yaml", "extends: base.yaml\nambient: {profile: {time_s: [0, 10], temp_C: [0, 10]}}\n");
  for (const char* f : {"explicit.yaml", "implicit.yaml"}) {
    // Was: "ambient: give exactly one of temp_C or profile (the value comes from base.yaml; give ambient in ...)".
    const Scenario s = loadScenarioFile((d / f).string());
    EXPECT_DOUBLE_EQ(s.ambient_C.at(5.0), 5.0) << f;
  }
  const Scenario e = loadScenarioFile((d / "explicit.yaml").string());
  const Scenario b = loadScenarioFile((d / "base.yaml").string());
  EXPECT_DOUBLE_EQ(b.run.stop_after_trip_s, 2.0);
  EXPECT_DOUBLE_EQ(e.run.stop_after_trip_s, 60.0);  // the default, not the base's 2 s
  EXPECT_TRUE(b.expect.present);
  EXPECT_FALSE(e.expect.present);
  // `--set KEY=null` on a child whose base gives the key: the default, not the base's
  // (was the base's 2 s: the null removed the key from the child alone, which had none).
  const Scenario o = loadScenarioFileWithOverrides((d / "implicit.yaml").string(), {{"run.stop_after_trip_s", "null"}});
  EXPECT_DOUBLE_EQ(o.run.stop_after_trip_s, 60.0);
  // --set: null removes, and a profile replaces temp_C.
  const std::string base = test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 10}\n";
  for (const Overrides& o : {Overrides{{"ambient.temp_C", "null"}, {"ambient.profile", "{time_s: [0, 10], temp_C: [0, 10]}"}},
                             Overrides{{"ambient.profile", "{time_s: [0, 10], temp_C: [0, 10]}"}}}) {
    const Scenario s = loadScenarioWithOverrides(base, o, "s.yaml", test::scenarioDir());
    EXPECT_DOUBLE_EQ(s.ambient_C.at(5.0), 5.0);
  }
  // A preset's field: `r0_charge_ohm: null` would leave none; `v_max_V: null` gives the default.
  const Scenario p = presetWith({{"pack.cell.v_max_V", "null"}});
  EXPECT_DOUBLE_EQ(p.pack.cell.v_max_V, 4.2);
}

TEST(ScenarioLayers, NullOverNothingIsStillAnError) {
  // A forgotten value in a file of its own is not silently the default.
  const std::string e = test::yamlErrorOf(test::simpleCellYaml() + "load: {current_A: 1}\nrun: {duration_s: 10, stop_after_trip_s: }\n");
  EXPECT_NE(e.find("run.stop_after_trip_s"), std::string::npos) << e;
}

TEST(ScenarioLayers, CurveOverA2dPresetWithoutRowsSaysWhatToWrite) {
  const std::string text = "pack: {series: 2, cell: {preset: lto_20Ah, r0_ohm: {x: [0, 1], y: [0.002, 0.001]}}}\n"
                           "load: {current_A: 1}\nrun: {duration_s: 10}\n";
  const std::string e = test::yamlErrorOf(text);
  EXPECT_NE(e.find("pack.cell.r0_ohm: the preset's curve is a table over temp_C"), std::string::npos) << e;
  EXPECT_NE(e.find("arrhenius_K"), std::string::npos) << e;
  const std::string ok = "pack: {series: 2, cell: {preset: lto_20Ah, r0_ohm: {x: [0, 1], y: [0.002, 0.001], "
                         "arrhenius_K: 0, ref_temp_C: 25}}}\nload: {current_A: 1}\nrun: {duration_s: 10}\n";
  const Scenario s = test::scenarioFromYaml(ok);
  EXPECT_NEAR(r0(s.pack.cell, 0.5, -20.0), 0.0015, 1e-15);
}


TEST(ScenarioLayers, ALayerChangesOneUseOfAnAliasNotTheOther) {
  // `cell_undervoltage: *slow` is the node anchored at cell_overvoltage: a child's (or a
  // --set's) change of cell_overvoltage.delay_ms changed it too -- 100 ms under-voltage
  // delay, shown as the base's line, where the base says 2000.
  const fs::path d = test::freshTempDir("packsim_layers_", "alias");
  write(d / "base.yaml", test::simpleCellYaml() +
                             "bms:\n  protections:\n    cell_overvoltage: &slow {delay_ms: 2000}\n"
                             "    cell_undervoltage: *slow\n"
                             "load: {current_A: 1}\nrun: {duration_s: 10}\n");
  write(d / "child.yaml", "extends: base.yaml\nbms: {protections: {cell_overvoltage: {delay_ms: 100}}}\n");
  const auto delays = [](const Scenario& s) {
    return std::make_pair(s.bms.protection(bms::FaultId::CellOverVoltage).delay_s,
                          s.bms.protection(bms::FaultId::CellUnderVoltage).delay_s);
  };
  EXPECT_EQ(delays(loadScenarioFile((d / "base.yaml").string())), std::make_pair(2.0, 2.0));
  EXPECT_EQ(delays(loadScenarioFile((d / "child.yaml").string())), std::make_pair(0.1, 2.0));
  const Scenario o = loadScenarioFileWithOverrides((d / "base.yaml").string(), {{"bms.protections.cell_overvoltage.delay_ms", "100"}});
  EXPECT_EQ(delays(o), std::make_pair(0.1, 2.0));
  // A scalar alias alike, and the entries after it keep their lines (an error still names one).
  write(d / "scalar.yaml", test::simpleCellYaml() +
                               "bms:\n  protections:\n    cell_overvoltage: {delay_ms: &d 2000}\n"
                               "    cell_undervoltage: {delay_ms: *d, threshold_V: 9}\n"
                               "load: {current_A: 1}\nrun: {duration_s: 10}\n");
  const std::string e = test::fileErrorOf(d / "scalar.yaml");
  EXPECT_NE(e.find("scalar.yaml:22:52: bms.protections.cell_undervoltage.threshold_V"), std::string::npos) << e;
  const Scenario so = loadScenarioFileWithOverrides((d / "scalar.yaml").string(),
      {{"bms.protections.cell_overvoltage.delay_ms", "100"}, {"bms.protections.cell_undervoltage.threshold_V", "2.9"}});
  EXPECT_EQ(delays(so), std::make_pair(0.1, 2.0));
  // A YAML merge key is named as such (was "unknown key (valid keys: ...)").
  write(d / "merge.yaml", test::simpleCellYaml() +
                              "bms:\n  protections:\n    cell_overvoltage: &s {delay_ms: 2000}\n"
                              "    cell_undervoltage: {<<: *s, threshold_V: 2.9}\n"
                              "load: {current_A: 1}\nrun: {duration_s: 10}\n");
  const std::string m = test::fileErrorOf(d / "merge.yaml");
  EXPECT_NE(m.find("bms.protections.cell_undervoltage.<<: YAML merge keys ('<<: *anchor') are not supported"), std::string::npos) << m;
}

}  // namespace
}  // namespace packsim
