// What the co-simulation loop needs from an integrator of the plant ODE (plant states
// followed by the energy quadratures). Two implementations:
//
//   CvodeIntegrator  (core/sim/cvode_integrator.hpp)  the reference: adaptive BDF,
//                    error-controlled by run.rtol and the absolute tolerances
//   FastIntegrator   (core/sim/fast_integrator.hpp)   fixed sub-steps per tick:
//                    exponential RC update, explicit SOC / temperature / quadratures
//
// The ODE of the plant (states + quadratures, core/sim/plant_ode.hpp) is what both
// integrate. The loop owns time: reset() at every discontinuity (an input of the ODE jumps),
// advance(t_out, t_stop) between them. Inputs are held fixed between two resets.
#pragma once
#include <memory>

namespace packsim {

struct PlantSignals;

struct SolverStats {
  long steps = 0;      // internal steps (CVODE) or sub-steps (fast)
  long rhs_evals = 0;  // right-hand-side evaluations
  long jac_evals = 0;  // Jacobian evaluations (CVODE only)
  long reinits = 0;    // restarts at discontinuities
  long lin_setups = 0;     // linear-solver setups: Newton matrix I - γJ formed and factored (CVODE only)
  long jac_rhs_evals = 0;  // right-hand sides spent on the Jacobian's difference quotients (CVODE only)
  long jac_reused = 0;     // restarts that kept the last Jacobian instead of evaluating one (CVODE only)
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // (Re)starts the integration at t from x (length of the ODE).
  virtual void reset(double t, const double* x) = 0;
  // Integrates to t_out without stepping past t_stop (t_stop >= t_out).
  virtual void advance(double t_out, double t_stop) = 0;
  virtual const double* state() const = 0;
  virtual double time() const = 0;
  virtual SolverStats stats() const = 0;
  virtual const char* name() const = 0;  // "cvode" or "fast", as in run.solver
  // The plant's signals at (t, state()) under the inputs held since the last reset,
  // when the integrator evaluated the plant exactly there as the end of its last step
  // (no reset since); nullptr otherwise, and the loop evaluates the plant itself. The
  // signals stay valid until the next advance() or reset().
  virtual const PlantSignals* signalsAt(double t) const = 0;
};

}  // namespace packsim
