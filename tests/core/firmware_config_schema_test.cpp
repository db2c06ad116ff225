// A firmware's configuration schema (bms/packsim_fw.h psfw_config_schema, issue 29):
// read from the example firmware's library and its Cortex-M4 ELF, bms.firmware.config
// checked against it at its file:line, the blob built in the schema's order with the
// defaults; a firmware without a schema (the probe) keeps the positional blob.
#include "core/firmware/config_schema.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/firmware/elf_image.hpp"
#include "core/scenario/load_scenario.hpp"
#include "test_support.hpp"

namespace packsim {
namespace {

namespace fs = std::filesystem;

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Built next to packsim (examples/firmware/CMakeLists.txt).
const std::string kExampleLib = (fs::path(PACKSIM_BINARY).parent_path() / "libpacksim_example_bms.so").string();
const std::string kExampleElf = (fs::path(PACKSIM_BINARY).parent_path() / "packsim_example_bms_cm4.elf").string();
const std::string kWatchdogElf = (fs::path(PACKSIM_BINARY).parent_path() / "packsim_watchdog_demo_cm4.elf").string();

std::vector<uint8_t> int32s(const std::vector<int32_t>& v) {
  std::vector<uint8_t> out;
  for (const int32_t x : v)
    for (int b = 0; b < 4; ++b) out.push_back(static_cast<uint8_t>((static_cast<uint32_t>(x) >> (8 * b)) & 0xFFu));
  return out;
}

int32_t int32At(const std::vector<uint8_t>& blob, size_t field) {
  uint32_t u = 0;
  for (int b = 0; b < 4; ++b) u |= uint32_t{blob.at(4 * field + b)} << (8 * b);
  return static_cast<int32_t>(u);
}

std::string exampleYaml(const std::string& config) {
  return "extends: bench_6s_ncr18650_2C.yaml\n"
         "bms:\n  firmware:\n    library: " + kExampleLib + "\n" + config;
}

// The example's table as examples/firmware/example_bms.c declares it: struct ex_config's
// 21 int32 fields and its 11-value OCV table (128 bytes), in its order, with the ranges
// ex_init accepts.
TEST(FirmwareConfigSchema, TheExampleLibraryExportsItsStructsFields) {
  const std::optional<ConfigSchema> s = readLibraryConfigSchema(kExampleLib);
  ASSERT_TRUE(s);
  ASSERT_EQ(s->fields.size(), 22u);
  EXPECT_EQ(s->blobBytes(), 128u);
  EXPECT_EQ(s->fields[0].name, "cell_count");
  EXPECT_EQ(s->fields[3].name, "cov_mV");
  EXPECT_EQ(s->fields[3].unit, "mV");
  EXPECT_EQ(s->fields[3].min, 1000.0);
  EXPECT_EQ(s->fields[3].max, 5000.0);
  EXPECT_EQ(s->fields[3].def, 4250.0);
  EXPECT_EQ(s->fields[17].name, "ntc_bits");
  EXPECT_EQ(s->fields[17].min, 8.0);  // ex_init refuses fewer than 8 bits
  EXPECT_EQ(s->fields[18].name, "precharge_ms");
  EXPECT_EQ(s->fields[19].name, "capacity_mAh");
  EXPECT_EQ(s->fields[21].name, "ocv_mV");
  for (const ConfigField& f : s->fields) {
    EXPECT_FALSE(f.real) << f.name;
    EXPECT_EQ(f.count, f.name == "ocv_mV" ? 11u : 1u) << f.name;
  }
}

// The probe firmware (tests/firmware/probe_fw.c) exports no schema: its blob stays
// positional -- the keys as written, a misspelt one appended unchecked.
TEST(FirmwareConfigSchema, AFirmwareWithoutASchemaKeepsThePositionalBlob) {
  EXPECT_FALSE(readLibraryConfigSchema(PACKSIM_PROBE_FW));
  const Scenario s = test::scenarioFromYaml("extends: bench_6s_ncr18650_2C.yaml\n"
                                            "bms: {firmware: {library: " PACKSIM_PROBE_FW ", config: {mode: 1, at_mz: 50}}}\n");
  EXPECT_EQ(s.bms.firmware.config, int32s({1, 50}));
}

// Keys in any order, some omitted: the blob is the schema's order, an omitted field its default.
TEST(FirmwareConfigSchema, TheBlobFollowsTheSchemaOrderWithDefaults) {
  const Scenario s = test::scenarioFromYaml(exampleYaml("    config: {precharge_ms: 120, cuv_mV: 2800, cell_count: 12}\n"));
  const std::vector<uint8_t>& blob = s.bms.firmware.config;
  ASSERT_EQ(blob.size(), 128u);
  EXPECT_EQ(int32At(blob, 0), 12);    // cell_count
  EXPECT_EQ(int32At(blob, 1), 6);     // cells_per_device: default
  EXPECT_EQ(int32At(blob, 3), 4250);  // cov_mV: default
  EXPECT_EQ(int32At(blob, 4), 2800);  // cuv_mV
  EXPECT_EQ(int32At(blob, 13), 503540);  // current_lsb_nA: default
  EXPECT_EQ(int32At(blob, 18), 120);  // precharge_ms
  // No config at all: every default.
  const Scenario d = test::scenarioFromYaml(exampleYaml(""));
  ASSERT_EQ(d.bms.firmware.config.size(), 128u);
  EXPECT_EQ(int32At(d.bms.firmware.config, 0), 6);
  EXPECT_EQ(int32At(d.bms.firmware.config, 18), 300);
}

// The bundled scenario lists all 22 keys in the struct's order: the schema's blob is
// byte for byte the positional one it was before (so its results are unchanged).
TEST(FirmwareConfigSchema, TheBundledExampleScenarioGetsTheSameBytesAsBefore) {
  setenv("PACKSIM_FIRMWARE_PATH", fs::path(PACKSIM_BINARY).parent_path().c_str(), 1);
  const Scenario s = loadScenarioFile(test::scenarioDir() + "/firmware/c_example_firmware.yaml");
  EXPECT_EQ(s.bms.firmware.config, int32s({6, 6, 2, 4250, 2500, 500, 10000, 2000, 200, 600, 1000, 5, 32768, 503540,
                                           10000, 3435, 10000, 12, 300, 3100, 30000, 2600, 3240, 3435, 3515, 3569, 3622,
                                           3702, 3846, 3953, 4057, 4180}));
}

TEST(FirmwareConfigSchema, EachBadKeyOrValueIsOneErrorAtItsLine) {
  // unknown key: the closest valid one
  const std::string unknown = test::yamlErrorOf(exampleYaml("    config:\n      cell_count: 6\n      cov_mv: 4300\n"));
  EXPECT_TRUE(has(unknown, "test.yaml:7:")) << unknown;
  EXPECT_TRUE(has(unknown, "bms.firmware.config.cov_mv")) << unknown;
  EXPECT_TRUE(has(unknown, "did you mean 'cov_mV'?")) << unknown;
  // out of range: the range, the unit and the doc line
  const std::string range = test::yamlErrorOf(exampleYaml("    config:\n      cov_mV: 42500\n"));
  EXPECT_TRUE(has(range, "test.yaml:6:")) << range;
  EXPECT_TRUE(has(range, "bms.firmware.config.cov_mV")) << range;
  EXPECT_TRUE(has(range, "expected an integer in [1000, 5000] mV (cell over-voltage trip), got 42500")) << range;
  // not a whole number, not a number, a list for one number
  EXPECT_TRUE(has(test::yamlErrorOf(exampleYaml("    config: {ntc_bits: 12.5}\n")), "got '12.5'"));
  EXPECT_TRUE(has(test::yamlErrorOf(exampleYaml("    config: {ntc_bits: twelve}\n")), "got 'twelve'"));
  const std::string list = test::yamlErrorOf(exampleYaml("    config: {ntc_bits: [12]}\n"));
  EXPECT_TRUE(has(list, "bms.firmware.config.ntc_bits: expected an integer in [8, 16]")) << list;
  // config_file: exactly the schema's bytes
  const fs::path dir = test::processTempDir("fw_schema");
  fs::create_directories(dir);
  std::ofstream((dir / "short.bin").string(), std::ios::binary) << "12345678";
  const std::string file = test::yamlErrorOf(exampleYaml("    config_file: " + (dir / "short.bin").string() + "\n"));
  EXPECT_TRUE(has(file, "8 bytes; the firmware's configuration schema (22 fields) takes 128")) << file;
}

// A float field is IEEE-754 single precision, a list exactly its count of numbers
// (tests/firmware/schema_fw.c: gain float in [-2.5, 2.5], limits_mV int32[3], delay_ms).
TEST(FirmwareConfigSchema, FloatAndListFieldsAreEncodedAndChecked) {
  const std::string base = "extends: bench_6s_ncr18650_2C.yaml\nbms:\n  firmware:\n    library: " PACKSIM_SCHEMA_FW "\n";
  const Scenario s = test::scenarioFromYaml(base + "    config: {limits_mV: [1, 2, 3], gain: -0.5}\n");
  EXPECT_EQ(s.bms.firmware.config, (std::vector<uint8_t>{0, 0, 0, 0xBF, 1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 50, 0, 0, 0}));
  const Scenario d = test::scenarioFromYaml(base);  // gain 1.25 = 0x3FA00000, limits 3300 = 0x0CE4
  EXPECT_EQ(d.bms.firmware.config,
            (std::vector<uint8_t>{0, 0, 0xA0, 0x3F, 0xE4, 0x0C, 0, 0, 0xE4, 0x0C, 0, 0, 0xE4, 0x0C, 0, 0, 50, 0, 0, 0}));
  const std::string shortList = test::yamlErrorOf(base + "    config: {limits_mV: [1, 2]}\n");
  EXPECT_TRUE(has(shortList, "test.yaml:5:")) << shortList;
  EXPECT_TRUE(has(shortList, "expected a list of exactly 3 numbers, each an integer in [0, 5000] mV (three limits), got 2"))
      << shortList;
  const std::string element = test::yamlErrorOf(base + "    config: {limits_mV: [1, 2, 6000]}\n");
  EXPECT_TRUE(has(element, "bms.firmware.config.limits_mV[2]: expected an integer in [0, 5000] mV")) << element;
  const std::string real = test::yamlErrorOf(base + "    config: {gain: 3}\n");
  EXPECT_TRUE(has(real, "expected a number in [-2.5, 2.5] (current-sense gain), got 3")) << real;
}

// A schema that breaks its own rules is the firmware's error, at library: with the field.
TEST(FirmwareConfigSchema, ABrokenSchemaIsAnErrorNamingItsField) {
  const std::string e = test::yamlErrorOf("extends: bench_6s_ncr18650_2C.yaml\n"
                                          "bms: {firmware: {library: " PACKSIM_BAD_SCHEMA_FW ", config: {gain: 1}}}\n");
  EXPECT_TRUE(has(e, "test.yaml:2:")) << e;
  EXPECT_TRUE(has(e, "bms.firmware.library")) << e;
  EXPECT_TRUE(has(e, "its configuration schema (psfw_firmware_config_schema): field 2 'delay_ms': min 100 > max 10")) << e;
}

// Issue 29's case: a scenario extending the bundled one with a misspelt key. Without a
// schema the merged map appended it (80 bytes for 76, read by nobody); now it is an error
// at the extending file's line.
TEST(FirmwareConfigSchema, AMisspeltKeyInAnExtendingScenarioIsAnError) {
  setenv("PACKSIM_FIRMWARE_PATH", fs::path(PACKSIM_BINARY).parent_path().c_str(), 1);
  const std::string e = test::yamlErrorOf("extends: firmware/c_example_firmware.yaml\n"
                                          "bms:\n  firmware:\n    config:\n      precharge_mS: 500\n");
  EXPECT_TRUE(has(e, "test.yaml:5:")) << e;
  EXPECT_TRUE(has(e, "bms.firmware.config.precharge_mS")) << e;
  EXPECT_TRUE(has(e, "did you mean 'precharge_ms'?")) << e;
  // The same key spelt right overrides the base's value in place.
  const Scenario s = test::scenarioFromYaml("extends: firmware/c_example_firmware.yaml\n"
                                            "bms:\n  firmware:\n    config:\n      precharge_ms: 500\n");
  ASSERT_EQ(s.bms.firmware.config.size(), 128u);
  EXPECT_EQ(int32At(s.bms.firmware.config, 18), 500);
  EXPECT_EQ(int32At(s.bms.firmware.config, 3), 4250);
}

// Target mode reads the same table from the ELF's flash (32-bit pointers): the example's
// ELF gives the library's schema field for field; the watchdog demo, which declares
// none, gets none (its -u leaves the symbol undefined).
TEST(FirmwareConfigSchema, TheTargetElfCarriesTheSameSchema) {
  if (!fs::exists(kExampleElf)) GTEST_SKIP() << "no arm-none-eabi-gcc: " << kExampleElf << " not built";
  const std::optional<ConfigSchema> host = readLibraryConfigSchema(kExampleLib);
  const std::optional<ConfigSchema> target = readElfConfigSchema(readTargetElf(kExampleElf));
  ASSERT_TRUE(host && target);
  ASSERT_EQ(target->fields.size(), host->fields.size());
  for (size_t i = 0; i < host->fields.size(); ++i) {
    const ConfigField &h = host->fields[i], &t = target->fields[i];
    EXPECT_EQ(t.name, h.name);
    EXPECT_EQ(t.unit, h.unit);
    EXPECT_EQ(t.doc, h.doc);
    EXPECT_EQ(t.min, h.min);
    EXPECT_EQ(t.max, h.max);
    EXPECT_EQ(t.def, h.def);
    EXPECT_EQ(t.real, h.real);
    EXPECT_EQ(t.count, h.count);
  }
  if (fs::exists(kWatchdogElf)) {
    EXPECT_FALSE(readElfConfigSchema(readTargetElf(kWatchdogElf)));
  }
  const std::string e = test::yamlErrorOf("extends: bench_6s_ncr18650_2C.yaml\n"
                                          "bms:\n  firmware:\n    target: cortex-m4\n    elf: " + kExampleElf +
                                          "\n    config: {ocd_ma: 1}\n");
  EXPECT_TRUE(has(e, "test.yaml:6:")) << e;
  EXPECT_TRUE(has(e, "did you mean 'ocd_mA'?")) << e;
}

}  // namespace
}  // namespace packsim
