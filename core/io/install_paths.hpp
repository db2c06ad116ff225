// Where an installed packsim finds its data at run time. Nothing here is compiled in:
// the paths are found relative to the running executable (or set by the environment),
// so the same binary works from the build tree, from a wheel and from any folder.
//
//   bundled scenarios   $PACKSIM_SCENARIOS, else the first of <exe>/scenarios,
//                       <exe>/../scenarios (wheel: packsim/_bin/packsim -> packsim/scenarios)
//   Python package      $PACKSIM_PYTHONPATH, else the first folder holding
//                       packsim/__init__.py of <exe>/python (build tree), <exe>/../..
//                       (wheel: site-packages)
//
// <exe> is the folder of the running executable with symbolic links resolved. In a
// Python process (the extension) <exe> is the interpreter's folder, so the package
// sets $PACKSIM_SCENARIOS itself (python/packsim/__init__.py).
#pragma once
#include <string>
#include <vector>

namespace packsim {

// Folder of the running executable ("" if it cannot be determined).
std::string executableDir();
// The first existing folder of `candidates` that contains `marker` (a relative path),
// or "" if none does.
std::string firstFolderWith(const std::vector<std::string>& candidates, const std::string& marker);

}  // namespace packsim
