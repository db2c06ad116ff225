#include "core/scenario/load_scenario.hpp"

#include "core/io/install_paths.hpp"

#include <bms/bms_limits.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/parts/monitor_parts.hpp"
#include "core/scenario/derived_defaults.hpp"
#include "core/scenario/files_read.hpp"
#include "core/scenario/part_current_limits.hpp"
#include "core/scenario/monitor_boards.hpp"
#include "core/scenario/provenance.hpp"
#include "core/scenario/scenario_warnings.hpp"
#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/text_file_kind.hpp"
#include "core/scenario/value_ranges.hpp"
#include "core/scenario/yaml_layers.hpp"

namespace packsim {

namespace fs = std::filesystem;

namespace {

constexpr size_t kMaxExtendsDepth = 8;

// Child keys replace the base's; mappings merge key by key, lists replace whole.
// `prefix` is the dotted key of `base`; the active Provenance learns which keys
// `childFile` set.
void deepMerge(YAML::Node base, const YAML::Node& child, const std::string& prefix, const std::string& childFile) {
  Provenance* prov = Provenance::active();
  for (auto it = child.begin(); it != child.end(); ++it) {
    const std::string key = it->first.Scalar();
    if (key == "extends") continue;
    const std::string path = prefix.empty() ? key : prefix + "." + key;
    // A child's expectations are its own: `expect` replaces the base's block whole.
    // Const lookups: a non-const one would add an undefined entry for a missing key,
    // which then shadows the one inserted below.
    const YAML::Node existing = static_cast<const YAML::Node&>(base)[key];
    // `key: null` removes the base's key (yaml_layers.hpp): the key is then as if the
    // chain never gave it.
    if (removesKey(it->second)) {
      if (existing) base.remove(key);
      if (prov) prov->eraseUnder(path);
      continue;
    }
    if (key != "expect" && it->second.IsMap() && existing && existing.IsMap()) {
      dropReplacedAlternatives(base[key], it->second, path);
      deepMerge(base[key], it->second, path, childFile);
      continue;
    }
    if (prov) {
      if (existing && (existing.IsMap() || existing.IsSequence()) && it->second.IsScalar())
        prov->warn(dependenceRemovedWarning(path, existing, nodePlace(prov->fileOf(path), existing), it->second,
                                            nodePlace(Provenance::displayName(childFile), it->second)));
      prov->setFile(path, childFile);
    }
    if (existing) {
      base[key] = it->second;  // in place (the key order of the merged text stays)
    } else {
      // A new key: the child's own key node, so an error there keeps its line and column.
      base.force_insert(it->first, it->second);
    }
  }
}

// `extends: other.yaml`: the other scenario (validated on its own first) is the base;
// this file's keys are merged on top. Relative CSV paths of the base stay relative to
// the base's folder. `chain` holds the files being resolved (outermost first): a file
// that extends one already in it is a cycle, reported with the whole chain.
Scenario loadScenarioChain(const std::string& text, const std::string& file, const std::string& base_dir,
                           std::vector<std::string>& chain);
bool severalMonitorBoards(const MonitorConfig& a) { return a.devices_per_board > 0 && a.devices_per_board < a.devices; }

// Several monitor boards (hardware.afe.devices_per_board): a balancing board per monitor
// board (core/scenario/monitor_boards.hpp).
void setBoardBalancing(YamlMap& m, Scenario& s) {
  const MonitorConfig& a = s.hardware.afe;
  PassiveBalancerConfig& b = s.hardware.balancing;
  if (!severalMonitorBoards(a) || !b.present) return;
  const int boardCells = a.devices_per_board * a.cells_per_device;
  if (b.cells_per_board != 0 && b.cells_per_board != boardCells)
    throw m.map("hardware").map("balancing").errorAt(
        "cells_per_board", "with monitor boards of " + std::to_string(a.devices_per_board) + " devices the balancing "
                           "boards are the monitor boards: " + std::to_string(boardCells) + " cells (or leave it out)");
  b.cells_per_board = boardCells;
  b.boards = (s.pack.series + boardCells - 1) / boardCells;
}

// Every board's thermistors on its own inputs (core/scenario/monitor_boards.hpp).
void checkMonitorBoards(YamlMap& m, Scenario& s) {
  if (!severalMonitorBoards(s.hardware.afe)) return;
  YamlMap afe = m.map("hardware").map("afe");
  try {
    monitorBoards(s.hardware, s.pack.series);
  } catch (const std::invalid_argument& e) {
    throw afe.errorAt("devices_per_board", e.what());
  }
}

Scenario loadScenarioTreeChain(const YAML::Node& given, const std::string& text, const std::string& file,
                               const std::string& base_dir, std::vector<std::string>& chain);

std::string chainKey(const std::string& file) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::path(file), ec);
  return ec ? file : p.string();
}

