#include <cstdio>
#include <iostream>

#include "core/check/check.hpp"
#include "core/cli/commands.hpp"

namespace packsim {

int cmdCheck(const CheckOptions& o) {
  const std::vector<std::string> files = collectScenarioFiles(o.paths.empty() ? std::vector<std::string>{bundledScenarioDir()} : o.paths);
  if (files.empty()) {
    std::cerr << "packsim: error: no scenario files found\n";
    return 2;
  }
  int passed = 0, failed = 0, unchecked = 0, skipped = 0;
  for (const std::string& f : files) {
    const CheckOutcome c = checkScenarioFile(f, o.target);
    if (c.skipped) {  // --target on a host-mode library: not run
      ++skipped;
      std::cout << "SKIP  " << c.error_message << "\n";
      continue;
    }
    if (!c.passed) ++failed; else if (c.nothing_to_check) ++unchecked; else ++passed;
    std::cout << (c.error ? "ERROR " : !c.passed ? "FAIL  " : c.nothing_to_check ? "RAN   " : "PASS  ") << f;
    if (c.error) {
      std::cout << "\n      " << c.error_message << "\n";
      continue;
    }
    std::cout << "  -- " << c.verdict << "\n";
    for (const auto& l : c.latencies) std::cout << "      injected " << l << "\n";
    for (const auto& l : c.target) std::cout << "      target " << l << "\n";
    for (const auto& l : c.failures) std::cout << "      failed: " << l << "\n";
    for (const auto& l : c.warnings) std::cout << "      warning: " << l << "\n";
  }
  std::cout << passed << " passed, " << failed << " failed";
  if (unchecked > 0) std::cout << ", " << unchecked << " ran with nothing to check";
  if (skipped > 0) std::cout << ", " << skipped << " skipped (a firmware library: not on --target)";
  std::cout << "\n";
  return failed == 0 ? 0 : 1;
}

}  // namespace packsim
