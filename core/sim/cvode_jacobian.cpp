#include "core/sim/cvode_jacobian.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>

namespace packsim {

ColouredJacobian::ColouredJacobian(JacobianPattern p)
    : p_(std::move(p)), groups_(colourColumns(p_)), inc_(static_cast<size_t>(p_.n), 0.0) {}

void ColouredJacobian::fill(OdeSystem& sys, double t, const double* x, const double* f0, const double* w, double* x1,
                            double* f1, double* values) {
  const double srur = std::sqrt(DBL_EPSILON);
  std::memcpy(x1, x, sizeof(double) * static_cast<size_t>(p_.n));
  std::fill(values, values + p_.nonzeros(), 0.0);  // columns >= read stay zero
  sys.holdCouplings(t, x);
  for (const std::vector<int>& group : groups_) {
    for (int j : group) {
      const size_t js = static_cast<size_t>(j);
      const double h = srur * std::max(std::fabs(x[js]), 1.0 / w[js]);
      x1[js] = x[js] + h;
      inc_[js] = x1[js] - x[js];  // the increment actually represented
    }
    sys.rhsHeld(t, x1, f1);
    ++rhsEvals_;
    for (int j : group) {
      const size_t js = static_cast<size_t>(j);
      x1[js] = x[js];
      const double inv = 1.0 / inc_[js];
      for (int k = p_.colptr[js]; k < p_.colptr[js + 1]; ++k) {
        const size_t i = static_cast<size_t>(p_.rows[static_cast<size_t>(k)]);
        values[k] = (f1[i] - f0[i]) * inv;
      }
    }
  }
}

}  // namespace packsim
