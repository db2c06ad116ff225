// CVODE's output interpolation (core/sim/cvode_output.hpp) against SUNDIALS' own: the
// library's N_VLinearCombination on serial vectors without fused operations (its
// fallback: N_VScale, then one N_VLinearSum per further vector) is the oracle, and the
// two must agree to the bit -- the results of every CVODE run rest on it.
#include <gtest/gtest.h>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "core/sim/cvode_integrator.hpp"
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

// A small ODE with what CVODE meets in a pack: a capacitor at constant power carried as
// its square (OdeSystem::squaredState), a damped oscillator, a stiff relaxation towards
// a moving target, a nonlinear decay and a quadrature; its power switches as an input.
class MixedOde : public OdeSystem {
 public:
  double power_W = 4.0;
  int size() const override { return 6; }
  JacobianPattern jacobianPattern() const override {
    PatternBuilder b(6);
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) b.add(r, c);
    return b.build(6, 6);
  }
  std::vector<double> absTolerances() const override { return std::vector<double>(6, 1e-8); }
  void rhs(double t, const double* x, double* dx) override {
    dx[0] = power_W / (2.0 * x[0]);
    dx[1] = x[2];
    dx[2] = -0.04 * x[1] - 0.01 * x[2];
    dx[3] = -50.0 * (x[3] - std::sin(0.1 * t));
    dx[4] = -0.1 * x[4] * x[4] * x[4] + 0.05 * std::cos(0.03 * t);
    dx[5] = x[1] * x[1];
  }
  int squaredState() const override { return 0; }
};

struct OutputRun {
  std::vector<double> states;  // every tick's state
  SolverStats stats;
  long own = 0;
  long outputs = 0;  // advance() calls
};

// 10 ms ticks over 40 s as the loop drives CVODE: the stop time mostly far ahead (a load
// breakpoint), every 211th tick at the tick's end (a pin written inside the tick), every
// 53rd tick half way into the tick and behind a step CVODE already took (a fault learnt
// of mid-tick: advance() restarts there), and the input switched with a restart every
// 7 s (order 1 again, then up).
OutputRun runMixed(bool own, CvodeIntegrator::Newton newton) {
  MixedOde ode;
  CvodeIntegrator cv(ode, 1e-7, newton);
  cv.setOwnOutputs(own);
  const double x0[6] = {3.0, 1.0, 0.0, 0.2, 0.7, 0.0};
  cv.reset(0.0, x0);
  OutputRun r;
  const double tick_s = 0.01;
  for (int k = 0; k < 4000; ++k) {
    const double t = k * tick_s, t_next = (k + 1) * tick_s;
    if (k > 0 && k % 700 == 0) {
      ode.power_W = -ode.power_W;
      cv.reset(t, cv.state());
    }
    if (k % 293 == 0) {
      const double mid = t + 0.5 * tick_s;
      cv.advance(mid, mid);
      cv.advance(t_next, t_next + 60.0);
      r.outputs += 2;
    } else {
      ++r.outputs;
      cv.advance(t_next, k % 211 == 0 ? t_next : t_next + 60.0);
    }
    r.states.insert(r.states.end(), cv.state(), cv.state() + 6);
  }
  r.stats = cv.stats();
  r.own = cv.ownOutputs();
  return r;
}

// The integrator's own outputs inside CVODE's last step (CvodeIntegrator::setOwnOutputs)
// against CVode's: the same state to the bit at every tick, and CVODE's own counters the
// same (the same steps, right-hand sides, setups: skipping the library calls left its
// stepping alone). The smooth inputs take CVODE through its orders 1 to 5.
TEST(CvodeOutput, OwnInterpolationIsCvodesToTheBitTickByTick) {
  for (CvodeIntegrator::Newton newton : {CvodeIntegrator::Newton::Sparse, CvodeIntegrator::Newton::Diagonal}) {
    const OutputRun lib = runMixed(false, newton), own = runMixed(true, newton);
    std::printf("%s: %ld steps, %ld restarts, %ld of %ld outputs formed without the library\n",
                newton == CvodeIntegrator::Newton::Sparse ? "sparse" : "diagonal", own.stats.steps, own.stats.reinits,
                own.own, own.outputs);
    EXPECT_EQ(lib.own, 0);
    // Most outputs (measured 3,344 of 4,014): CVODE's steps are longer than a tick. Its
    // orders on this run (measured): 1 to 5, mostly 3 and 4.
    EXPECT_GT(4 * own.own, 3 * own.outputs);
    ASSERT_EQ(lib.states.size(), own.states.size());
    for (size_t i = 0; i < lib.states.size(); ++i)
      ASSERT_EQ(std::memcmp(&lib.states[i], &own.states[i], sizeof(double)), 0)
          << "tick " << i / 6 << ", state " << i % 6 << ": " << lib.states[i] << " vs " << own.states[i];
    EXPECT_EQ(lib.stats.steps, own.stats.steps);
    EXPECT_EQ(lib.stats.rhs_evals, own.stats.rhs_evals);
    EXPECT_EQ(lib.stats.lin_setups, own.stats.lin_setups);
    EXPECT_EQ(lib.stats.jac_evals, own.stats.jac_evals);
    EXPECT_EQ(lib.stats.reinits, own.stats.reinits);
  }
}

// cvodeInterpolate against the library's sum (N_VLinearCombination's fallback) with
// CVodeGetDky's coefficients and vector order: random vectors and steps for every
// order, s from 0 to -1 (the test above meets CVodeGetDky itself inside CVode).
TEST(CvodeOutput, InterpolationMatchesTheLibrarysSumForEveryOrder) {
  constexpr sunindextype n = 45;
  Vectors vs(8, n);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> mag(-30.0, 30.0), frac(0.0, 1.0);
  const N_Vector lib = vs.v[6], ours = vs.v[7];
  for (int trial = 0; trial < 300; ++trial) {
    for (int k = 0; k < 6; ++k) {
      double* x = N_VGetArrayPointer(vs.v[static_cast<size_t>(k)]);
      for (sunindextype j = 0; j < n; ++j) x[j] = std::ldexp(mag(rng), static_cast<int>(mag(rng)) / 3);
    }
    const int q = 1 + trial % 5;
    const double tn = 100.0 * frac(rng), h = 1e-3 + frac(rng);
    const double t = trial % 10 == 0 ? tn : trial % 10 == 1 ? tn - h : tn - h * frac(rng);
    CvodeOutputRecord rec;
    rec.nvec = q + 1;
    std::vector<double> c;  // the library's sum: CVodeGetDky's coefficients, its vectors' order
    std::vector<N_Vector> X;
    const double s = (t - tn) / h;
    for (int j = q; j >= 0; --j) {
      double cj = 1.0;
      for (int i = 0; i < j; ++i) cj *= s;
      c.push_back(cj);
      X.push_back(vs.v[static_cast<size_t>(j)]);
      rec.x[q - j] = N_VGetArrayPointer(vs.v[static_cast<size_t>(j)]);
    }
    ASSERT_EQ(N_VLinearCombination(q + 1, c.data(), X.data(), lib), 0);
    cvodeInterpolate(rec, t, tn, h, N_VGetArrayPointer(ours), n);
    ASSERT_TRUE(sameBits(lib, ours)) << "trial " << trial << ", q = " << q;
  }
}

}  // namespace
}  // namespace packsim
