#include "core/sim/cvode_integrator.hpp"

#include <cvode/cvode.h>
#include <cvode/cvode_diag.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "core/sim/cvode_jacobian.hpp"
#include "core/sim/cvode_output.hpp"
#include "core/sim/same_instant.hpp"

namespace packsim {

namespace {

// The ODE as CVODE sees it: the model's, with its squared state (OdeSystem::squaredState)
// carried as its square z = V² while `squared` is on (set at each restart, from the
// state's sign there). z' = 2·V·V'; V = sqrt(z), held at 0 if CVODE's trial z dips
// below. The transform is per component, so the Jacobian's pattern is the model's.
class SquaredOde final : public OdeSystem {
 public:
  explicit SquaredOde(OdeSystem& model)
      : model_(model), index_(model.squaredState()), x_(static_cast<size_t>(model.size())) {}
  int size() const override { return model_.size(); }
  JacobianPattern jacobianPattern() const override { return model_.jacobianPattern(); }
  std::vector<double> absTolerances() const override { return model_.absTolerances(); }
  void rhs(double t, const double* y, double* dy) override {
    model_.rhs(t, modelState(y), dy);
    scaleRate(dy);
  }
  void holdCouplings(double t, const double* y0) override { model_.holdCouplings(t, modelState(y0)); }
  void rhsHeld(double t, const double* y, double* dy) override {
    model_.rhsHeld(t, modelState(y), dy);
    scaleRate(dy);
  }
  int squaredState() const override { return index_; }

  bool squared() const { return squared_; }
  void setSquared(bool on) { squared_ = on && index_ >= 0; }
  // Model coordinates x from CVODE's y, and back.
  void toModel(const double* y, double* x) const {
    if (x != y) std::memcpy(x, y, sizeof(double) * x_.size());
    if (squared_) x[index_] = std::sqrt(std::max(0.0, y[index_]));
  }
  void toSolver(const double* x, double* y) const {
    if (x != y) std::memcpy(y, x, sizeof(double) * x_.size());
    if (squared_) y[index_] = x[index_] * x[index_];
  }

 private:
  const double* modelState(const double* y) {
    if (!squared_) return y;
    toModel(y, x_.data());
    return x_.data();
  }
  void scaleRate(double* dy) const {
    if (squared_) dy[index_] *= 2.0 * x_[static_cast<size_t>(index_)];
  }
  OdeSystem& model_;
  const int index_;
  bool squared_ = false;
  std::vector<double> x_;  // the model's coordinates of the last y converted
};

}  // namespace

struct CvodeIntegrator::Impl {
  SquaredOde sys;
  std::vector<double> x;      // the state in the model's coordinates (state())
  double squaredAtol = 0.0;   // the model's absolute tolerance on the squared state
  double rtol = 0.0;
  SUNContext ctx = nullptr;
  void* mem = nullptr;
  N_Vector y = nullptr;
  N_Vector atol = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  std::unique_ptr<ColouredJacobian> dq;
  // The last Jacobian the difference quotients gave (the pattern's values), the total
  // step count when it was taken, and whether the next request after a restart may
  // return it instead of a new one (see reset()).
  std::vector<double> savedJ;
  bool haveSavedJ = false;
  bool reuseSavedJ = false;
  long stepsAtJ = 0;
  long stepsBefore = 0;  // steps taken before the last CVodeReInit (its counters restart)
  long jacReused = 0;
  bool diagonal = false;  // Newton::Diagonal: CVDiag, no matrix, no Jacobian callback
  long rhsCalls = 0;      // right-hand sides CVODE asked for, its own and CVDiag's
  // CVODE's last step as its last output into y summed it (core/sim/cvode_output.hpp):
  // the Nordsieck vectors, the step's end tn and size h. `dense` while they describe
  // CVODE's history (a call returned since the last restart and took no step since).
  CvodeOutputRecord history;
  bool dense = false;
  double tn = 0.0, h = 0.0;
  bool ownOutputs = true;  // form the outputs inside the last step without the library
  long ownOutputCount = 0;

