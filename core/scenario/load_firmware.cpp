// `bms.firmware`: a user firmware library and its configuration blob (docs/firmware.md).
//
//   library:     a path (relative to the scenario's folder) or a bare name looked up in
//                the scenario's folder, each folder of $PACKSIM_FIRMWARE_PATH and the
//                folder of the packsim executable, as given and as lib<name>.so
//   config:      a firmware that exports a configuration schema (packsim_fw.h
//                psfw_config_schema): its keys, each checked for type and range, an
//                omitted one taking its default, the blob built in the schema's order.
//                Without a schema: a map of integers or lists of integers, each number
//                a little-endian int32 in the order written (a C struct of int32_t
//                fields in that order reads it as is)
//   config_file: raw bytes instead (relative to the scenario's folder); with a schema,
//                exactly the bytes its fields take
//   watchdog_ms: CPU time one init or task call may take before it counts as hung
//                (target mode: the MCU's simulated time)
//   target:      cortex-m4: instead of a library, an ELF (`elf:`, looked up as a library
//                is, bare names as <name>.elf) runs on the virtual MCU at clock_mhz;
//                without `elf:`, packsim's own core (packsim_core_cm4.elf, built next to
//                packsim) with the image host mode flashes from the bms settings
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <algorithm>
#include <limits>
#include <optional>
#include <sstream>

#include <bms/packsim_fw.h>

#include "core/firmware/config_schema.hpp"
#include "core/firmware/elf_image.hpp"
#include "core/io/install_paths.hpp"
#include "core/scenario/files_read.hpp"
#include "core/scenario/provenance.hpp"  // numberText
#include "core/scenario/scenario_sections.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

constexpr size_t kMaxConfigBytes = 65536;
constexpr const char* kCoreElf = "packsim_core_cm4";  // bms/CMakeLists.txt builds it

std::vector<std::string> libraryCandidates(const std::string& name, const std::string& baseDir, bool elf) {
  const fs::path given(name);
  if (given.is_absolute()) return {name};
  if (given.has_parent_path()) return {(fs::path(baseDir) / given).string()};
  std::vector<std::string> dirs{baseDir};
  if (const char* env = std::getenv("PACKSIM_FIRMWARE_PATH"); env && *env) {
    std::stringstream ss(env);
    for (std::string d; std::getline(ss, d, ':');)
      if (!d.empty()) dirs.push_back(d);
  }
  if (const std::string exe = executableDir(); !exe.empty()) dirs.push_back(exe);
  const bool bare = given.extension().empty();
  std::vector<std::string> out;
  for (const std::string& d : dirs) {
    out.push_back((fs::path(d) / name).string());
    if (bare) out.push_back((fs::path(d) / (elf ? name + ".elf" : "lib" + name + ".so")).string());
  }
  return out;
}

void appendInt32(std::vector<uint8_t>& blob, int32_t v) {
  const uint32_t u = static_cast<uint32_t>(v);
  for (int b = 0; b < 4; ++b) blob.push_back(static_cast<uint8_t>((u >> (8 * b)) & 0xFFu));
}

void appendNumber(const YamlMap& fw, const YAML::Node& n, const std::string& field, std::vector<uint8_t>& blob) {
  const std::string expect = "expected an integer in [-2147483648, 2147483647] (each becomes a little-endian int32)";
  if (!n.IsScalar()) throw fw.errorAt(n, field, expect);
  if (quotedScalar(n)) throw fw.errorAt(n, field, quotedValueMessage(n, expect));
  long long v = 0;
  try {
    size_t used = 0;
    v = std::stoll(n.Scalar(), &used, 0);
    if (used != n.Scalar().size()) throw std::invalid_argument("trailing");
  } catch (const std::exception&) {
    throw fw.errorAt(n, field, expect + ", got '" + n.Scalar() + "'");
  }
  if (v < std::numeric_limits<int32_t>::min() || v > std::numeric_limits<int32_t>::max())
    throw fw.errorAt(n, field, expect + ", got " + n.Scalar());
  appendInt32(blob, static_cast<int32_t>(v));
}

std::vector<uint8_t> configBlob(YamlMap& fw) {
  std::vector<uint8_t> blob;
  const YAML::Node c = fw.node("config");
  const std::string base = fw.path() + ".config";
  if (!c.IsMap()) throw fw.errorAt("config", "expected a map of integers or lists of integers");
  for (const auto& kv : c) {
    const std::string field = base + "." + kv.first.Scalar();
    const YAML::Node v = kv.second;
    if (v.IsSequence()) {
      for (size_t i = 0; i < v.size(); ++i) appendNumber(fw, v[i], field + "[" + std::to_string(i) + "]", blob);
    } else {
      appendNumber(fw, v, field, blob);
    }
  }
  return blob;
}

