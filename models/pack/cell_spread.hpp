// Cell-to-cell spread: every cell of a pack drawn from a seeded distribution around
// the nominal cell, then explicit per-cell values applied on top.
//
//   capacity_Ah      = nominal · (1 + capacity_rel_sd · z1)
//   r0_scale         = 1 + r0_rel_sd · z2
//   initial_soc      = nominal + initial_soc_sd · z3          (clamped to 0…1)
//   self_discharge_A = nominal + |self_discharge_A_sd · z4|
//
// z ~ N(0,1) from a stream derived from the scenario seed (separate from sensor noise),
// truncated at ±3σ so no cell gets a non-physical value. With per_group the draw is
// made once per series group (module-level drift) and shared by its parallel cells.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "models/cell/ecm.hpp"

namespace packsim {

struct CellSpread {
  double capacity_rel_sd = 0.0;
  double r0_rel_sd = 0.0;
  double initial_soc_sd = 0.0;
  double self_discharge_A_sd = 0.0;
  bool per_group = false;
};

struct CellOverride {
  int cell = 0;  // 0-based
  std::optional<double> capacity_Ah, r0_scale, initial_soc, self_discharge_A;
};

struct PackCells {
  std::vector<CellParams> params;
  std::vector<double> initial_soc;
};

PackCells drawCells(const CellParams& nominal, double nominal_soc, int count, int parallel, const CellSpread& spread,
                    const std::vector<CellOverride>& overrides, uint64_t seed);

}  // namespace packsim
