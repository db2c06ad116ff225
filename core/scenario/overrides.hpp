// Scenario overrides: "set this field to this value" on top of a scenario's YAML text,
// the one implementation behind packsim.run(..., overrides) in Python and batch sweeps.
//
// A key is a dotted path from the scenario root: `pack.cell.capacity_Ah`, `seed`,
// `pack.cell.rc_pairs.0.r_ohm` or `pack.cell.rc_pairs[0].r_ohm` (list elements by
// 0-based index). A value is YAML text (`3.0`, `true`, `[1, 2]`, `{r_ohm: 0.004}`);
// JSON is YAML, so callers may pass json-encoded values. The value replaces whatever
// sat at the path (a mapping value replaces the whole mapping; callers that want a
// deep merge flatten it into one key per leaf).
//
// Missing mapping keys along the path are created, because most scenario keys are
// optional and absent from the file; the strict scenario loader then rejects a key
// that does not exist (with the closest valid one). Paths that cannot exist are
// errors here: an empty component, descending into a scalar, a non-numeric or
// out-of-range index into a list, a value that is not valid YAML.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "core/scenario/scenario.hpp"

namespace packsim {

// (dotted key, YAML value text), applied in order (a later key wins).
using Overrides = std::vector<std::pair<std::string, std::string>>;

// The file name of a Python dict scenario (packsim.run({...})): its leaves arrive as
// overrides on an empty scenario, and an error on one names it "given as KEY = VALUE".
inline constexpr const char* kDictScenarioName = "<dict>";

// Returns the scenario text with the overrides applied (the edited tree emitted by
// yaml-cpp, so comments are dropped). Throws ScenarioError naming `fileForErrors` and the key.
// With no overrides the text is returned unchanged.
std::string applyOverrides(const std::string& yamlText, const Overrides& dottedKeyToYamlValue,
                           const std::string& fileForErrors);

// The overrides applied on the parsed tree, which the loader reads directly (one parse,
// no re-emitted text in between); Scenario::text is the overridden scenario emitted.
// A ScenarioError the loader raises on a field an override set is reported against
// that override (line/column 0, the message saying which override and the allowed
// range; "given as" instead of "after override" for a kDictScenarioName file); one on an
// untouched field keeps its position in the original text.
Scenario loadScenarioWithOverrides(const std::string& yamlText, const Overrides& overrides,
                                   const std::string& file = "<scenario>", const std::string& base_dir = ".");
// Same for a file: relative CSV paths resolve against the file's folder.
Scenario loadScenarioFileWithOverrides(const std::string& path, const Overrides& overrides);

}  // namespace packsim