// ---- with the firmware's schema ----

// "an integer in [3000, 5000] mV (cell over-voltage trip)": what a field takes.
std::string allowed(const ConfigField& f) {
  return std::string(f.real ? "a number" : "an integer") + " in [" + numberText(f.min) + ", " + numberText(f.max) + "]" +
         (f.unit.empty() ? "" : " " + f.unit) + (f.doc.empty() ? "" : " (" + f.doc + ")");
}

void appendField(std::vector<uint8_t>& blob, const ConfigField& f, double v) {
  uint32_t u = 0;
  if (f.real) {
    const float x = static_cast<float>(v);
    std::memcpy(&u, &x, sizeof u);
  } else {
    u = static_cast<uint32_t>(static_cast<int32_t>(v));
  }
  for (int b = 0; b < 4; ++b) blob.push_back(static_cast<uint8_t>((u >> (8 * b)) & 0xFFu));
}

double schemaNumber(const YamlMap& c, const YAML::Node& n, const std::string& field, const ConfigField& f) {
  const std::string expect = "expected " + allowed(f);
  if (!n.IsScalar()) throw c.errorAt(n, field, expect);
  if (quotedScalar(n)) throw c.errorAt(n, field, quotedValueMessage(n, expect));
  double v = 0.0;
  try {
    size_t used = 0;
    v = f.real ? std::stod(n.Scalar(), &used) : static_cast<double>(std::stoll(n.Scalar(), &used, 0));
    if (used != n.Scalar().size()) throw std::invalid_argument("trailing");
  } catch (const std::exception&) {
    throw c.errorAt(n, field, expect + ", got '" + n.Scalar() + "'");
  }
  if (!std::isfinite(v) || v < f.min || v > f.max) throw c.errorAt(n, field, expect + ", got " + n.Scalar());
  return v;
}

// bms.firmware.config against the schema: every key one of its fields, each number of
// its type in its range, a list of exactly its count; the blob in the schema's order,
// an omitted field at its default.
std::vector<uint8_t> schemaBlob(YamlMap& fw, const ConfigSchema& schema) {
  YamlMap c = fw.mapOrEmpty("config");
  std::vector<std::string> names;
  for (const ConfigField& f : schema.fields) names.push_back(f.name);
  for (const auto& kv : c.raw()) {
    const std::string key = kv.first.Scalar();
    if (std::find(names.begin(), names.end(), key) != names.end()) continue;
    const std::string near = closestMatch(key, names);
    std::string keys;
    for (const std::string& n : names) keys += (keys.empty() ? "" : ", ") + n;
    throw c.errorAt(kv.first, c.path() + "." + key,
                    "unknown key: not in the firmware's configuration schema" +
                        (near.empty() ? " (its keys: " + (keys.empty() ? std::string("none") : keys) + ")"
                                      : "; did you mean '" + near + "'?"));
  }
  std::vector<uint8_t> blob;
  for (const ConfigField& f : schema.fields) {
    const std::string field = c.path() + "." + f.name;
    if (!c.has(f.name)) {  // its default (recorded as one for packsim show)
      const double v = c.number(f.name, f.def, Range::closed(f.min, f.max));
      for (uint32_t i = 0; i < f.count; ++i) appendField(blob, f, v);
      continue;
    }
    const YAML::Node n = c.node(f.name);
    if (f.count == 1) {
      appendField(blob, f, schemaNumber(c, n, field, f));
      continue;
    }
    if (!n.IsSequence() || n.size() != f.count)
      throw c.errorAt(n, field, "expected a list of exactly " + std::to_string(f.count) + " numbers, each " + allowed(f) +
                                    (n.IsSequence() ? ", got " + std::to_string(n.size()) : std::string()));
    for (size_t i = 0; i < n.size(); ++i) appendField(blob, f, schemaNumber(c, n[i], field + "[" + std::to_string(i) + "]", f));
  }
  c.finish();
  return blob;
}

std::vector<uint8_t> configFileBytes(YamlMap& fw, const std::string& baseDir) {
  const std::string rel = fw.string("config_file");
  const fs::path p = fs::path(rel).is_relative() ? fs::path(baseDir) / rel : fs::path(rel);
  std::error_code ec;
  if (!fs::is_regular_file(p, ec)) throw fw.errorAt("config_file", "file not found: " + p.string());
  if (fs::file_size(p, ec) > kMaxConfigBytes)
    throw fw.errorAt("config_file", "larger than " + std::to_string(kMaxConfigBytes) + " bytes: " + p.string());
  noteFileRead(p.string());
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The first candidate that is a file, as an absolute path ("" if none); `tried` lists
// the others for the error.
std::string firstExisting(const std::vector<std::string>& candidates, std::string& tried) {
  for (const std::string& c : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(c, ec)) return fs::absolute(c, ec).string();
    tried += "\n  " + c;
  }
  return "";
}

