// CVODE's output interpolation (core/sim/cvode_output.hpp) against SUNDIALS' own: the
// library's N_VLinearCombination on serial vectors without fused operations (its
// fallback: N_VScale, then one N_VLinearSum per further vector) is the oracle, and the
// two must agree to the bit -- the results of every CVODE run rest on it.
#include <gtest/gtest.h>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "core/sim/cvode_output.hpp"

namespace packsim {
namespace {

struct Vectors {
  SUNContext ctx = nullptr;
  std::vector<N_Vector> v;
  Vectors(int count, sunindextype n) {
    SUNContext_Create(nullptr, &ctx);
    for (int i = 0; i < count; ++i) v.push_back(N_VNew_Serial(n, ctx));
  }
  ~Vectors() {
    for (N_Vector x : v) N_VDestroy(x);
    SUNContext_Free(&ctx);
  }
};

bool sameBits(N_Vector a, N_Vector b) {
  return std::memcmp(N_VGetArrayPointer(a), N_VGetArrayPointer(b), sizeof(double) * N_VGetLength(a)) == 0;
}

TEST(CvodeOutput, MatchesTheLibrarysLinearCombinationToTheBit) {
  constexpr sunindextype n = 45;  // system A's ODE: 12 cells x 3 states, a board node, 8 quadratures
  Vectors vs(8, n);               // six Nordsieck vectors, the library's output, ours
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mag(-30.0, 30.0);
  const N_Vector lib = vs.v[6], ours = vs.v[7];
  ASSERT_EQ(lib->ops->nvlinearcombination, nullptr) << "the oracle is the library's fallback";
  long compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    for (int k = 0; k < 6; ++k) {
      double* x = N_VGetArrayPointer(vs.v[static_cast<size_t>(k)]);
      // values over many decades, as states and quadratures have, and some exact zeros
      for (sunindextype j = 0; j < n; ++j) x[j] = (j % 11 == 0) ? 0.0 : std::ldexp(mag(rng), static_cast<int>(mag(rng)));
    }
    const int q = 1 + trial % 5;  // CVODE's order 1..5: q+1 vectors
    // CVodeGetDky's coefficients for k = 0: s^j, s = (t - tn)/h in [-1, 0]; the ends
    // (s = 0, -1) make coefficients 0 and ±1, which the library special-cases.
    const double s = trial % 7 == 0 ? 0.0 : trial % 7 == 1 ? -1.0 : -std::uniform_real_distribution<double>(0, 1)(rng);
    std::vector<double> c;
    std::vector<N_Vector> X;
    for (int j = q; j >= 0; --j) {
      double cj = 1.0;
      for (int i = 0; i < j; ++i) cj *= s;
      c.push_back(cj);
      X.push_back(vs.v[static_cast<size_t>(j)]);
    }
    for (int nvec = 1; nvec <= q + 1; ++nvec) {
      ASSERT_EQ(N_VLinearCombination(nvec, c.data(), X.data(), lib), 0);
      ASSERT_EQ(cvodeOutputCombination(nvec, c.data(), X.data(), ours), 0);
      ASSERT_TRUE(sameBits(lib, ours)) << "trial " << trial << ", " << nvec << " vectors, s = " << s;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 200 * 4);  // Σ over q = 1..5 of q+1 = 20 per five trials
}

TEST(CvodeOutput, ScalesInPlaceWhenTheOutputIsTheFirstVector) {
  Vectors vs(3, 4);
  double* a = N_VGetArrayPointer(vs.v[0]);
  double* b = N_VGetArrayPointer(vs.v[1]);
  const double a0[] = {1.0, -2.0, 0.5, 3.0}, b0[] = {4.0, 0.25, -1.0, 2.0};
  std::memcpy(a, a0, sizeof a0);
  std::memcpy(b, b0, sizeof b0);
  double c[] = {-0.5, 2.0};
  N_Vector X[] = {vs.v[0], vs.v[1]};
  ASSERT_EQ(cvodeOutputCombination(2, c, X, vs.v[0]), 0);
  const double want[] = {-0.5 + 8.0, 1.0 + 0.5, -0.25 - 2.0, -1.5 + 4.0};  // exact in binary
  for (int j = 0; j < 4; ++j) EXPECT_EQ(a[j], want[j]) << j;
  EXPECT_EQ(cvodeOutputCombination(0, c, X, vs.v[2]), -1);
}

}  // namespace
}  // namespace packsim
