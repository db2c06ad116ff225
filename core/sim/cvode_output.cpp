#include "core/sim/cvode_output.hpp"

#include <nvector/nvector_serial.h>

namespace packsim {

int cvodeOutputCombination(int nvec, realtype* c, N_Vector* X, N_Vector z) {
  if (nvec < 1) return -1;
  // Element by element, every input read before the output is written: z may be any of
  // the X[i] (the library's own general case is safe only for X[0]).
  const sunindextype n = NV_LENGTH_S(z);
  double* zd = NV_DATA_S(z);
  for (sunindextype j = 0; j < n; ++j) {
    double acc = c[0] * NV_DATA_S(X[0])[j];
    for (int i = 1; i < nvec; ++i) acc += c[i] * NV_DATA_S(X[i])[j];
    zd[j] = acc;
  }
  return 0;
}

}  // namespace packsim
