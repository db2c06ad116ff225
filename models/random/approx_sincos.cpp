#include "models/random/approx_sincos.hpp"

#include <cmath>

namespace packsim {

namespace {

SinCosTable makeSinCosTable() {
  SinCosTable t{};
  for (int k = 0; k <= SinCosTable::kSteps; ++k) {
    const double a = 6.283185307179586 * k / SinCosTable::kSteps;
    t.at[k] = SinCosTable::Entry{a, std::sin(a), std::cos(a)};
  }
  return t;
}

}  // namespace

const SinCosTable kSinCosTable = makeSinCosTable();

}  // namespace packsim
