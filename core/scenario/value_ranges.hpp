// Bounds shared by many scenario keys, each with its reason. Every number a scenario
// holds is read through a Range with finite ends (core/scenario/yaml_map.hpp refuses
// any other), so no value can overflow the simulation or the result file; a key with
// a bound of its own states it where it is read. docs/scenario.md lists every key.
#pragma once

namespace packsim::limits {

// 30 days: the longest storage or cycling run a tick-level co-simulation is for.
constexpr double kMaxTime_s = 30.0 * 86400.0;
// 100 kA: a pack of 20 parallel 50 Ah cells at 100C, beyond what any cell carries;
// a load's own pack is held to a C-rate (load_load.cpp) well below this.
constexpr double kMaxCurrent_A = 1.0e5;
// 100 MW: 1 kV at 100 kA.
constexpr double kMaxPower_W = 1.0e8;
// 100 MW for 30 days, in Wh (an energy expectation).
constexpr double kMaxEnergy_Wh = 1.0e11;
// A cell's capacity up to 10 kAh: the largest cells built hold ~1-3 kAh.
constexpr double kMaxCapacity_Ah = 1.0e4;
// A cell's resistance: 10 ohm is a dead cell; the curve checks catch the rest.
constexpr double kMaxCellResistance_ohm = 10.0;
// A conductance to a cell or node: 10 kW/K is a liquid-cooled plate many times over.
constexpr double kMaxConductance_W_per_K = 1.0e4;
// Heat capacity of a cell or thermal node: up to 1e12 J/K, the "infinite" heat
// capacity that holds a cell at its temperature in a what-if run (1e12 J/K warms by
// 1 uK per MJ); a real cell holds ~1e2..1e4 J/K.
constexpr double kMaxHeatCapacity_J_per_K = 1.0e12;
// A resistor of the hardware (pull-up, precharge, leakage): 1 GOhm is an open circuit.
constexpr double kMaxResistor_ohm = 1.0e9;
// A scenario's `seed:` (and --seed, a batch's master_seed and Monte Carlo seeds): the
// non-negative int32 range, which YAML, the result file's attribute and Python all hold.
constexpr long kMaxSeed = 2147483647L;
// Temperatures of a cell, a node, the ambient or a coolant.
constexpr double kMinTemp_C = -60.0;
constexpr double kMaxTemp_C = 150.0;

}  // namespace packsim::limits
