#include "core/sim/cvode_integrator.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_band.h>
#include <sunmatrix/sunmatrix_band.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace packsim {

struct CvodeIntegrator::Impl {
  OdeSystem& sys;
  SUNContext ctx = nullptr;
  void* mem = nullptr;
  N_Vector y = nullptr;
  N_Vector atol = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  bool initialised = false;

  explicit Impl(OdeSystem& s) : sys(s) {}
  ~Impl() {
    if (mem) CVodeFree(&mem);
    if (LS) SUNLinSolFree(LS);
    if (A) SUNMatDestroy(A);
    if (y) N_VDestroy(y);
    if (atol) N_VDestroy(atol);
    if (ctx) SUNContext_Free(&ctx);
  }

  static int rhs(realtype t, N_Vector y, N_Vector ydot, void* user) {
    auto* self = static_cast<Impl*>(user);
    self->sys.rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
    return 0;
  }

  // Banded difference-quotient Jacobian that respects OdeSystem::bandedSize().
  // CVODE's own banded DQ perturbs every (2·bw+1)-th column at once and credits a
  // row's change to the one perturbed column inside the row's band. A row that depends
  // on states outside its band (the energy quadratures depend on every cell) then gets
  // the sum of all those changes as a spurious in-band entry, which stalls its Newton
  // correction: the quadratures came out as if their rate were frozen. Here the banded
  // block is perturbed in column groups with only banded rows recorded, and each loose
  // column alone; loose rows keep only what the loose columns give them.
  static int jac(realtype t, N_Vector y, N_Vector fy, SUNMatrix J, void* user, N_Vector tmp1, N_Vector tmp2,
                 N_Vector tmp3) {
    auto* self = static_cast<Impl*>(user);
    const sunindextype n = N_VGetLength(y);
    const sunindextype nb = std::min<sunindextype>(self->sys.bandedSize(), n);
    const sunindextype bw = SM_UBAND_B(J);
    const double* y0 = N_VGetArrayPointer(y);
    const double* f0 = N_VGetArrayPointer(fy);
    double* f1 = N_VGetArrayPointer(tmp1);
    double* y1 = N_VGetArrayPointer(tmp2);
    double* ewt = N_VGetArrayPointer(tmp3);
    CVodeGetErrWeights(self->mem, tmp3);
    N_VScale(1.0, y, tmp2);
    SUNMatZero(J);
    const double srur = std::sqrt(UNIT_ROUNDOFF);
    auto inc = [&](sunindextype j) { return srur * std::max(std::fabs(y0[j]), 1.0 / ewt[j]); };
    const sunindextype width = 2 * bw + 1;
    for (sunindextype g = 0; g < std::min(width, nb); ++g) {
      for (sunindextype j = g; j < nb; j += width) y1[j] += inc(j);
      self->sys.rhs(t, y1, f1);
      for (sunindextype j = g; j < nb; j += width) {
        const double h = inc(j);
        y1[j] = y0[j];
        double* col = SM_COLUMN_B(J, j);
        for (sunindextype i = std::max<sunindextype>(0, j - bw); i <= std::min(nb - 1, j + bw); ++i)
          SM_COLUMN_ELEMENT_B(col, i, j) = (f1[i] - f0[i]) / h;
      }
    }
    for (sunindextype j = nb; j < n; ++j) {
      const double h = inc(j);
      y1[j] += h;
      self->sys.rhs(t, y1, f1);
      y1[j] = y0[j];
      double* col = SM_COLUMN_B(J, j);
      for (sunindextype i = std::max<sunindextype>(0, j - bw); i <= std::min(n - 1, j + bw); ++i)
        SM_COLUMN_ELEMENT_B(col, i, j) = (f1[i] - f0[i]) / h;
    }
    return 0;
  }
};

namespace {

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("CVODE: ") + what + " failed (flag " + std::to_string(flag) + ")");
}

}  // namespace

CvodeIntegrator::CvodeIntegrator(OdeSystem& sys, double rtol) : impl_(std::make_unique<Impl>(sys)) {
  Impl& m = *impl_;
  const sunindextype n = sys.size();
  const sunindextype bw = std::min<sunindextype>(sys.halfBandwidth(), n - 1);
  check(SUNContext_Create(nullptr, &m.ctx), "SUNContext_Create");
  m.y = N_VNew_Serial(n, m.ctx);
  m.atol = N_VNew_Serial(n, m.ctx);
  const std::vector<double> atol = sys.absTolerances();
  std::copy(atol.begin(), atol.end(), N_VGetArrayPointer(m.atol));
  N_VConst(0.0, m.y);
  m.mem = CVodeCreate(CV_BDF, m.ctx);
  if (!m.mem) throw std::runtime_error("CVODE: CVodeCreate failed");
  check(CVodeInit(m.mem, &Impl::rhs, 0.0, m.y), "CVodeInit");
  check(CVodeSetUserData(m.mem, &m), "CVodeSetUserData");
  check(CVodeSVtolerances(m.mem, rtol, m.atol), "CVodeSVtolerances");
  m.A = SUNBandMatrix(n, bw, bw, m.ctx);
  m.LS = SUNLinSol_Band(m.y, m.A, m.ctx);
  check(CVodeSetLinearSolver(m.mem, m.LS, m.A), "CVodeSetLinearSolver");
  if (sys.bandedSize() < sys.size()) check(CVodeSetJacFn(m.mem, &Impl::jac), "CVodeSetJacFn");
  check(CVodeSetMaxNumSteps(m.mem, 100000), "CVodeSetMaxNumSteps");
  check(CVodeSetMaxStep(m.mem, 60.0), "CVodeSetMaxStep");
}

CvodeIntegrator::~CvodeIntegrator() = default;

void CvodeIntegrator::reset(double t, const double* x) {
  Impl& m = *impl_;
  base_ = stats();  // CVodeReInit zeroes CVODE's own counters
  double* y = N_VGetArrayPointer(m.y);
  if (x != y) std::memcpy(y, x, sizeof(double) * static_cast<size_t>(m.sys.size()));
  check(CVodeReInit(m.mem, t, m.y), "CVodeReInit");
  t_ = t;
  ++reinits_;
}

void CvodeIntegrator::advance(double t_out, double t_stop) {
  if (!(t_out > t_)) return;
  Impl& m = *impl_;
  check(CVodeSetStopTime(m.mem, std::max(t_stop, t_out)), "CVodeSetStopTime");
  realtype t_reached = t_;
  const int flag = CVode(m.mem, t_out, m.y, &t_reached, CV_NORMAL);
  check(flag, "CVode");
  t_ = t_out;
}

const double* CvodeIntegrator::state() const { return N_VGetArrayPointer(impl_->y); }

CvodeStats CvodeIntegrator::stats() const {
  CvodeStats s = base_;
  long v = 0;
  CVodeGetNumSteps(impl_->mem, &v);
  s.steps += v;
  CVodeGetNumRhsEvals(impl_->mem, &v);
  s.rhs_evals += v;
  CVodeGetNumJacEvals(impl_->mem, &v);
  s.jac_evals += v;
  s.reinits = reinits_;
  return s;
}

}  // namespace packsim
