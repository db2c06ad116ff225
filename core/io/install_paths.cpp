#include "core/io/install_paths.hpp"

#include <filesystem>
#include <system_error>

namespace packsim {

namespace fs = std::filesystem;

std::string executableDir() {
  std::error_code ec;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

std::string firstFolderWith(const std::vector<std::string>& candidates, const std::string& marker) {
  std::error_code ec;
  for (const std::string& c : candidates) {
    if (c.empty()) continue;
    if (fs::exists(fs::path(c) / marker, ec)) return fs::weakly_canonical(c, ec).string();
  }
  return "";
}

}  // namespace packsim
