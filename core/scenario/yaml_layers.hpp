// One layer of a scenario written over another: an `extends:` child over its base, a
// `--set` override over the file, a preset field (`pack.cell.ocv_V`) over the preset.
// The three follow the same two rules (docs/scenario.md, "Layers"):
//
// - `key: null` (or `~`, or nothing after the colon) in a layer removes the key the
//   layer beneath gave (if any), so the key is as if never written (its default applies,
//   or another key of a choice can take its place). In a file of its own, with nothing
//   beneath, a null is read as the value it is (an error where a value is expected).
// - Keys that are alternatives of one choice replace each other: a layer stating one
//   drops the others beneath. A curve's form (`poly`, or a table `x`, `y`, with its
//   `axis`) is one choice; its temperature law (`arrhenius_K` / `ref_temp_C`, or a 2-D
//   table's `temp_C` rows) another, so a layer that gives only `y` or only `arrhenius_K`
//   changes that part and keeps the rest. `ambient` is `temp_C` or `profile`;
//   `hardware.thermistors` is `at_groups` or `channels`.
#pragma once
#include <yaml-cpp/yaml.h>

#include <string>

namespace packsim {

// True for a value that removes the key beneath it.
bool removesKey(const YAML::Node& value);

// A curve's mapping (states a form or a part of one).
bool isCurveMapping(const YAML::Node& n);

// Removes from `base` (a mapping at dotted key `path`) the keys that the keys of `layer`
// replace as alternatives of one choice (see above). Nothing else is touched.
void dropReplacedAlternatives(YAML::Node base, const YAML::Node& layer, const std::string& path);

}  // namespace packsim