  explicit Impl(OdeSystem& s) : sys(s), x(static_cast<size_t>(s.size()), 0.0) {}
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
    ++self->rhsCalls;
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
    long nst = 0, ncf = 0;
    CVodeGetNumSteps(self->mem, &nst);
    CVodeGetNumNonlinSolvConvFails(self->mem, &ncf);
    // Before the first step after a warm restart (reset()) CVODE asks for a Jacobian at
    // every attempt, also after an error-test failure; the saved one serves until a step
    // is taken or Newton fails to converge on it.
    if (self->reuseSavedJ && nst == 0 && ncf == 0) {
      std::copy(self->savedJ.begin(), self->savedJ.end(), SM_DATA_S(J));
      ++self->jacReused;
      return 0;
    }
    self->reuseSavedJ = false;
    CVodeGetErrWeights(self->mem, tmp3);
    self->dq->fill(self->sys, t, N_VGetArrayPointer(y), N_VGetArrayPointer(fy), N_VGetArrayPointer(tmp3),
                   N_VGetArrayPointer(tmp2), N_VGetArrayPointer(tmp1), SM_DATA_S(J));
    self->savedJ.assign(SM_DATA_S(J), SM_DATA_S(J) + p.nonzeros());
    self->haveSavedJ = true;
    self->stepsAtJ = self->stepsBefore + nst;
    return 0;
  }

  // KLU's initialisation forces a new symbolic analysis (ordering) and a full
  // factorisation at the next setup; CVODE initialises its linear solver again after
  // every CVodeReInit. The matrix's pattern never changes here, so only the first one
  // is done: after it the setups refactor numerically on the same ordering (KLU checks
  // the condition estimate and factors afresh if that degrades).
  static int initializeOnce(SUNLinearSolver S) {
    if (SUNLinSol_KLUGetSymbolic(S) == nullptr) return SUNLinSolInitialize_KLU(S);
    return SUNLS_SUCCESS;
  }
};

namespace {

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("CVODE: ") + what + " failed (flag " + std::to_string(flag) + ")");
}

}  // namespace

CvodeIntegrator::CvodeIntegrator(OdeSystem& sys, double rtol, Newton newton) : impl_(std::make_unique<Impl>(sys)) {
  Impl& m = *impl_;
  const sunindextype n = sys.size();
  m.dq = std::make_unique<ColouredJacobian>(m.sys.jacobianPattern());
  check(SUNContext_Create(nullptr, &m.ctx), "SUNContext_Create");
  m.y = N_VNew_Serial(n, m.ctx);
  m.atol = N_VNew_Serial(n, m.ctx);
  const std::vector<double> atol = sys.absTolerances();
  std::copy(atol.begin(), atol.end(), N_VGetArrayPointer(m.atol));
  if (m.sys.squaredState() >= 0) m.squaredAtol = atol[static_cast<size_t>(m.sys.squaredState())];
  m.rtol = rtol;
  N_VConst(0.0, m.y);
  m.mem = CVodeCreate(CV_BDF, m.ctx);
  if (!m.mem) throw std::runtime_error("CVODE: CVodeCreate failed");
  check(CVodeInit(m.mem, &Impl::rhs, 0.0, m.y), "CVodeInit");
  // Set on y alone, after CVodeInit cloned its own vectors from it: only the output
  // interpolation into y takes it (core/sim/cvode_output.hpp).
  m.y->ops->nvlinearcombination = &cvodeOutputCombination;
  m.history.z = m.y;
  check(CVodeSetUserData(m.mem, &m), "CVodeSetUserData");
  check(CVodeSVtolerances(m.mem, rtol, m.atol), "CVodeSVtolerances");
  check(CVodeSetMaxNumSteps(m.mem, 100000), "CVodeSetMaxNumSteps");
  check(CVodeSetMaxStep(m.mem, 60.0), "CVodeSetMaxStep");
  if (newton == Newton::Diagonal) {
    m.diagonal = true;
    check(CVDiag(m.mem), "CVDiag");
    return;
  }
  m.A = SUNSparseMatrix(n, n, m.dq->pattern().nonzeros(), CSC_MAT, m.ctx);
  m.LS = SUNLinSol_KLU(m.y, m.A, m.ctx);
  if (!m.A || !m.LS) throw std::runtime_error("CVODE: sparse matrix or KLU solver not created");
  m.LS->ops->initialize = &Impl::initializeOnce;
  check(CVodeSetLinearSolver(m.mem, m.LS, m.A), "CVodeSetLinearSolver");
  check(CVodeSetJacFn(m.mem, &Impl::jac), "CVodeSetJacFn");
  // A new Newton matrix I - γJ only when γ (step × method coefficient) moved by more
  // than kGammaChangeForSetup (CVODE's default: 0.3). On a pack with parallel groups a
  // setup refactors a dense block per group (B: 28 blocks of 45×45, ~4 ms), an extra
  // Newton iteration on a matrix with an older γ costs a right-hand side and a solve;
  // CVODE scales the correction for the γ ratio, and its convergence test (not this
  // setting) decides when an iterate is accepted, so the answers keep the tolerances.
  check(CVodeSetDeltaGammaMaxLSetup(m.mem, kGammaChangeForSetup), "CVodeSetDeltaGammaMaxLSetup");
}

