// Whether a file given as a scenario (or a preset) is YAML text at all: a result file,
// an FMU, a firmware library or other binary data handed to `run`, `check` or `show`
// would otherwise read as a YAML syntax error at some line of its bytes.
#pragma once
#include <string>

namespace packsim {

// "" for text; else what the file is and what to do with it instead.
std::string notYamlText(const std::string& bytes);

}  // namespace packsim