// `target:` without `elf:`: packsim's own core on the virtual MCU. Its configuration is
// the scenario's bms settings (the image host mode flashes), not a blob.
FirmwareSettings coreOnTarget(YamlMap& m, FirmwareSettings f, const std::string& baseDir) {
  f.library = false;
  for (const char* key : {"config", "config_file"})
    if (m.has(key))
      throw m.errorAt(key, "packsim's core (target without elf:) is configured by the scenario's bms settings, as in "
                           "host mode; a blob is for your own firmware's elf:");
  std::string tried;
  f.library_path = firstExisting(libraryCandidates(kCoreElf, baseDir, true), tried);
  if (f.library_path.empty())
    throw m.errorAt("target", std::string("packsim's core for the target, ") + kCoreElf + ".elf, not found; tried:" +
                                  tried + "\n(packsim's build makes it next to packsim when arm-none-eabi-gcc is "
                                          "installed: scripts/install-deps.sh; or give elf: for your own firmware)");
  try {
    (void)readTargetElf(f.library_path);
  } catch (const ElfError& e) {
    throw m.errorAt("target", e.what());
  }
  f.watchdog_s = m.number("watchdog_ms", f.watchdog_s * 1e3, Range::closed(1.0, 60000.0)) * 1e-3;
  m.finish();
  return f;
}

}  // namespace

FirmwareSettings readFirmware(std::optional<YamlMap> m, const std::string& baseDir) {
  FirmwareSettings f;
  if (!m) return f;
  f.library = true;
  if (m->has("target")) {
    f.target = m->string("target");
    if (f.target != "cortex-m4") throw m->errorAt("target", "unknown target '" + f.target + "'; allowed: cortex-m4");
    // `library: null` clears a library an extended scenario names.
    if (m->has("library") && !m->node("library").IsNull())
      throw m->errorAt("library", "a cortex-m4 target runs an ELF: give elf:, not library: (a host-mode shared library; "
                                  "`library: null` clears one an extended scenario names)");
    f.clock_hz = m->number("clock_mhz", f.clock_hz * 1e-6, Range::closed(1.0, 1000.0)) * 1e6;
    if (!m->has("elf")) return coreOnTarget(*m, f, baseDir);
  }
  const char* key = f.isTarget() ? "elf" : "library";
  const std::string name = m->string(key);
  std::string tried;
  f.library_path = firstExisting(libraryCandidates(name, baseDir, f.isTarget()), tried);
  if (f.library_path.empty())
    throw m->errorAt(key, std::string(f.isTarget() ? "firmware ELF '" : "firmware library '") + name +
                              "' not found; tried:" + tried +
                              "\n(build it, give a path relative to the scenario, or set PACKSIM_FIRMWARE_PATH)");
  // The firmware's configuration schema, if it exports one (read, never run).
  std::optional<ConfigSchema> schema;
  try {
    if (f.isTarget()) {
      try {
        schema = readElfConfigSchema(readTargetElf(f.library_path));
      } catch (const ElfError& e) {
        throw m->errorAt("elf", e.what());
      }
    } else {
      schema = readLibraryConfigSchema(f.library_path);
    }
  } catch (const ConfigSchemaError& e) {
    throw m->errorAt(key, f.library_path + ": its configuration schema (" PSFW_CONFIG_SCHEMA_SYMBOL "): " + e.what());
  }
  if (m->has("config") && m->has("config_file")) throw m->errorAt("config_file", "give config or config_file, not both");
  if (m->has("config_file")) {
    f.config = configFileBytes(*m, baseDir);
    if (schema && f.config.size() != schema->blobBytes())
      throw m->errorAt("config_file", std::to_string(f.config.size()) + " bytes; the firmware's configuration schema (" +
                                          std::to_string(schema->fields.size()) + " fields) takes " +
                                          std::to_string(schema->blobBytes()));
  } else if (schema) {
    f.config = schemaBlob(*m, *schema);
  } else if (m->has("config")) {
    f.config = configBlob(*m);
  }
  if (f.config.size() > kMaxConfigBytes)
    throw m->errorAt("config", "the blob is larger than " + std::to_string(kMaxConfigBytes) + " bytes");
  f.watchdog_s = m->number("watchdog_ms", f.watchdog_s * 1e3, Range::closed(1.0, 60000.0)) * 1e-3;
  m->finish();
  return f;
}

}  // namespace packsim
