// `packsim show`: a loaded scenario's values with their origins (core/scenario/provenance.hpp)
// and its warnings (core/scenario/scenario_warnings.hpp), as text for a reader, as YAML
// that `packsim run` accepts back, or as JSON (docs/scenario.md "packsim show").
#pragma once
#include <string>

#include "core/scenario/scenario.hpp"

namespace packsim {

// Grouped by section, one aligned line a value: key, value, origin; then the warnings.
std::string showText(const Scenario& s);
// The scenario as YAML: what the files and --set state as keys (each with its origin as
// a comment), preset values and defaults as commented-out lines; the warnings as comments.
// Run it (from the scenario's folder, so relative paths resolve the same) and it gives
// the same results: presets and defaults are taken again, derived defaults re-derived.
std::string showYaml(const Scenario& s);
// {"values": {"key": {"value": "...", "origin": "...", "stated": true}, ...}, "warnings": [...]}
std::string showJson(const Scenario& s);

}  // namespace packsim
