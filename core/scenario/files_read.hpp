// Every file a scenario load reads: the files of its extends: chain, cell presets, the load,
// route and irradiance CSVs, a firmware config_file. The readers note each one as they open
// it, so a caller that must know when a loaded scenario is out of date (a resumed batch,
// core/batch/case_inputs.hpp) has the loader's own list rather than a re-derivation of it
// that misses a kind of file. The loader fills Scenario::files_read.
#pragma once
#include <string>
#include <vector>

namespace packsim {

// While alive, the thread's collector of noted files; a load inside a load (a base checked
// alone, a sweep value) adds to the outermost one.
class FilesReadScope {
 public:
  FilesReadScope();
  ~FilesReadScope();
  FilesReadScope(const FilesReadScope&) = delete;
  FilesReadScope& operator=(const FilesReadScope&) = delete;

  bool outermost() const { return outer_ == nullptr; }
  const std::vector<std::string>& files() const { return files_; }  // first read first, each once

 private:
  friend void noteFileRead(const std::string& path);
  FilesReadScope* outer_;
  std::vector<std::string> files_;
};

// Called by each reader as it opens `path` (nothing happens outside a scope).
void noteFileRead(const std::string& path);

}  // namespace packsim
