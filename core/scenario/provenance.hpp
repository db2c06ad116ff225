// Where each value of a scenario came from: `packsim show` (docs/scenario.md).
//
// While a scenario loads, the active Provenance (one per thread, set by a Scope)
// receives every value the loader's getters read (core/scenario/yaml_map.cpp): its
// dotted key, its YAML text and its origin -- `file:line` of the file of the extends
// chain that set it, `preset NAME (file:line)` for a field of a cell preset, `--set`
// for an override, `default` for a getter's fallback, and `default (...)` for a value
// the loader derived from others (core/scenario/derived_defaults.hpp). It also collects
// load-time warnings (an override that replaced a table by a single value).
#pragma once
#include <yaml-cpp/yaml.h>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace packsim {

struct ProvenanceEntry {
  std::string key;     // dotted key as the loader names it: pack.cell.r0_ohm, faults[0].at_s
  std::string value;   // YAML text (flow style for lists and mappings)
  std::string origin;  // file:line | preset NAME (file:line) | --set KEY | default | default (...)
  bool stated = false; // written by the user (a file of the chain or --set): `show --format yaml` emits it
};

class Provenance {
 public:
  explicit Provenance(std::string topFile) : top_(displayName(topFile)) {}

  // The thread's recorder while a scenario loads (nullptr: nothing is recorded).
  static Provenance* active();
  class Scope {  // makes `p` (or nullptr: pause) the active recorder until destroyed
   public:
    explicit Scope(Provenance* p);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    Provenance* previous_;
  };

  // Which file set which part of the merged tree (the extends chain).
  void resetFiles(const std::string& file);                            // every key from `file`
  void setFile(const std::string& path, const std::string& file);      // `path` and below from `file`
  void eraseUnder(const std::string& path);                            // `path` and below dropped
  std::string fileOf(const std::string& path) const;                   // the file that set `path`
  // An override (--set, Python overrides): `field` is the loader's field name of its key.
  void addOverride(const std::string& field, const std::string& text);
  // Whether an override set `key` or a mapping or list above it.
  bool overridden(const std::string& key) const;
  // Keys under `path` not in `scenarioKeys` come from the cell preset `name` (file `file`).
  void addPresetScope(const std::string& path, const std::string& name, const std::string& file,
                      const std::vector<std::string>& scenarioKeys);

  void recordNode(const std::string& key, const YAML::Node& n);
  void recordDefault(const std::string& key, const std::string& valueYaml, const std::string& origin = "default");
  void warn(const std::string& text);
  // A mapping the scenario holds (its presence can matter: `fuse: {}` is a fuse).
  void markSection(const std::string& key) {
    if (!presetFor(key)) sections_.insert(key);  // a preset's own mappings come with the preset
  }
  bool sectionPresent(const std::string& key) const { return key.empty() || sections_.count(key) > 0; }

  // Entries in reading order (a key recorded twice keeps its first place, its last value).
  std::vector<ProvenanceEntry> entries() const;
  const ProvenanceEntry* find(const std::string& key) const;
  // "origin" of a key, or "default" when the loader never read it.
  std::string originOf(const std::string& key) const;
  // "key = value (origin)" for messages.
  std::string describe(const std::string& key, const std::string& fallbackValue = "") const;
  const std::vector<std::string>& warnings() const { return warnings_; }
  const std::string& topFile() const { return top_; }

  static std::string displayName(const std::string& path);

 private:
  std::string originFor(const std::string& key, const YAML::Node& n, bool& stated) const;
  void put(ProvenanceEntry e);

  struct PresetScope {
    std::string path, name, file;
    std::vector<std::string> scenarioKeys;
  };
  const PresetScope* presetFor(const std::string& key) const;  // the preset a key's value comes from
  std::string top_;
  std::map<std::string, std::string> files_;  // path prefix -> file that set it
  std::vector<std::pair<std::string, std::string>> overrides_;  // (field, "KEY=VALUE")
  std::vector<PresetScope> presets_;
  std::vector<ProvenanceEntry> entries_;
  std::vector<bool> alive_;
  std::map<std::string, size_t> index_;
  std::vector<std::string> warnings_;
  std::set<std::string> sections_;
};

// A YAML node as one line of YAML text (flow style for lists and mappings).
std::string yamlFlowText(const YAML::Node& n);
// A number as the shortest text that reads back to the same double.
std::string numberText(double v);
// True when `inner` is `outer` or lies below it ("a.b" under "a", "a[0]" under "a").
bool keyUnder(const std::string& inner, const std::string& outer);

}  // namespace packsim
