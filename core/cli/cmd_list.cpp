// `packsim list`: the bundled scenarios and cell presets with one-line descriptions.
#include <algorithm>
#include <iostream>

#include "core/cli/commands.hpp"

namespace packsim {

int cmdList() {
  const std::vector<CatalogEntry> all = bundledCatalog();
  size_t width = 0;
  for (const CatalogEntry& e : all) width = std::max(width, e.name.size());
  std::string kind;
  for (const CatalogEntry& e : all) {
    if (e.kind != kind) {
      kind = e.kind;
      std::cout << (kind == "scenario" ? "scenarios (packsim run NAME):\n"
                                       : "\ncells (pack.cell.preset: NAME):\n");
    }
    std::cout << "  " << e.name << std::string(width - e.name.size() + 2, ' ') << e.description << "\n";
  }
  std::cout << "\nfolder: " << bundledScenarioDir() << "\n";
  return 0;
}

}  // namespace packsim
