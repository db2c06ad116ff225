#include "core/scenario/files_read.hpp"

#include <algorithm>

namespace packsim {

namespace {
thread_local FilesReadScope* active = nullptr;
}

FilesReadScope::FilesReadScope() : outer_(active) {
  if (!outer_) active = this;
}

FilesReadScope::~FilesReadScope() {
  if (!outer_) active = nullptr;
}

void noteFileRead(const std::string& path) {
  if (!active) return;
  std::vector<std::string>& f = active->files_;
  if (std::find(f.begin(), f.end(), path) == f.end()) f.push_back(path);
}

}  // namespace packsim