CvodeIntegrator::~CvodeIntegrator() = default;

void CvodeIntegrator::reset(double t, const double* x) {
  Impl& m = *impl_;
  // The step size CVODE last used, kept across restarts that took no step in between.
  realtype hLast = 0.0;
  CVodeGetLastStep(m.mem, &hLast);
  if (hLast > 0.0) lastStep_s_ = hLast;
  base_ = stats();  // CVodeReInit zeroes CVODE's own counters
  m.stepsBefore = base_.steps;
  if (x != m.x.data()) std::memcpy(m.x.data(), x, sizeof(double) * m.x.size());
  const int sq = m.sys.squaredState();
  if (sq >= 0) {
    // The squared state (a capacitor charged at near-constant power between two
    // switches): CVODE carries V² while V > 0, so that its order-1 restart meets a
    // straight line, not V's bend. Its absolute tolerance maps to V² at the restart
    // (dV² = 2·V·dV), and run.rtol on V² is rtol/2 on V: the answer is held at least
    // as tightly as in V. At V = 0 (the bus before its precharge) V² would not move
    // (z' = 2·V·V'), so it stays in V there.
    const bool wasSquared = m.sys.squared();
    const double v = m.x[static_cast<size_t>(sq)];
    m.sys.setSquared(v > 0.0);
    N_VGetArrayPointer(m.atol)[sq] = m.sys.squared() ? 2.0 * v * m.squaredAtol : m.squaredAtol;
    check(CVodeSVtolerances(m.mem, m.rtol, m.atol), "CVodeSVtolerances");
    if (m.sys.squared() != wasSquared) m.haveSavedJ = false;  // its entries were in the other coordinate
  }
  m.sys.toSolver(m.x.data(), N_VGetArrayPointer(m.y));
  check(CVodeReInit(m.mem, t, m.y), "CVodeReInit");
  // Warm restart: the history (order, higher derivatives) is dropped, the state is
  // continuous. The first step tries a quarter of the last step size (kRestartStepFraction:
  // the restart is at order 1, whose error constant is larger than that of the order
  // the last step had; CVODE's error test shrinks it further if the new inputs need
  // less), instead of CVODE's own estimate from scratch; the Newton matrix starts from
  // the last Jacobian while it is younger than CVODE's own reuse limit
  // (kJacobianMaxAgeSteps); a Newton failure on it makes CVODE ask again, and that
  // request is evaluated afresh.
  check(CVodeSetInitStep(m.mem, kRestartStepFraction * lastStep_s_), "CVodeSetInitStep");
  m.reuseSavedJ = m.haveSavedJ && base_.steps - m.stepsAtJ < kJacobianMaxAgeSteps;
  m.dense = false;
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
  if (m.dense && m.ownOutputs && ownOutputInside(t_out, std::max(t_stop, t_out))) return;
  // CVODE may have stepped ahead of t_ (it interpolates back to each t_out). A stop
  // time inside that step -- a fault the loop learnt of only now, mid-tick -- restarts
  // it at t_, where state() holds the interpolated state.
  realtype t_internal = t_;
  CVodeGetCurrentTime(m.mem, &t_internal);
  if (std::max(t_stop, t_out) < t_internal) reset(t_, m.x.data());
  check(CVodeSetStopTime(m.mem, std::max(t_stop, t_out)), "CVodeSetStopTime");
  realtype t_reached = t_;
  int flag = 0;
  {
    m.history.nvec = 0;  // a call that ends without a combination into y leaves no history
    const CvodeOutputWatch watch(m.history);
    flag = CVode(m.mem, t_out, m.y, &t_reached, CV_NORMAL);
  }
  check(flag, "CVode");
  noteHistory();
  m.sys.toModel(N_VGetArrayPointer(m.y), m.x.data());
  t_ = t_out;
}

