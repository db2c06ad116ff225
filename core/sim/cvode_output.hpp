// The state at each t_out, as CVODE interpolates it inside its last step (CVodeGetDky):
// z = c[0]·X[0] + c[1]·X[1] + … over the q+1 Nordsieck vectors, a vector operation
// SUNDIALS dispatches on the output vector z (its ops->nvlinearcombination).
//
// A 10 ms tick is far shorter than CVODE's steps (about one step per 100 ticks on the
// small packs), so nearly every advance() of the integrator is this sum alone. Without
// an operation of its own SUNDIALS forms it as N_VScale(c[0], X[0], z) followed by
// N_VLinearSum(c[i], X[i], 1, z, z) for each further vector: z = c[0]·x0, then
// z += c[i]·xi (their special cases for c = ±1, a copy, negation, addition or
// subtraction, equal the products exactly). This function does the same arithmetic,
// element by element and in the same order, so the state is the same to the bit
// (packsim is built without floating-point contraction); it only runs as one loop of
// packsim's optimised code instead of a library call per vector (Debian's
// libsundials-cvode is built without optimisation: its linear sum costs ~16
// instructions per element). core/sim/cvode_integrator.cpp sets it on its output
// vector alone, so CVODE's internal vector operations stay the library's.
#pragma once
#include <sundials/sundials_nvector.h>

namespace packsim {

// An N_Vector_Ops::nvlinearcombination for serial vectors: z = Σ c[i]·X[i] as above;
// 0 on success, -1 for nvec < 1.
int cvodeOutputCombination(int nvec, realtype* c, N_Vector* X, N_Vector z);

}  // namespace packsim
