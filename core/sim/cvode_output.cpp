#include "core/sim/cvode_output.hpp"

#include <nvector/nvector_serial.h>

namespace packsim {

int cvodeOutputCombination(int nvec, realtype* c, N_Vector* X, N_Vector z) {
  if (nvec < 1) return -1;
  const sunindextype n = N_VGetLength_Serial(z);
  double* zd = N_VGetArrayPointer_Serial(z);
  const double* x0 = N_VGetArrayPointer_Serial(X[0]);
  const double c0 = c[0];
  for (sunindextype j = 0; j < n; ++j) zd[j] = c0 * x0[j];
  for (int i = 1; i < nvec; ++i) {
    const double* xd = N_VGetArrayPointer_Serial(X[i]);
    const double ci = c[i];
    for (sunindextype j = 0; j < n; ++j) zd[j] += ci * xd[j];
  }
  return 0;
}

}  // namespace packsim