// After CVode returned: its last output into y was CVodeGetDky's sum over the
// Nordsieck array of the step it ended on (order q = nvec - 1; after a step the step's
// size h is CVODE's last step, and CVODE's error-free return leaves h and q as the
// step had them). Checked against CVODE's own order; anything else: no history.
void CvodeIntegrator::noteHistory() {
  Impl& m = *impl_;
  int q = -1;
  realtype tn = 0.0, hu = 0.0;
  CVodeGetLastOrder(m.mem, &q);
  CVodeGetCurrentTime(m.mem, &tn);
  CVodeGetLastStep(m.mem, &hu);
  m.dense = m.history.nvec >= 2 && m.history.nvec - 1 == q && hu > 0.0;
  m.tn = tn;
  m.h = hu;
}

// What CVode(t_out) would do once it has stepped past t_out (CV_NORMAL): return
// CVodeGetDky(t_out) from the step's history, taking no step. Done here with no library
// call when t_out lies inside the last step and the stop time is not behind CVODE
// (advance() would restart it). CVODE's stop time is set again before every call that
// reaches the library, and only such a call can step: skipping CVodeSetStopTime here
// changes nothing CVODE does later (its stop time is read only when it steps).
bool CvodeIntegrator::ownOutputInside(double t_out, double t_stop) {
  Impl& m = *impl_;
  if (!(t_out <= m.tn && t_out >= m.tn - m.h && t_stop >= m.tn)) return false;
  // Straight into the model's coordinates: y's content between two CVode calls is read
  // by nothing (CVode writes it; reset() fills it from x).
  cvodeInterpolate(m.history, t_out, m.tn, m.h, m.x.data(), static_cast<long>(m.x.size()));
  m.sys.toModel(m.x.data(), m.x.data());
  t_ = t_out;
  ++m.ownOutputCount;
  return true;
}

void CvodeIntegrator::setOwnOutputs(bool on) { impl_->ownOutputs = on; }
long CvodeIntegrator::ownOutputs() const { return impl_->ownOutputCount; }

const double* CvodeIntegrator::state() const { return impl_->x.data(); }

CvodeStats CvodeIntegrator::stats() const {
  CvodeStats s = base_;
  long v = 0;
  CVodeGetNumSteps(impl_->mem, &v);
  s.steps += v;
  CVodeGetNumRhsEvals(impl_->mem, &v);
  s.rhs_evals += v;
  if (impl_->diagonal) {
    // CVDiag's difference quotients (no Jacobian): the right-hand sides CVODE asked for
    // beyond its own count (CVDiagGetNumRhsEvals is not set before the first step).
    CVodeGetNumLinSolvSetups(impl_->mem, &v);
    s.lin_setups += v;
    s.jac_rhs_evals = impl_->rhsCalls - s.rhs_evals;
    s.reinits = reinits_;
    return s;
  }
  CVodeGetNumJacEvals(impl_->mem, &v);
  s.jac_evals += v;
  CVodeGetNumLinSolvSetups(impl_->mem, &v);
  s.lin_setups += v;
  s.jac_evals -= impl_->jacReused - base_.jac_reused;  // a reused Jacobian is no evaluation
  s.jac_reused = impl_->jacReused;
  s.jac_rhs_evals = impl_->dq->rhsEvals();
  s.reinits = reinits_;
  return s;
}

}  // namespace packsim
