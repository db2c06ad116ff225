#include "core/fit/ecm_zoh.hpp"

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cmath>
#include <stdexcept>

#include "core/scenario/scenario_error.hpp"
#include "core/scenario/scenario_sections.hpp"
#include "core/scenario/yaml_map.hpp"

namespace packsim::fit {

namespace {

double tauAt(const double* tau_s, size_t tau_len, size_t k) { return tau_len == 1 ? tau_s[0] : tau_s[k]; }

}  // namespace

void rcResponse(const double* time_s, const double* x, size_t n, const double* tau_s, size_t tau_len, double* v) {
  if (n == 0) return;
  v[0] = 0.0;
  for (size_t k = 0; k + 1 < n; ++k) {
    const double one_minus_a = -std::expm1(-(time_s[k + 1] - time_s[k]) / tauAt(tau_s, tau_len, k));
    v[k + 1] = v[k] + one_minus_a * (x[k] - v[k]);  // a·v + (1 - a)·x
  }
}

void rcSensitivity(const double* time_s, const double* x, size_t n, const double* tau_s, size_t tau_len,
                   const double* dlogtau, size_t m, double* v, double* s) {
  if (n == 0) return;
  using Row = Eigen::Map<Eigen::RowVectorXd>;
  using ConstRow = Eigen::Map<const Eigen::RowVectorXd>;
  v[0] = 0.0;
  Row(s, static_cast<Eigen::Index>(m)).setZero();
  for (size_t k = 0; k + 1 < n; ++k) {
    const double tau = tauAt(tau_s, tau_len, k);
    const double dt_over_tau = (time_s[k + 1] - time_s[k]) / tau;
    const double a = std::exp(-dt_over_tau);
    const double one_minus_a = -std::expm1(-dt_over_tau);
    // d a / d theta_j = a · dt/tau · d log tau / d theta_j
    const double drift = a * dt_over_tau * (v[k] - x[k]);
    Row next(s + (k + 1) * m, static_cast<Eigen::Index>(m));
    next = a * ConstRow(s + k * m, static_cast<Eigen::Index>(m)) +
           drift * ConstRow(dlogtau + k * m, static_cast<Eigen::Index>(m));
    v[k + 1] = v[k] + one_minus_a * (x[k] - v[k]);
  }
}

std::vector<double> simulateCell(const CellParams& cell, const std::vector<double>& time_s,
                                 const std::vector<double>& current_A, const std::vector<double>& held_A,
                                 const std::vector<double>& temp_C, double initial_soc) {
  const size_t n = time_s.size();
  if (current_A.size() != n || held_A.size() != n || temp_C.size() != n)
    throw std::invalid_argument("simulate_cell: time_s, current_A, held_A and temp_C need the same length");
  if (cell.has_hysteresis)
    throw std::invalid_argument("simulate_cell: a cell with hysteresis is not a model packsim fit simulates");
  for (size_t k = 1; k < n; ++k)
    if (!(time_s[k] > time_s[k - 1])) throw std::invalid_argument("simulate_cell: time_s must increase strictly");
  std::vector<double> out(n);
  std::vector<double> v_rc(cell.rc.size(), 0.0);
  double soc = initial_soc;
  const double q_As = 3600.0 * cell.capacity_Ah;
  for (size_t k = 0; k < n; ++k) {
    const double t_C = temp_C[k];
    double v = ecm::ocv(cell, soc, t_C) - current_A[k] * ecm::r0(cell, soc, t_C, current_A[k]);
    for (double x : v_rc) v -= x;
    out[k] = v;
    if (k + 1 == n) break;
    const double dt = time_s[k + 1] - time_s[k];
    const double u = held_A[k];
    for (size_t j = 0; j < cell.rc.size(); ++j) {
      const RcPair& pair = cell.rc[j];
      const double r = ecm::rcR_ohm(pair, cell, soc, t_C);
      const double tau = r * ecm::rcC_F(pair, cell, soc, t_C);
      v_rc[j] += -std::expm1(-dt / tau) * (r * u - v_rc[j]);
    }
    const double eta = u < 0.0 ? cell.coulombic_efficiency : 1.0;
    soc -= (eta * u + cell.self_discharge_A) * dt / q_As;
  }
  return out;
}

CellParams cellFromYaml(const std::string& text, const std::string& file) {
  YAML::Node node;
  try {
    node = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ScenarioError(file, e.mark.line + 1, e.mark.column + 1, "", e.msg);
  }
  if (!node.IsMap()) throw ScenarioError(file, 1, 1, "", "a cell preset is a mapping (capacity_Ah, ocv_V, ...)");
  return readCell(YamlMap(node, file, ""));
}

}  // namespace packsim::fit
