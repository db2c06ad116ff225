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
//
// The combination also tells, while a CvodeOutputWatch on its output vector is alive,
// which vectors CVodeGetDky summed (the Nordsieck array zn[q], …, zn[0], in that order)
// with their data: until CVODE's next step the integrator forms the next outputs
// itself from them (cvodeInterpolate), with no library call at all.
#pragma once
#include <sundials/sundials_nvector.h>

namespace packsim {

// An N_Vector_Ops::nvlinearcombination for serial vectors: z = Σ c[i]·X[i] as above;
// 0 on success, -1 for nvec < 1.
int cvodeOutputCombination(int nvec, realtype* c, N_Vector* X, N_Vector z);

// z[j] = Σ_i c[i]·x[i][j] for j < n, summed in i order (z may be any x[i]).
void cvodeCombine(int nvec, const double* c, const double* const* x, double* z, long n);

// The vectors of the last combination into one output vector.
struct CvodeOutputRecord {
  static constexpr int kMaxVectors = 6;  // BDF's highest order is 5: q+1 vectors
  N_Vector z = nullptr;                  // the output vector watched
  int nvec = 0;                          // vectors of its last combination (0: none, or too many)
  const double* x[kMaxVectors] = {};     // their data, in the order they were summed
};

// While alive, the combinations into rec.z made on this thread are noted in rec
// (each one replaces the last). Not nested.
class CvodeOutputWatch {
 public:
  explicit CvodeOutputWatch(CvodeOutputRecord& rec);
  ~CvodeOutputWatch();
  CvodeOutputWatch(const CvodeOutputWatch&) = delete;
  CvodeOutputWatch& operator=(const CvodeOutputWatch&) = delete;
};

// CVodeGetDky(t, k = 0) inside the step the record's vectors describe: with
// s = (t - tn)/h, the coefficient of zn[j] is s^j formed as CVODE forms it (1, then
// j multiplications by s), and the sum is cvodeOutputCombination's; so the result is
// the library's to the bit. rec.nvec - 1 is the order q of that step.
void cvodeInterpolate(const CvodeOutputRecord& rec, double t, double tn, double h, double* z, long n);

}  // namespace packsim
