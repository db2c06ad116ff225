// The simulator's view of the BMS settings table (bms/bms_settings.def): one row per
// scalar firmware setting -- its `bms.` key, unit, range and default, its firmware field
// and unit, its doc line. The loader reads a section's rows straight into firmware units
// (BmsSettings::image), the bridge copies them into the flashed image
// (bms::copySettings), `packsim show` lists each with where it came from, and
// docs/scenario.md's settings table is settingsDocTable() (a test compares them).
#pragma once
#include <bms/bms_config.hpp>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/scenario/yaml_map.hpp"

namespace packsim {

enum class SettingKind { Number, Integer, Flag, Enable, Choice };

struct SettingRow {
  const char* key;     // under `bms.`: "balancing.start_delta_mV"
  SettingKind kind;
  const char* unit;    // of the key's value ("" for none)
  const char* fwUnit;  // of the firmware field
  double mul, div;     // firmware value = key value * mul / div
  double def;          // in the key's unit (a choice: its index; Enable: the value without the section)
  double lo, hi;       // allowed key values
  bool loOpen;
  std::vector<std::string> choices;  // a choice's names, in enum order
  const char* doc;
  void (*set)(bms::Config&, double keyValue);  // converted as the firmware converts its defaults
  double (*get)(const bms::Config&);           // the field, in firmware units

  std::string section() const;  // "balancing" ("" at the top of `bms`)
  std::string leaf() const;     // "start_delta_mV"
  std::string defaultText() const;  // as `show` and the docs print it
  std::string rangeText() const;    // "[1, 2000]", "true | false", "charging | rest | ..."
};

const std::vector<SettingRow>& settingRows();
const SettingRow& settingRow(const std::string& key);  // std::out_of_range for an unknown key

// Reads the rows of `section` from `m` (m absent: the section is not stated; defaults,
// recorded for `packsim show`) into `image`. Returns each row's value in its key's unit,
// by leaf name, for checks across keys. The caller finishes `m`.
std::map<std::string, double> readSettings(YamlMap* m, const std::string& section, bms::Config& image);

// The name of a choice row's current value ("charging_or_rest"), and the index of a name (-1: none).
std::string settingChoice(const std::string& key, const bms::Config& image);
int settingChoiceIndex(const std::string& key, const std::string& name);
// A setting's value in its key's unit (firmware value * div / mul).
double settingValue(const std::string& key, const bms::Config& image);

// The markdown rows of docs/scenario.md's settings table, in row order.
std::string settingsDocTable();

}  // namespace packsim
