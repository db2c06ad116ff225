// A fixed-step integrator of the plant for large batches (`run.solver: fast`).
//
// Between two resets the inputs are held (relay, load segment, injected faults), and
// each advance(t_k -> t_out) takes n equal sub-steps h = (t_out - t_k)/n with
//
//   n = ceil((t_out - t_k) / h_max),
//   h_max = min(max_substep_s (if > 0),  substep_fraction · Plant::explicitTimeConstant_s())
//
// One sub-step from (t, x) with rates f = Plant::derivatives(t, x) already known:
//
//   RC branch  v <- v + τ·f_v·(1 - e^{-h/τ})          exact exponential update of
//              ( = v·e^{-h/τ} + i·R·(1 - e^{-h/τ}) )   dv/dt = (i·R - v)/τ, i frozen
//                                                      (τ of a pair that varies with
//                                                      SOC or temperature: at the start;
//                                                      a hysteresis state likewise, with
//                                                      τ = 3600/(γ·|i|))
//   others     x <- x + h·f_x                          explicit Euler: SOC, temperatures,
//                                                      any state the plant adds later
//   quadrature q <- q + h/2·(g(t, x) + g(t+h, x'))     trapezoid (charge, energies, heat)
//
// The rates at the end of a sub-step are those at the start of the next one, so a
// sub-step costs one evaluation of the plant. A reset (an input jumped) discards them.
//
// Stability and accuracy rule: explicit Euler on a mode with time constant τ is stable
// for h < 2τ; h <= 0.1·τ_min (the default fraction) keeps the fastest explicit mode's
// amplification at 0.9 per sub-step and its local error below 0.5 %. The RC branches'
// own decay is exact for any h, so a 10 ms … 1 s tick usually needs a single sub-step.
// Nothing is allocated after construction.
#pragma once
#include <vector>

#include "core/sim/integrator.hpp"
#include "core/sim/plant.hpp"

namespace packsim {

struct FastSettings {
  double max_substep_s = 0.0;       // cap on the sub-step; 0: none beyond the rule
  double substep_fraction = 0.1;    // sub-step <= fraction · smallest explicit time constant
};

class FastIntegrator : public Integrator {
 public:
  // `inputs` is read at every evaluation; the caller changes it only before a reset().
  FastIntegrator(const Plant& plant, const PlantInputs& inputs, const FastSettings& settings);

  void reset(double t, const double* x) override;
  void advance(double t_out, double t_stop) override;
  const double* state() const override { return x_.data(); }
  double time() const override { return t_; }
  SolverStats stats() const override { return stats_; }
  const char* name() const override { return "fast"; }
  // The largest sub-step the rule allows (s).
  double maxSubstep_s() const { return hMax_; }
  // The signals of the last sub-step's end, when it ended at t (Integrator::signalsAt):
  // the loop samples them instead of evaluating the plant a second time there.
  const PlantSignals* signalsAt(double t) const override { return ratesValid_ && t == t_ ? &sig_ : nullptr; }

 private:
  void evaluateRates();        // rates_ at (t_, x_)
  void prepareGains(double h); // gain_k = τ_k·(1 - e^{-h/τ_k}) - h for the current h
  void substep(double h, double t_end);

  const Plant& plant_;
  const PlantInputs& in_;
  int n_ = 0;                    // plant states; quadratures follow in x_
  double hMax_ = 0.0;
  std::vector<double> x_;        // [plant states…, quadratures…]
  std::vector<double> rates_;    // d/dt of x_ at (t_, x_)
  std::vector<double> quadStart_;
  std::vector<int> socState_;       // each cell's SOC state
  std::vector<double> socRateStart_;  // its rate at the sub-step's start
  std::vector<int> rcState_;
  std::vector<double> rcTau_s_;
  std::vector<Plant::RcBranch> rcBranches_;
  std::vector<size_t> variableRc_;  // branches whose τ is taken at every sub-step
  std::vector<double> rcGain_;   // extra factor on top of the Euler step: τ(1-e^{-h/τ}) - h
  double gainStep_s_ = -1.0;     // h the gains were computed for
  PlantSignals sig_;
  bool ratesValid_ = false;
  double t_ = 0.0;
  SolverStats stats_;
};

}  // namespace packsim
