// The floor benchmark: bench/floor_kernel over a scenario's pack at its BMS tick.
#include <vector>

#include "bench/benchmarks.hpp"
#include "bench/floor_kernel.hpp"

namespace packsim::bench {

FloorResult runFloor(const Scenario& s, long ticks, int repeats) {
  const Plant plant(s);
  const double tick_s = s.bms.tick_s;
  double perCell = 1.0 / plant.pack().parallel;
  // A load in watts: its current at the pack's starting open-circuit voltage.
  if (s.load.quantity == LoadProfile::Quantity::Power_W) {
    const CellParams& c = plant.pack().cells.front();
    perCell /= plant.pack().series * ecm::ocv(c, s.pack.initial_soc, kReferenceTemp_C);
  }
  // The load's cell current at every tick, taken before the clock starts.
  std::vector<double> current(static_cast<size_t>(ticks));
  for (long k = 0; k < ticks; ++k) {
    const double t = static_cast<double>(k) * tick_s;
    current[static_cast<size_t>(k)] = s.load.segmentAt(t).current_A(t) * perCell;
  }
  FloorResult r;
  std::vector<double> v(static_cast<size_t>(plant.pack().cellCount()));
  const Timing t = measure(repeats, [&] {
    FloorPack pack(plant, s.thermal.cell_to_cell_W_per_K, s.ambient_C.at(0.0));
    pack.prepare(tick_s);
    double sum = 0.0;
    for (long k = 0; k < ticks; ++k) {
      sum += pack.step(current[static_cast<size_t>(k)], v.data());
      doNotOptimize(v.data());
    }
    doNotOptimize(sum);
    r.checksum = sum;
  });
  const double cellSteps = static_cast<double>(ticks) * plant.pack().cellCount();
  r.cpu_ns_per_cell_step = t.cpu_s * 1e9 / cellSteps;
  r.wall_ns_per_cell_step = t.wall_s * 1e9 / cellSteps;
  return r;
}

}  // namespace packsim::bench
