// A sweep: one base scenario and the parameters to vary, expanded into cases.
//
//   name: resistor_sweep              # default: the sweep file's stem
//   base: ../scenarios/motorcycle_110s.yaml   # relative to the sweep file
//   output_dir: runs/resistor_sweep   # default: <name>-results beside the sweep file
//   threads: 0                        # 0 (default): every core
//   grid:                             # cartesian product, one axis per key
//     pack.cell.capacity_Ah: [38, 40, 42]
//     bms.tick_ms: [10, 100]
//   zip:                              # equal-length lists varied together (one axis)
//     pack.initial_soc: [0.9, 0.8]
//     ambient.temp_C: [20, 35]
//   monte_carlo:                      # one more axis: N seeds from one master seed
//     samples: 100
//     master_seed: 7
//
// Keys are dotted paths into the scenario YAML; values are any YAML (numbers, strings,
// lists, mappings). At least one of grid / zip / monte_carlo. Cases are the cartesian
// product of all axes, the first grid key varying slowest and the seed fastest.
// Monte Carlo sets the scenario's `seed` (which draws the cell spread) of sample i to
// monteCarloSeed(master_seed, i): splitmix64 of master_seed + (i+1)·0x9E3779B97F4A7C15,
// masked to the scenario's seed range [0, 2^31-1].
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace packsim {

struct SweepCase {
  int index = 0;        // 0-based position in the expansion
  std::string id;       // zero-padded index, names the result file
  std::vector<std::pair<std::string, std::string>> params;  // dotted key -> YAML value (flow text)
};

struct Sweep {
  std::string name;
  std::string file;         // the sweep YAML's path ("" for inline text)
  std::string base_path;    // resolved base scenario path
  std::string base_text;    // its YAML
  std::string output_dir;   // resolved
  int threads = 0;          // 0: every core
  std::vector<std::string> keys;  // varied keys in column order
  std::vector<SweepCase> cases;

  std::string resultPath(const SweepCase& c) const;  // <output_dir>/case_<id>.h5
  std::string summaryCsvPath() const;                // <output_dir>/summary.csv
};

// Seed of Monte Carlo sample i: splitmix64 via deriveSeed (models/random/random.hpp,
// the same derivation the cell spread uses for its streams), masked to [0, 2^31-1].
uint64_t monteCarloSeed(uint64_t master_seed, uint64_t sample);

// Strict like a scenario: unknown keys, wrong types, unequal zip lengths, a key varied
// twice are ScenarioErrors naming file:line:column; so is a varied value the base
// scenario refuses on its own (each value loaded alone on the base: about a scenario
// load per distinct value). ValueCheck::Skip leaves that out: the fuzz harness, whose
// value loads are the overrides harness's code, at the sweep parser's own input rate.
enum class ValueCheck { Load, Skip };
Sweep loadSweepFile(const std::string& path);
Sweep loadSweepText(const std::string& text, const std::string& file, const std::string& base_dir,
                    ValueCheck check = ValueCheck::Load);

}  // namespace packsim
