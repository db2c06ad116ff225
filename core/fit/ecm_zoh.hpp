// The cell model of `packsim fit`, simulated over a sampled test record by an exact
// zero-order hold: the plant's equations (models/cell/ecm.hpp, without hysteresis) with
// the current held constant over each sample interval [t_k, t_k+1].
//
//   soc[k+1]  = soc[k] - u[k]·dt_k / (3600·Q)
//   v_j[k+1]  = a·v_j[k] + (1 - a)·R_j(soc[k], T[k])·u[k],   a = exp(-dt_k / tau_j(soc[k], T[k]))
//   V[k]      = OCV(soc[k], T[k]) - i[k]·R0(soc[k], T[k], i[k]) - Σ_j v_j[k]
//
// u[k] is the current held over the interval after sample k; i[k] the current at sample
// k (the one across R0 when V[k] is read). Both are the caller's choice: a cycler that
// logs the current at each sample gives i; u may be i[k] or the mean of i[k] and i[k+1]
// (docs/fit.md). With R_j and tau_j constant over an interval the RC update is the exact
// solution of d v/dt = (R·u - v)/tau: no step size, no integration error.
//
// rcResponse / rcSensitivity are the fitter's building blocks: one RC branch driven by a
// given input x[k] (= R·u[k], or a column of it) with a time constant per interval, and
// the derivatives of its response with respect to parameters of log tau (the analytic
// Jacobian of the variable-projection fit, python/packsim/_fit_ecm.py).
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "models/cell/ecm.hpp"

namespace packsim::fit {

// v[0] = 0; v[k+1] = a_k·v[k] + (1 - a_k)·x[k], a_k = exp(-(t[k+1]-t[k]) / tau[k]).
// tau has one value per sample (the last is not used) or a single value (tau_len 1).
void rcResponse(const double* time_s, const double* x, size_t n, const double* tau_s, size_t tau_len, double* v);

// The same response v and its derivatives s[k, j] = d v[k] / d theta_j (row-major n × m),
// where log tau[k] depends on theta_j with slope dlogtau[k, j] (row-major n × m; a
// constant tau: one column of ones). The input x does not depend on theta.
void rcSensitivity(const double* time_s, const double* x, size_t n, const double* tau_s, size_t tau_len,
                   const double* dlogtau, size_t m, double* v, double* s);

// The model voltage of a cell (its preset, as the plant reads it) over a record:
// time_s, current_A (i), held_A (u), temp_C per sample, starting at rest at initial_soc.
std::vector<double> simulateCell(const CellParams& cell, const std::vector<double>& time_s,
                                 const std::vector<double>& current_A, const std::vector<double>& held_A,
                                 const std::vector<double>& temp_C, double initial_soc);

// A cell preset from its YAML text (the format of scenarios/cells/*.yaml), checked as a
// scenario's `cell:` is; ScenarioError naming `file` when it is not valid.
CellParams cellFromYaml(const std::string& text, const std::string& file);

}  // namespace packsim::fit