// A base's relative paths name files in the base's folder: re-expressed relative to the
// extending file's folder, so the merged scenario reads the same files wherever the two
// files sit. A firmware `library` / `elf` is a path only with a folder in it (a bare name
// is searched for: next to the scenario, $PACKSIM_FIRMWARE_PATH, next to packsim).
struct FileKey {
  const char* path[3];  // nullptr after the last step
  bool bareNameIsASearch;
};
const FileKey kFileKeys[] = {
    {{"load", "csv"}, false},           {{"load", "csv", "file"}, false},
    {{"load", "route", "csv"}, false},  {{"load", "sun", "irradiance_csv"}, false},
    {{"compare", "scenario"}, false},   {{"bms", "firmware", "config_file"}, false},
    {{"bms", "firmware", "library"}, true}, {{"bms", "firmware", "elf"}, true},
};

// The map that holds `path`'s last key in `root` (each earlier step a map), or an invalid
// node; `key` is set to that last key.
YAML::Node holderOf(YAML::Node root, const char* const (&path)[3], const char*& key) {
  YAML::Node holder;
  holder.reset(root);
  size_t n = 0;
  while (n < 3 && path[n]) ++n;
  for (size_t i = 0; i + 1 < n; ++i) {
    const YAML::Node& view = holder;  // const: a lookup must not add the key
    if (!view.IsMap() || !view[path[i]] || !view[path[i]].IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    YAML::Node next = holder[path[i]];
    holder.reset(next);
  }
  key = path[n - 1];
  return holder;
}

void rebaseRelativePaths(YAML::Node base, const std::string& fromDir, const std::string& toDir) {
  for (const FileKey& k : kFileKeys) {
    const char* key = nullptr;
    YAML::Node holder = holderOf(base, k.path, key);
    const YAML::Node& view = holder;
    if (!holder.IsDefined() || !holder.IsMap() || !view[key] || !view[key].IsScalar() || view[key].IsNull()) continue;
    const fs::path given(view[key].Scalar());
    if (given.empty() || !given.is_relative() || (k.bareNameIsASearch && !given.has_parent_path())) continue;
    std::error_code ec;
    const fs::path here = fs::weakly_canonical(toDir.empty() ? fs::path(".") : fs::path(toDir), ec);
    const fs::path file = fs::weakly_canonical(fs::path(fromDir) / given, ec);
    // The node is edited in place: its line and column (for errors) stay the base's.
    YAML::Node n = holder[key];
    n = file.lexically_relative(here).string();
  }
}

// Whether a scenario's own text names the cell preset (pack.cell.preset).
bool namesPreset(const YAML::Node& root) {
  const YAML::Node& r = root;
  return r.IsMap() && r["pack"] && r["pack"].IsMap() && r["pack"]["cell"] && r["pack"]["cell"].IsMap() &&
         r["pack"]["cell"]["preset"];
}

// `presetDir`: the folder a preset name is looked up from (cells/NAME.yaml there, then the
// bundled ones): that of the file of the chain that names it, as the base's CSV paths are
// its own folder's -- a base's own cells/ preset was "unknown" from a child elsewhere.
YAML::Node resolveExtends(const YAML::Node& root, const std::string& file, const std::string& base_dir,
                          std::vector<std::string>& chain, std::string& presetDir) {
  presetDir = base_dir;
  if (!root.IsMap() || !root["extends"]) {
    if (Provenance* p = Provenance::active()) p->resetFiles(file);
    return root;
  }
  YamlMap m(root, file, "");
  std::string rel;
  {
    Provenance::Scope pause(nullptr);  // merged away: not a key of the scenario that runs
    rel = m.string("extends");
  }
  if (Provenance* p = Provenance::active(); p && chain.size() == 1)
    p->recordDefault("extends", yamlFlowText(root["extends"]),
                     nodePlace(Provenance::displayName(file), root["extends"]) + " (merged in)");
  fs::path path = fs::path(rel).is_relative() ? fs::path(base_dir) / rel : fs::path(rel);
  std::error_code ec;  // a name too long for the file system is "not found", not an exception
  if (!fs::exists(path, ec)) {
    // Not a file next to this one: a bundled scenario's name (`extends: formula_student_96s`,
    // as `packsim run NAME` takes it), when it has no file extension.
    const bool bareName = fs::path(rel).extension().empty() && fs::path(rel).is_relative();
    const std::string bundled = bareName ? bundledScenarioFile(rel) : "";
    if (bundled.empty()) {
      std::string hint;
      if (bareName) {
        const std::string near = closestMatch(fs::path(rel).filename().string(), bundledScenarioNames());
        hint = ", nor a bundled scenario of that name" + (near.empty() ? std::string() : " (did you mean '" + near + "'?)") +
               "; `packsim list` lists them";
      } else if (const fs::path given(rel); given.is_relative() && !given.has_parent_path() &&
                 (given.extension() == ".yaml" || given.extension() == ".yml") &&
                 !bundledScenarioFile(given.stem().string()).empty()) {
        // `extends: bench_6s_ncr18650_2C.yaml` from a folder of the user's own: the
        // bundled scenario is named without its extension.
        hint = "; the bundled scenario of that name is `extends: " + given.stem().string() + "` (no extension)";
      }
      throw m.errorAt("extends", "file not found: " + path.string() + hint);
    }
    path = bundled;
  }
  const std::string key = chainKey(path.string());
  if (std::find(chain.begin(), chain.end(), key) != chain.end()) {
    std::string names;
    for (const std::string& c : chain) names += fs::path(c).filename().string() + " -> ";
    throw m.errorAt("extends", "extends cycle: " + names + fs::path(key).filename().string());
  }
  if (chain.size() >= kMaxExtendsDepth)
    throw m.errorAt("extends", "more than " + std::to_string(kMaxExtendsDepth) + " nested extends");
  chain.push_back(key);
  const std::string baseText = readScenarioText(path.string());
  const std::string baseDir = path.parent_path().string();
  // The base must be valid alone: its errors name its own file (nothing recorded).
  {
    Provenance::Scope pause(nullptr);
    loadScenarioChain(baseText, path.string(), baseDir.empty() ? "." : baseDir, chain);
  }
  // Freshly parsed, so merged in place (YAML::Clone would lose the nodes' lines).
  std::string basePresetDir;
  YAML::Node base = resolveExtends(parseYaml(baseText, path.string()), path.string(), baseDir.empty() ? "." : baseDir,
                                   chain, basePresetDir);
  if (!namesPreset(root)) presetDir = basePresetDir;
  chain.pop_back();
  // Reads through a const view: a non-const lookup of a missing key adds an undefined
  // entry that would shadow the child's key inserted by deepMerge.
  const YAML::Node& cbase = base;
  rebaseRelativePaths(base, baseDir.empty() ? "." : baseDir, base_dir);
  // A child that names its own kind of load (current, power, segments, points, csv,
  // charger) replaces the base's load whole; otherwise its load keys (laps, ...) merge.
  if (cbase["load"] && cbase["load"].IsMap() && root["load"] && root["load"].IsMap()) {
    static const char* kinds[] = {"current_A", "power_W", "segments", "points", "csv", "charger", "vehicle"};
    bool childKind = false;
    for (const char* k : kinds) childKind = childKind || root["load"][k];
    // A vehicle extending a vehicle: its keys (mass, route, driver ...) merge.
    if (root["load"]["vehicle"] && cbase["load"]["vehicle"]) childKind = false;
    // A CSV mapping without a `file` changes the base's CSV mapping (`csv: {scale: -1}`
    // flips the inherited log's sign); one with a `file` is a new log, read as written
    // (the base's columns and scale do not carry over to it).
    const YAML::Node childCsv = root["load"]["csv"];
    if (childCsv && childCsv.IsMap() && !childCsv["file"] && cbase["load"]["csv"] && cbase["load"]["csv"].IsMap())
      childKind = false;
    if (childKind) {
      base.remove("load");
      if (Provenance* p = Provenance::active()) p->eraseUnder("load");
    }
  }
  deepMerge(base, root, "", file);
  return base;
}

// A hardware part's `key` names one of thermal.nodes.
void checkThermalNode(YamlMap section, const char* key, const std::string& node, const Scenario& s) {
  if (node.empty()) return;
  std::vector<std::string> names;
  for (const ThermalNodeConfig& n : s.thermal.nodes) names.push_back(n.name);
  if (std::find(names.begin(), names.end(), node) != names.end()) return;
  const std::string near = closestMatch(node, names);
  throw section.errorAt(key, "no thermal node named '" + node + "' in thermal.nodes" +
                                 (near.empty() ? "" : " (did you mean '" + near + "'?)"));
}

// A thermistor on a thermal node sits on the power FETs' node: the firmware judges it
// by its own limit (fet_overtemperature), not as a cell temperature.
void checkThermistorNodes(YamlMap& root, const Scenario& s) {
  const HardwareConfig& hw = s.hardware;
  const std::string fetNodes[] = {hw.discharge_fet.thermal_node, hw.charge_fet.thermal_node};
  for (size_t k = 0; k < hw.thermistor_sites.size(); ++k) {
    const std::string& node = hw.thermistor_sites[k].node;
    if (node.empty() || node == fetNodes[0] || node == fetNodes[1]) continue;
    YamlMap channel = root.map("hardware").map("thermistors").mapList("channels")[k];
    checkThermalNode(channel, "node", node, s);
    throw channel.errorAt("node", "a thermistor on a thermal node sits on the FETs' node (the thermal_node of "
                                  "hardware.discharge_fet or charge_fet); '" + node + "' is not one");
  }
}

// Balancing hardware against the thermal network and the BMS policy.
void checkBalancing(YamlMap& root, const Scenario& s) {
  const PassiveBalancerConfig& b = s.hardware.balancing;
  auto hwMap = [&](const char* section) { return root.map("hardware").map(section); };
  if (b.present) checkThermalNode(hwMap("balancing"), "board_node", b.board_node, s);
  if (!s.hardware.discharge_fet.thermal_node.empty())
    checkThermalNode(hwMap("discharge_fet"), "thermal_node", s.hardware.discharge_fet.thermal_node, s);
  if (!s.hardware.charge_fet.thermal_node.empty())
    checkThermalNode(hwMap("charge_fet"), "thermal_node", s.hardware.charge_fet.thermal_node, s);
  if (s.hardware.thermistors.count() > bms::kMaxThermistors)
    throw hwMap("balancing").errorAt("board_thermistors", "cell and board thermistors together exceed " +
                                                              std::to_string(bms::kMaxThermistors));
  const MonitorPart& part = monitorPart(s.hardware.afe.model);
  if (part.balances_on_its_own != nullptr && part.balances_on_its_own(s.hardware.afe) && !b.present)
    throw hwMap("afe").errorAt("autonomous_balancing", "the AFE's balancing needs balancing resistors (hardware.balancing)");
  if (s.bms.image.balance.enabled && !b.present)
    throw root.map("bms").errorAt("balancing", "the balancing policy needs balancing resistors (hardware.balancing)");
  if (s.hardware.active_balancer.present && b.present && s.bms.image.balance.enabled)
    throw root.map("bms").errorAt("balancing", "choose passive (bms.balancing) or active (hardware.active_balancer) balancing");
}

}  // namespace

