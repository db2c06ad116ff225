// `packsim batch SWEEP.yaml`: expands the sweep, checks the first case strictly before
// anything runs (a misspelt key fails the whole sweep at once, exit 2), runs the cases
// on a thread pool and writes one result per case plus summary.csv. Exit 0 when every
// case succeeded, 1 when any failed (their errors are in the CSV).
#include <cstdio>
#include <filesystem>

#include "core/batch/batch_runner.hpp"
#include "core/batch/sweep.hpp"
#include "core/cli/commands.hpp"
#include "core/io/hdf5_writer.hpp"
#include "core/scenario/overrides.hpp"
#include "core/sim/stop_signal.hpp"

namespace packsim {

int cmdBatch(const BatchCliOptions& o) {
  Sweep sw = loadSweepFile(o.sweep);
  if (!o.output_dir.empty()) sw.output_dir = o.output_dir;
  if (!sw.cases.empty()) {
    const std::string dir = std::filesystem::path(sw.base_path).parent_path().string();
    loadScenarioWithOverrides(sw.base_text, sw.cases.front().params, sw.base_path + " (sweep " + sw.name + ", case " +
                                                                          sw.cases.front().id + ")",
                              dir.empty() ? "." : dir);
  }
  checkResultPathWritable(sw.summaryCsvPath());  // before any case runs
  BatchOptions opt;
  opt.threads = o.threads;
  opt.resume = !o.no_resume;
  opt.progress = o.quiet ? nullptr : stdout;
  opt.isolate = true;  // a case that crashes is recorded, the others finish
  if (!o.quiet)
    std::printf("sweep %s: %zu cases from %s -> %s\n", sw.name.c_str(), sw.cases.size(), sw.base_path.c_str(),
                sw.output_dir.c_str());
  const BatchReport r = runBatch(sw, opt);
  if (!o.quiet)
    std::printf("%d ok (%d already complete), %d failed, %.1f s on %d threads; summary %s\n", r.ok, r.skipped, r.failed,
                r.wall_s, r.threads, r.csv_path.c_str());
  for (size_t i = 0; i < r.cases.size(); ++i)
    if (!r.cases[i].ok) std::fprintf(stderr, "case_%s failed: %s\n", sw.cases[i].id.c_str(), r.cases[i].error.c_str());
  if (const int sig = stopSignal()) {
    int notRun = 0;
    for (const CaseOutcome& c : r.cases) notRun += c.ok ? 0 : 1;
    throw Interrupted(sig, "batch interrupted by " + stopSignalName(sig) + ": " + std::to_string(r.ok) + " of " +
                               std::to_string(r.total) + " cases complete, " + std::to_string(notRun) +
                               " not; run the same command again to resume");
  }
  return r.failed > 0 ? 1 : 0;
}

}  // namespace packsim
