// The bundled scenarios and cell presets by name: what `packsim list` prints and what
// `packsim run NAME`, `packsim.run("NAME")` and `balance-time --preset NAME` resolve.
//
// A scenario's name is its file name without .yaml, in any folder of the bundled
// scenarios except cells/ (motorcycle_110s, a_host_dead, bench_6s_balancing); a
// folder-qualified name (faults/a_host_dead) works too. Its description is the
// scenario's `description:`, else (and for a cell preset) the first sentence of the
// file's leading comment.
#pragma once
#include <string>
#include <vector>

namespace packsim {

struct CatalogEntry {
  std::string kind;         // "scenario" or "cell"
  std::string name;         // run / preset name
  std::string path;         // the YAML file
  std::string description;  // one line ("" if the file has none)
};

// Every bundled scenario then every cell preset, each sorted by name.
std::vector<CatalogEntry> bundledCatalog();
// Path of a bundled scenario by name; throws std::invalid_argument naming the closest
// name and listing the known ones.
std::string presetPath(const std::string& name);

}  // namespace packsim