Scenario loadScenarioText(const std::string& text, const std::string& file, const std::string& base_dir) {
  FilesReadScope reads;
  const std::shared_ptr<Provenance> prov = Provenance::active() ? nullptr : std::make_shared<Provenance>(file);
  Provenance::Scope scope(prov ? prov.get() : Provenance::active());
  std::vector<std::string> chain{chainKey(file)};
  Scenario s = loadScenarioChain(text, file, base_dir, chain);
  if (prov) attachProvenance(s, prov);
  if (reads.outermost()) s.files_read = reads.files();
  return s;
}

Scenario loadScenarioTree(const YAML::Node& tree, const std::string& text, const std::string& file,
                          const std::string& base_dir) {
  FilesReadScope reads;
  const std::shared_ptr<Provenance> prov = Provenance::active() ? nullptr : std::make_shared<Provenance>(file);
  Provenance::Scope scope(prov ? prov.get() : Provenance::active());
  std::vector<std::string> chain{chainKey(file)};
  Scenario s = loadScenarioTreeChain(tree, text, file, base_dir, chain);
  if (prov) attachProvenance(s, prov);
  if (reads.outermost()) s.files_read = reads.files();
  return s;
}

void attachProvenance(Scenario& s, const std::shared_ptr<Provenance>& prov) {
  s.provenance = prov;
  s.warnings = scenarioWarnings(s);
}

