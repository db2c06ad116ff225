// Plant::jacobianPattern: which states each state's rate depends on.
//
//   cell states       every state of every cell in the same parallel group: the group's
//                     current split moves each cell's current with any cell's EMF and
//                     R0 (SOC, RC voltages, hysteresis, temperature); a cell's
//                     temperature also with its thermal neighbours (cells or nodes)
//   extra nodes, bus  loose rows (core/sim/sparsity.hpp): their own state, the other
//                     extra nodes they are linked to; not the cells (a node's heat from
//                     the cells' currents, its conduction from the cells' temperatures)
//   bus column        every cell row: the bus precharge current comes from the stack
//   quadratures       nothing reads them
//
// Complete for a current load. Under a power load or a charger the pack current
// depends on every cell through the pack's EMF: that coupling (rank one) is left out,
// and the Jacobian's difference quotients hold the current (PlantOde::holdCouplings) so
// it does not leak into the listed entries. Left out and not held: the active
// balancer's bus precharge current, drawn from the whole stack while the bus charges.
#include "core/sim/plant.hpp"

namespace packsim {

JacobianPattern Plant::jacobianPattern(int quadratures) const {
  const int cells = pack_.cellCount();
  const int local = cells * stride_;
  const int n = stateSize_ + quadratures;
  PatternBuilder b(n);
  for (int g = 0; g < pack_.series; ++g) {
    const int first = g * pack_.parallel * stride_;
    const int last = first + pack_.parallel * stride_;
    for (int col = first; col < last; ++col)
      for (int row = first; row < last; ++row) b.add(row, col);
  }
  for (const ThermalLink& l : thermal_.links) {
    const int ia = tempIndex(l.a), ib = tempIndex(l.b);
    if (ia < local || ib >= local) b.add(ia, ib);
    if (ib < local || ia >= local) b.add(ib, ia);
  }
  if (busIndex_ >= 0)
    for (int row = 0; row < local; ++row) b.add(row, busIndex_);
  return b.build(local, stateSize_);
}

}  // namespace packsim
