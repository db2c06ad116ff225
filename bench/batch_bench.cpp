// Batch speed-up: the same Monte Carlo cases of system D through core/batch with one
// thread and with two (wall time; results written to a temporary folder, no resume).
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "bench/benchmarks.hpp"
#include "core/batch/batch_runner.hpp"
#include "core/batch/sweep.hpp"

namespace packsim::bench {

namespace fs = std::filesystem;

namespace {

double processCpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto sec = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return sec(u.ru_utime) + sec(u.ru_stime);
}

}  // namespace

BatchFigures runBatchBench(int cases, double duration_s, int repeats) {
  char tmpl[] = "/tmp/packsim-bench-XXXXXX";
  const char* dir = mkdtemp(tmpl);
  if (!dir) throw std::runtime_error("batch bench: cannot create a temporary folder");
  const std::string text = "name: bench_batch\n"
                           "base: " + std::string(PACKSIM_SCENARIO_DIR) + "/motorcycle_110s.yaml\n"
                           "output_dir: " + std::string(dir) + "/results\n"
                           "grid:\n  run.solver: [fast]\n  run.duration_s: [" + fmt(duration_s, 3) + "]\n"
                           "monte_carlo: {samples: " + std::to_string(cases) + ", master_seed: 7}\n";
  const Sweep sweep = loadSweepText(text, "<bench>", dir);
  BatchFigures f;
  f.cases = cases;
  f.load_before = loadAverage1();
  BatchOptions o;
  o.resume = false;
  o.progress = nullptr;
  f.wall1_s = f.wall2_s = INFINITY;
  f.all_ok = true;
  for (int r = 0; r < std::max(1, repeats); ++r) {
    for (int threads : {1, 2}) {
      o.threads = threads;
      const double cpu0 = processCpu_s();
      const BatchReport rep = runBatch(sweep, o);
      const double cpu = processCpu_s() - cpu0;
      f.all_ok = f.all_ok && rep.ok == cases;
      double& best = threads == 1 ? f.wall1_s : f.wall2_s;
      if (rep.wall_s < best) {
        best = rep.wall_s;
        (threads == 1 ? f.cores1 : f.cores2) = cpu / rep.wall_s;
        (threads == 1 ? f.cpu1_s : f.cpu2_s) = cpu;
      }
    }
  }
  f.load_after = loadAverage1();
  fs::remove_all(dir);
  return f;
}

}  // namespace packsim::bench