std::string resolvedScenarioText(const std::string& path, std::string* presetDirOut) {
  const std::string dir = fs::path(path).parent_path().string();
  std::vector<std::string> chain{chainKey(path)};
  std::string presetDir;
  const YAML::Node root =
      resolveExtends(parseYaml(readScenarioText(path), path), path, dir.empty() ? "." : dir, chain, presetDir);
  if (presetDirOut) *presetDirOut = presetDir;
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

namespace {

Scenario loadScenarioChain(const std::string& text, const std::string& file, const std::string& base_dir,
                           std::vector<std::string>& chain) {
  return loadScenarioTreeChain(parseYaml(text, file), text, file, base_dir, chain);
}

Scenario loadScenarioTreeChain(const YAML::Node& given, const std::string& text, const std::string& file,
                               const std::string& base_dir, std::vector<std::string>& chain) {
  if (!given || given.IsNull()) throw ScenarioError(file, 1, 1, "", "the scenario is empty");
  std::string presetDir;
  const YAML::Node root = resolveExtends(given, file, base_dir, chain, presetDir);
  YamlMap m(root, file, "");
  m.has("extends");
  Scenario s;
  s.file = file;
  s.text = text;
  if (!root.is(given)) {  // keep the complete merged scenario with the results
    YAML::Emitter out;
    out << root;
    s.text = "# " + file + " merged with the scenario it extends\n" + std::string(out.c_str()) + "\n";
  }
  s.name = m.string("name", fs::path(file).stem().string());
  s.description = m.string("description", "");
  const uint64_t seed = static_cast<uint64_t>(m.integer("seed", 1, 0, limits::kMaxSeed));
  s.pack = readPack(m.map("pack"), presetDir);
  s.hardware = readHardware(m.optionalMap("hardware"), s.pack);
  if (PassiveBalancerConfig& b = s.hardware.balancing; b.cells_per_board > 0) {
    b.boards = (s.pack.series + b.cells_per_board - 1) / b.cells_per_board;
    if (b.boards > bms::kMaxBoards)
      throw m.map("hardware").map("balancing").errorAt(
          "cells_per_board", std::to_string(s.pack.series) + " series cells at " + std::to_string(b.cells_per_board) +
                                 " per board make " + std::to_string(b.boards) + " boards; at most " +
                                 std::to_string(bms::kMaxBoards));
  }
  setBoardBalancing(m, s);
  s.hardware.thermistors = thermistorTable(s.hardware.thermistor_sites, s.hardware.balancing, s.pack.series);
  checkMonitorBoards(m, s);
  s.bms = readBms(m.optionalMap("bms"));
  if (auto b = m.optionalMap("bms")) s.bms.firmware = readFirmware(b->optionalMap("firmware"), base_dir);
  if (s.bms.firmware.library && s.hardware.afe.devices_per_board > 0 &&
      s.hardware.afe.devices_per_board < s.hardware.afe.devices)
    throw m.map("hardware").map("afe").errorAt(
        "devices_per_board", "a pack of several monitor boards runs packsim's core on each board's MCU; a firmware "
                             "library (bms.firmware) runs on a single board");
  if (s.bms.firmware.isTarget() && s.hardware.afe.devices_per_board > 0 &&
      s.hardware.afe.devices_per_board < s.hardware.afe.devices)
    throw m.map("hardware").map("afe").errorAt(
        "devices_per_board", "a pack of several monitor boards has one MCU per board on a CAN bus; target mode "
                             "(bms.firmware.target) emulates one MCU: run this pack in host mode");
  {
    YamlMap load = m.map("load");
    if (load.has("charger")) {  // the pack sits on a CC-CV charger (no other load)
      s.charger = readCharger(load.map("charger"));
      if (const std::string why = loadCRateError(s.pack, s.charger.current_A, false); !why.empty())
        throw load.map("charger").errorAt("current_A", why);
      load.finish();
      s.load = LoadProfile::constant(0.0);
      // On the charger unless the bms section says otherwise: connected, no drive request.
      const YAML::Node bmsNode = root["bms"];
      Provenance* prov = Provenance::active();
      if (!(bmsNode && bmsNode.IsMap() && bmsNode["charger_present"])) {
        s.bms.charger_present = true;
        if (prov) prov->recordDefault("bms.charger_present", "true", "default (the load is a charger)");
      }
      if (!(bmsNode && bmsNode.IsMap() && bmsNode["run_request"])) {
        s.bms.run_request = false;
        if (prov) prov->recordDefault("bms.run_request", "false", "default (the load is a charger)");
      }
    } else if (load.has("vehicle")) {  // a vehicle on a route draws a power it decides each tick
      s.vehicle = readVehicle(load, s.pack, base_dir);
      load.finish();
      s.load = LoadProfile::constant(0.0);
      s.load.quantity = LoadProfile::Quantity::Power_W;
    } else {
      s.load = readLoad(load, base_dir, s.pack);
    }
  }
  s.ambient_C = readAmbient(m.optionalMap("ambient"));
  s.thermal = readThermal(m.optionalMap("thermal"), s.pack.series * s.pack.parallel);
  s.run = readRun(m.optionalMap("run"), seed);
  // The recording keeps every n-th tick: its interval is a whole number of BMS ticks. A
  // stated one that is not is refused (it would be rounded silently); the default is the
  // whole number of ticks nearest 1 s.
  const double tick_s = s.bms.tick_s;
  const long tick_ms = std::lround(tick_s * 1e3);  // bms.tick_ms, whole
  // n ticks in seconds, from whole ms: 3 x 300 ms is 0.9 s, not 0.8999…
  const auto ticks_s = [tick_ms](long n) { return static_cast<double>(n * tick_ms) / 1000.0; };
  const auto wholeTicks = [tick_s](double interval_s) {
    const double ticks = interval_s / tick_s;
    const double n = std::round(ticks);
    return n >= 1.0 && std::fabs(ticks - n) <= 1e-6 * n;
  };
  auto o = m.optionalMap("output");
  if (o && o->has("interval_s")) {
    s.output.interval_s = o->number("interval_s", 1.0, Range::positive(limits::kMaxTime_s));
    if (!wholeTicks(s.output.interval_s)) {
      const long below = std::max(1L, static_cast<long>(std::floor(s.output.interval_s / tick_s)));
      std::ostringstream os;
      os << "interval_s = " << s.output.interval_s << " s is not a whole number of BMS ticks (bms.tick_ms " << tick_ms
         << "): the recording keeps every n-th tick; "
         << (s.output.interval_s < tick_s ? "at least " + numberText(ticks_s(1))
                                          : numberText(ticks_s(below)) + " or " + numberText(ticks_s(below + 1)));
      throw o->errorAt("interval_s", os.str());
    }
  } else if (!wholeTicks(s.output.interval_s)) {
    s.output.interval_s = ticks_s(std::max(1L, std::lround(1000.0 / static_cast<double>(tick_ms))));
    if (Provenance* prov = Provenance::active())
      prov->recordDefault("output.interval_s", numberText(s.output.interval_s),
                          "default (the whole number of BMS ticks nearest 1 s)");
  }
  if (o) {
    s.output.bus_trace = o->boolean("bus_trace", false);
    o->finish();
  }
  s.faults = readFaults(m, s.pack.series, s.pack.parallel, s.hardware.thermistors.count(), s.hardware.afe);
  // An over-current fault draws at most what the pack drives into a dead short: more
  // would put the cells' terminals far below 0 V (a 100 kA fault on a 12s pack: -840 V).
  for (size_t k = 0; k < s.faults.size(); ++k) {
    const FaultInjection& f = s.faults[k];
    const double isc_A = shortCircuitCurrent_A(s.pack);
    if (f.kind != FaultKind::Overcurrent || std::fabs(f.value) <= isc_A) continue;
    std::ostringstream os;
    os << f.value << " A is more than the pack can drive into a dead short: allowed [-" << isc_A << ", " << isc_A
       << "] A (" << s.pack.parallel << " parallel cell" << (s.pack.parallel > 1 ? "s" : "")
       << " at the highest OCV over the lowest R0 of the cell, 25 C)";
    throw m.mapList("faults")[k].errorAt("current_A", os.str());
  }
  s.expect = readExpect(m.optionalMap("expect"));
  if (auto c = m.optionalMap("compare")) {
    const std::string rel = c->string("scenario");
    const fs::path path = fs::path(rel).is_relative() ? fs::path(base_dir) / rel : fs::path(rel);
    if (!fs::exists(path)) throw c->errorAt("scenario", "file not found: " + path.string());
    c->finish();
    s.compare_scenario = path.string();
  }
  if ((s.expect.energy_lost_vs_compare_Wh_above || s.expect.min_cell_V_below_compare) && s.compare_scenario.empty())
    throw m.map("expect").error("energy_lost_vs_compare_Wh_above / min_cell_V_below_compare need a compare: {scenario: ...}");
  m.finish();

  // Cross-field checks, reported at the field a user would change.
  if (s.charger.present && s.run.duration_s <= 0.0 && !s.vehicle.present)
    throw m.errorAt("load", std::string("a charger needs run.duration_s: the longest the charge may run (") +
                                (s.charger.stop_run_when_done ? "the run ends earlier once the charger ends its taper"
                                                              : "load.charger.stop_run_when_done is false: the run goes on "
                                                                "after the charge") + ")");
  if (s.load.isConstant() && s.run.duration_s <= 0.0 && !s.vehicle.present)
    throw m.errorAt("load", "a constant load needs run.duration_s");
  if (s.run.duration_s <= 0.0 && s.load.duration_s() > limits::kMaxTime_s && !s.vehicle.present) {
    std::ostringstream os;
    os << "the load lasts " << s.load.duration_s() << " s (" << s.load.laps << " laps of " << s.load.lap_s()
       << " s); a run lasts at most " << limits::kMaxTime_s << " s (30 days): fewer laps or a run.duration_s";
    throw m.errorAt("load", os.str());
  }
  checkBalancing(m, s);  // also checks the FETs' thermal nodes, which the next check relies on
  checkThermistorNodes(m, s);
  applyDerivedDefaults(root, s);  // hardware derived from what the scenario states (before the range check)
  warnPartCurrentLimits(root, s);
  if (s.hardware.fet_paths == FetPaths::Separate && !s.load.i_A.empty() &&
      *std::min_element(s.load.i_A.begin(), s.load.i_A.end()) < 0.0)
    throw m.errorAt("load", "the load sits on the one-way discharge path (hardware.fet_paths: separate): it cannot "
                            "push current into the pack; a charge comes from `load: {charger: ...}`");
  if (s.vehicle.present && s.hardware.fet_paths == FetPaths::Separate &&
      (s.vehicle.params.max_regen_power_W > 0.0 || s.vehicle.array.area_m2 > 0.0))
    throw m.map("load").errorAt(s.vehicle.params.max_regen_power_W > 0.0 ? "vehicle" : "sun",
                                "the load sits on the one-way discharge path (hardware.fet_paths: separate): "
                                "regeneration and a solar array cannot charge the pack");
  // packsim's core's thresholds against the sensor: a user's firmware (bms.firmware) has
  // its own, and the core's defaults (30 A) refused its scenario on a sensitive shunt.
  const double senseRange_A = s.hardware.current_sense.zeroCode() * s.hardware.current_sense.lsb_A();
  for (const auto* p : {&s.bms.protection(bms::FaultId::OverCurrentDischarge), &s.bms.protection(bms::FaultId::OverCurrentCharge)}) {
    if (p->enabled && p->threshold >= senseRange_A && !s.bms.firmware.library) {
      std::ostringstream os;
      os << "over-current threshold " << p->threshold << " A is beyond the current sensor's range of +/-"
         << senseRange_A << " A (raise the range with a smaller shunt_ohm or amp_gain)";
      throw m.errorAt("bms", os.str());
    }
  }
  return s;
}

}  // namespace

std::string readScenarioText(const std::string& path, const std::string& what) {
  noteFileRead(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ScenarioError(path, 0, 0, "", "cannot open " + what);
  std::ostringstream os;
  os << in.rdbuf();
  std::string text = os.str();
  const std::string notText = notYamlText(text);
  if (!notText.empty()) throw ScenarioError(path, 0, 0, "", "this " + what + " is " + notText);
  return text;
}

Scenario loadScenarioFile(const std::string& path) {
  FilesReadScope reads;  // the file itself among them
  const std::string text = readScenarioText(path);
  const std::string dir = fs::path(path).parent_path().string();
  Scenario s = loadScenarioText(text, path, dir.empty() ? "." : dir);
  s.files_read = reads.files();
  return s;
}

// A vehicle ends its own run (route finished, or standing still): at most 30 days.
double Scenario::endTime_s() const {
  if (run.duration_s > 0.0) return run.duration_s;
  return vehicle.present ? limits::kMaxTime_s : load.duration_s();
}

}  // namespace packsim
