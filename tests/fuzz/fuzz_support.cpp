#include "fuzz_support.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "core/scenario/load_scenario.hpp"

namespace packsim::fuzz {

namespace fs = std::filesystem;

std::vector<std::string> splitParts(const uint8_t* data, size_t size, size_t max_parts) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> parts;
  size_t start = 0;
  while (parts.size() + 1 < max_parts) {
    const size_t cut = text.find("\n#---\n", start);
    if (cut == std::string::npos) break;
    parts.push_back(text.substr(start, cut + 1 - start));
    start = cut + 6;
  }
  parts.push_back(text.substr(start));
  return parts;
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

const std::string& scratchDir() {
  static const std::string dir = [] {
    const fs::path d = fs::temp_directory_path() / ("packsim-fuzz-" + std::to_string(getpid()));
    fs::remove_all(d);
    fs::create_directories(d / "cells");
    fs::create_directories(d / "profiles");
    const fs::path bundled = bundledScenarioDir();
    fs::copy_file(bundled / "eco_marathon_12s.yaml", d / "base.yaml");
    fs::copy_file(bundled / "profiles" / "eco_marathon_lap.csv", d / "profiles" / "eco_marathon_lap.csv");
    fs::copy_file(bundled / "profiles" / "eco_marathon_lap.csv", d / "profiles" / "lap.csv");
    for (const auto& e : fs::directory_iterator(bundled / "cells")) fs::copy_file(e.path(), d / "cells" / e.path().filename());
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(fs::temp_directory_path() / ("packsim-fuzz-" + std::to_string(getpid())), ec);
    });
    return d.string();
  }();
  return dir;
}

}  // namespace packsim::fuzz
