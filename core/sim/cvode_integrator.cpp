#include "core/sim/cvode_integrator.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "core/sim/cvode_jacobian.hpp"
#include "core/sim/same_instant.hpp"

namespace packsim {

struct CvodeIntegrator::Impl {
  OdeSystem& sys;
  SUNContext ctx = nullptr;
  void* mem = nullptr;
  N_Vector y = nullptr;
  N_Vector atol = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  std::unique_ptr<ColouredJacobian> dq;

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

  // The sparse Jacobian by coloured difference quotients (core/sim/cvode_jacobian.hpp).
  // CVODE zeroes the matrix, pattern included, before asking: the same pattern is written
  // back every time, so KLU refactors numerically on its first symbolic analysis.
  static int jac(realtype t, N_Vector y, N_Vector fy, SUNMatrix J, void* user, N_Vector tmp1, N_Vector tmp2,
                 N_Vector tmp3) {
    auto* self = static_cast<Impl*>(user);
    const JacobianPattern& p = self->dq->pattern();
    sunindextype* colptr = SM_INDEXPTRS_S(J);
    sunindextype* rows = SM_INDEXVALS_S(J);
    std::copy(p.colptr.begin(), p.colptr.end(), colptr);
    std::copy(p.rows.begin(), p.rows.end(), rows);
    CVodeGetErrWeights(self->mem, tmp3);
    self->dq->fill(self->sys, t, N_VGetArrayPointer(y), N_VGetArrayPointer(fy), N_VGetArrayPointer(tmp3),
                   N_VGetArrayPointer(tmp2), N_VGetArrayPointer(tmp1), SM_DATA_S(J));
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
  m.dq = std::make_unique<ColouredJacobian>(sys.jacobianPattern());
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
  m.A = SUNSparseMatrix(n, n, m.dq->pattern().nonzeros(), CSC_MAT, m.ctx);
  m.LS = SUNLinSol_KLU(m.y, m.A, m.ctx);
  if (!m.A || !m.LS) throw std::runtime_error("CVODE: sparse matrix or KLU solver not created");
  check(CVodeSetLinearSolver(m.mem, m.LS, m.A), "CVodeSetLinearSolver");
  check(CVodeSetJacFn(m.mem, &Impl::jac), "CVodeSetJacFn");
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
  // A sliver (core/sim/same_instant.hpp) is no interval: CVODE would refuse it ("tout too
  // close to t0") and the state cannot change across it.
  if (reached(t_, t_out)) {
    t_ = t_out;
    return;
  }
  Impl& m = *impl_;
  // CVODE may have stepped ahead of t_ (it interpolates back to each t_out). A stop
  // time inside that step -- a fault the loop learnt of only now, mid-tick -- restarts
  // it at t_, where m.y holds the interpolated state.
  realtype t_internal = t_;
  CVodeGetCurrentTime(m.mem, &t_internal);
  if (std::max(t_stop, t_out) < t_internal) reset(t_, N_VGetArrayPointer(m.y));
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
