"""The equivalent-circuit model packsim.fit adjusts to test data, and the least-squares
solve. The model is the plant's (models/cell/ecm.hpp), every sample at its temperature T:

    v_term = OCV(soc) - i·R0(soc)·f0(T) - Σ v_k,   d v_k/dt = (u·R_k(soc)·f_k(T) - v_k) / (tau_k·g_k(T))
    soc    = soc_0 - ∫ u dt / (3600·Q)        (positive current discharges)

f(T) = exp(K·(1/T_K - 1/T_ref,K)) are Arrhenius factors (T_ref = 25 °C), fitted only in a
joint fit over several temperatures (Layout.arrhenius); otherwise all K are 0. With rests at
several temperatures (Layout.ocv_dT) the OCV has a temperature coefficient over SOC too:
OCV(soc, T) = OCV(soc) + (T - T_ref)·dOCV/dT(soc), both tables over the SOC grid. The current
u held over a sample interval is the mean of its two ends, and the RC voltages follow
the exact zero-order hold of their equation, computed in C++ (packsim._packsim.rc_response,
core/fit/ecm_zoh.hpp). Every file starts with the cell at rest (all v_k = 0).

For fixed nonlinear parameters theta — log tau_k and, jointly over temperatures, the
Arrhenius constants — the voltage is *linear* in everything else: the OCV and R0 table
values (each sample a weighted sum of two neighbouring nodes), R0's polynomial
coefficients, the RC resistances (an RC voltage is a linear filter of its input). So the
fit is a variable projection (Golub & Pereyra): scipy.optimize.least_squares moves theta;
for each trial the linear parameters are the solution of a small normal-equation system,
built from the sparse fixed columns (precomputed) and the RC columns (C++); the Jacobian
is Kaufman's, from the analytic derivatives of the RC responses (C++,
rc_sensitivity). At the optimum the linear parameters are solved once more with bounds
(scipy.optimize.lsq_linear): resistances positive, the OCV's rise from node to node
positive (the preset loader requires a strictly increasing OCV).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._fit_data import CellTest, FitError

__all__ = ["Layout", "Trace", "LinearFit", "prepare", "fit_group", "soc_trace", "held_current", "REF_TEMP_C",
           "SMOOTH_WEIGHT"]

SMOOTH_WEIGHT = 0.1   # second-difference penalty on table values (fills nodes without data)
R_MIN_OHM = 1e-7      # resistances stay positive (the loader requires > 0)
OCV_STEP_MIN_V = 1e-5  # the OCV table rises strictly with SOC (the loader requires it)
REF_TEMP_C = 25.0     # reference temperature of the fitted Arrhenius laws
K_SCALE = 1000.0      # Arrhenius constants are moved in kK (theta of order 1)
K_BOUNDS_K = (-10000.0, 20000.0)
K_START_K = {"r": 2000.0, "tau": 0.0}
DOCV_DT_MAX_V_PER_K = 0.01  # the preset loader's range of docv_dT_V_per_K


@dataclass(frozen=True)
class Layout:
    """What is fitted: the SOC grid of the tables, R0's form, the RC pairs, and whether
    the resistances and time constants follow fitted Arrhenius laws over temperature."""
    soc_grid: np.ndarray
    form: str               # "table" (R0 over the SOC grid) or "poly" (R0 over discharged Ah)
    poly_order: int
    rc_pairs: int
    rc_over_soc: bool       # RC resistances as tables over the grid (else constants)
    capacity_Ah: float
    arrhenius: bool = False
    smooth_weight: float = SMOOTH_WEIGHT
    ocv_dT: bool = False    # an OCV temperature coefficient over the grid (rests at several temperatures)
    dT_scale_K: float = 1.0  # its smoothing rows are weighted by the span of temperatures (V, like the OCV's)

    def r0_columns(self) -> int:
        return self.poly_order + 1 if self.form == "poly" else self.soc_grid.size

    def rc_columns(self) -> int:
        return self.soc_grid.size if self.rc_over_soc else 1

    def thetas(self) -> int:
        return self.rc_pairs + (1 + 2 * self.rc_pairs if self.arrhenius else 0)

    def fixed_columns(self) -> int:
        """OCV, R0 and (with ocv_dT) the OCV's temperature coefficient: the columns that do
        not depend on the nonlinear parameters."""
        return self.soc_grid.size * (2 if self.ocv_dT else 1) + self.r0_columns()


@dataclass
class Trace:
    """One test prepared for the model."""
    test: CellTest
    soc: np.ndarray          # at each sample
    held_A: np.ndarray       # current held over the interval after each sample
    ocv_w: object            # sparse [samples, grid]: interpolation weights
    r0_basis: object         # sparse [samples, r0 columns]: weights, or powers of discharged Ah
    rc_input: np.ndarray     # [samples, rc columns]: u, or u·weights
    temp_C: np.ndarray       # each sample's temperature (REF_TEMP_C where none is known)
    g: np.ndarray            # 1/T_K - 1/T_ref,K


@dataclass
class LinearFit:
    """The solution: parameters and tau (at REF_TEMP_C when arrhenius)."""
    ocv_V: np.ndarray                # at the grid
    r0: np.ndarray                   # table values at the grid, or poly coefficients (highest first)
    rc_r_ohm: np.ndarray             # [pairs, rc columns]
    rc_tau_s: np.ndarray             # [pairs]
    r0_K: float = 0.0                # Arrhenius constants (0 without a temperature law)
    rc_r_K: np.ndarray | None = None
    rc_tau_K: np.ndarray | None = None
    evaluations: int = 0
    docv_dT: np.ndarray | None = None  # V/K at the grid (None: no temperature coefficient)


def soc_trace(test: CellTest, soc0: float, capacity_Ah: float) -> np.ndarray:
    """Coulomb-counted SOC at every sample (the held current: trapezoidal charge)."""
    dq_Ah = held_current(test.current_A, test.steps_on_samples)[:-1] * np.diff(test.time_s) / 3600.0
    return soc0 - np.concatenate(([0.0], np.cumsum(dq_Ah))) / capacity_Ah


def held_current(current_A: np.ndarray, steps_on_samples: bool = False) -> np.ndarray:
    """The current held over each interval: the mean of its two ends (the last sample's own),
    or with steps_on_samples the current of the sample that starts it.

    A step inside an interval at a fraction phi of it puts (1 - phi)·ΔI of charge-weighted
    current there; the mean assumes phi = 1/2, exact on average over steps at random phase
    (and for a current linear between samples). A step logged at the sample it happens at
    (phi = 1 for the interval before it) is off by ΔI/2 over that interval: the model's RC
    voltages at the step sample are too large by Σ_j (1 - exp(-Δt/τ_j))·R_j·ΔI/2, which the
    fit takes out of R0 (docs/fit.md "Where the current steps")."""
    if steps_on_samples:
        return np.array(current_A, dtype=float, copy=True)
    u = np.empty_like(current_A)
    u[:-1] = 0.5 * (current_A[1:] + current_A[:-1])
    u[-1] = current_A[-1]
    return u


def _weights(soc: np.ndarray, grid: np.ndarray):
    from scipy.sparse import csr_matrix
    s = np.clip(soc, grid[0], grid[-1])  # held flat beyond the grid, as the loader's tables
    j = np.clip(np.searchsorted(grid, s, side="right") - 1, 0, grid.size - 2)
    f = (s - grid[j]) / (grid[j + 1] - grid[j])
    rows = np.repeat(np.arange(soc.size), 2)
    cols = np.column_stack([j, j + 1]).ravel()
    vals = np.column_stack([1.0 - f, f]).ravel()
    return csr_matrix((vals, (rows, cols)), shape=(soc.size, grid.size))


def prepare(test: CellTest, soc0: float, layout: Layout, temp_C: np.ndarray | None = None) -> Trace:
    from scipy.sparse import csr_matrix
    soc = soc_trace(test, soc0, layout.capacity_Ah)
    w = _weights(soc, layout.soc_grid)
    u = held_current(test.current_A, test.steps_on_samples)
    if layout.form == "poly":
        r0_basis = csr_matrix(np.vander((1.0 - soc) * layout.capacity_Ah, layout.poly_order + 1))
    else:
        r0_basis = w
    rc_input = (w.multiply(u[:, None])).toarray() if layout.rc_over_soc else u[:, None].copy()
    temp = np.full(soc.size, REF_TEMP_C) if temp_C is None else np.asarray(temp_C, dtype=float)
    g = 1.0 / (temp + 273.15) - 1.0 / (REF_TEMP_C + 273.15)
    return Trace(test, soc, u, w, r0_basis, rc_input, temp, g)


def _ocv_basis(n: int) -> np.ndarray:
    """OCV values = basis @ (OCV at the first node, then the rise to each next node): the
    rises are bounded below, so the fitted OCV increases strictly with SOC."""
    return np.tril(np.ones((n, n)))


def _smoothing(layout: Layout, i_scale_A: float) -> tuple[np.ndarray, int]:
    """Second-difference rows on every table block (OCV, R0 table, RC tables), on the
    nodal values."""
    n = layout.soc_grid.size
    d2 = np.zeros((max(n - 2, 0), n))
    for k in range(n - 2):
        d2[k, k:k + 3] = (1.0, -2.0, 1.0)
    weight = layout.smooth_weight
    blocks = [(0, weight)]
    if layout.form == "table":
        blocks.append((n, weight * i_scale_A))
    if layout.ocv_dT:
        blocks.append((n + layout.r0_columns(), weight * layout.dT_scale_K))
    start = layout.fixed_columns()
    if layout.rc_over_soc:
        blocks += [(start + p * n, weight * i_scale_A) for p in range(layout.rc_pairs)]
    cols = start + layout.rc_pairs * layout.rc_columns()
    rows = np.zeros((d2.shape[0] * len(blocks), cols))
    for b, (c0, w) in enumerate(blocks):
        rows[b * d2.shape[0]:(b + 1) * d2.shape[0], c0:c0 + n] = w * d2
    return rows, cols


def _bounds(layout: Layout, cols: int) -> tuple[np.ndarray, np.ndarray]:
    """Bounds in the solve's variables: OCV as its first value and rises."""
    n = layout.soc_grid.size
    lo = np.full(cols, R_MIN_OHM)
    hi = np.full(cols, np.inf)
    lo[0], hi[0] = 0.1, 10.0                        # OCV at the first node (the loader wants > 0)
    lo[1:n] = OCV_STEP_MIN_V                        # its rise to each next node
    if layout.form == "poly":
        lo[n:n + layout.r0_columns()] = -np.inf     # polynomial coefficients: any sign
    if layout.ocv_dT:
        d0 = n + layout.r0_columns()
        lo[d0:d0 + n], hi[d0:d0 + n] = -DOCV_DT_MAX_V_PER_K, DOCV_DT_MAX_V_PER_K
    return lo, hi


def _gram(a, b=None) -> np.ndarray:
    """aᵀb in einsum's own loops (not a threaded BLAS: bit-identical on any machine load)."""
    return np.einsum("ki,kj->ij", a, a if b is None else b)


class _Problem:
    """The separable least-squares problem: A(theta)·p ≈ measured, plus smoothing rows S·p ≈ 0.
    A = [F(theta) | C(theta)]: F the sparse OCV and R0 columns, C the RC columns."""

    def __init__(self, traces: list[Trace], layout: Layout) -> None:
        from scipy.sparse import vstack
        self.traces = traces
        self.layout = layout
        self.n = layout.soc_grid.size
        self.nr = self.n + layout.r0_columns()  # R0's columns end here
        self.nf = layout.fixed_columns()
        i_scale = max(float(np.max(np.abs(t.test.current_A))) for t in traces)
        self.smooth, self.cols = _smoothing(layout, i_scale)
        self.sts = _gram(self.smooth)
        self.lo, self.hi = _bounds(layout, self.cols)
        self.measured = np.concatenate([t.test.voltage_V for t in traces])
        self.g = np.concatenate([t.g for t in traces])
        self.ocv_w = vstack([t.ocv_w for t in traces]).tocsr()
        self.r0_i = vstack([t.r0_basis.multiply(-t.test.current_A[:, None]) for t in traces]).tocsr()
        self.ocv_t = vstack([t.ocv_w.multiply((t.temp_C - REF_TEMP_C)[:, None]) for t in traces]).tocsr() \
            if layout.ocv_dT else None
        self._theta = None
        self.evaluations = 0

    def split(self, theta: np.ndarray):
        pairs = self.layout.rc_pairs
        tau = np.exp(theta[:pairs])
        if not self.layout.arrhenius:
            return tau, 0.0, np.zeros(pairs), np.zeros(pairs)
        k = K_SCALE * theta[pairs:]
        return tau, float(k[0]), k[1:1 + pairs], k[1 + pairs:]

    def _fixed(self, r0_K: float):
        from scipy.sparse import diags, hstack
        r0 = self.r0_i if r0_K == 0.0 else (diags(np.exp(r0_K * self.g)) @ self.r0_i)
        return hstack([self.ocv_w, r0] + ([self.ocv_t] if self.ocv_t is not None else [])).tocsr()

    def _rc(self, tau: np.ndarray, r_K: np.ndarray, tau_K: np.ndarray) -> np.ndarray:
        from ._packsim import rc_response
        rc_cols = self.layout.rc_columns()
        c = np.zeros((self.measured.size, self.layout.rc_pairs * rc_cols))
        row = 0
        for t in self.traces:
            rows = slice(row, row + t.soc.size)
            for p in range(self.layout.rc_pairs):
                tau_k = np.array([tau[p]]) if tau_K[p] == 0.0 else tau[p] * np.exp(tau_K[p] * t.g)
                scale = None if r_K[p] == 0.0 else np.exp(r_K[p] * t.g)
                for j in range(rc_cols):
                    x = t.rc_input[:, j] if scale is None else t.rc_input[:, j] * scale
                    c[rows, p * rc_cols + j] = -rc_response(t.test.time_s, x, tau_k)
            row += t.soc.size
        return c

    def evaluate(self, theta: np.ndarray) -> None:
        """The free (unbounded) solution for theta, and what the Jacobian needs."""
        from scipy.linalg import cho_factor, cho_solve
        if self._theta is not None and np.array_equal(theta, self._theta):
            return
        self.evaluations += 1
        tau, r0_K, r_K, tau_K = self.split(theta)
        f = self._fixed(r0_K)
        c = self._rc(tau, r_K, tau_K)
        ftf = (f.T @ f).toarray()
        ftc = np.asarray(f.T @ c)
        gram = np.block([[ftf, ftc], [ftc.T, _gram(c)]]) + self.sts
        rhs = np.concatenate([f.T @ self.measured, c.T @ self.measured])
        scale = np.sqrt(np.diag(gram))
        scale[scale == 0] = 1.0
        gram_n = gram / scale[:, None] / scale[None, :]
        gram_n[np.diag_indices_from(gram_n)] += 1e-12
        try:
            self.chol = cho_factor(gram_n)
        except np.linalg.LinAlgError:
            raise FitError("the fit did not converge: the parameters cannot be told apart by these tests "
                           "(a singular problem; fewer RC pairs or a coarser SOC grid may help)") from None
        self.scale = scale
        self.p = cho_solve(self.chol, rhs / scale) / scale
        self.f, self.c, self.gram, self.rhs = f, c, gram, rhs
        self.tau, self.r0_K, self.r_K, self.tau_K = tau, r0_K, r_K, tau_K
        self._theta = np.array(theta, copy=True)

    def model(self, p: np.ndarray) -> np.ndarray:
        return self.f @ p[:self.nf] + self.c @ p[self.nf:]

    def residual(self, theta: np.ndarray) -> np.ndarray:
        self.evaluate(theta)
        return np.concatenate([self.model(self.p) - self.measured, self.smooth @ self.p])

    def jacobian(self, theta: np.ndarray) -> np.ndarray:
        """Kaufman's variable-projection Jacobian: column j is P⊥·(dA/dtheta_j)·p, with
        (dA/dtheta_j)·p from the analytic derivatives of the RC responses (C++)."""
        from scipy.linalg import cho_solve
        from ._packsim import rc_response, rc_sensitivity
        self.evaluate(theta)
        lay = self.layout
        pairs, rc_cols = lay.rc_pairs, lay.rc_columns()
        h = np.zeros((self.measured.size, lay.thetas()))
        row = 0
        for t in self.traces:
            rows = slice(row, row + t.soc.size)
            for p in range(pairs):
                r_p = self.p[self.nf + p * rc_cols:self.nf + (p + 1) * rc_cols]
                x = t.rc_input @ r_p
                if self.r_K[p] != 0.0:
                    x = x * np.exp(self.r_K[p] * t.g)
                if lay.arrhenius:
                    tau_k = self.tau[p] * np.exp(self.tau_K[p] * t.g)
                    dlog = np.column_stack([np.ones_like(t.g), K_SCALE * t.g])
                    _, s = rc_sensitivity(t.test.time_s, x, tau_k, dlog)
                    h[rows, p] = -s[:, 0]
                    h[rows, pairs + 1 + pairs + p] = -s[:, 1]
                    h[rows, pairs + 1 + p] = -rc_response(t.test.time_s, x * (K_SCALE * t.g), tau_k)
                else:
                    _, s = rc_sensitivity(t.test.time_s, x, np.array([self.tau[p]]), np.ones((t.soc.size, 1)))
                    h[rows, p] = -s[:, 0]
            row += t.soc.size
        if lay.arrhenius:
            h[:, pairs] = (self.f[:, self.n:self.nr] @ self.p[self.n:self.nr]) * (K_SCALE * self.g)
        ath = np.vstack([np.asarray(self.f.T @ h), np.einsum("ki,kj->ij", self.c, h)])
        y = cho_solve(self.chol, ath / self.scale[:, None]) / self.scale[:, None]
        return np.vstack([h - (self.f @ y[:self.nf] + self.c @ y[self.nf:]), -(self.smooth @ y)])

    def bounded(self) -> np.ndarray:
        """The linear parameters at the current theta with their bounds (lsq_linear on the
        Cholesky-reduced problem: ||A p - b||² = ||R q - d||² + const)."""
        from scipy.linalg import cholesky, solve_triangular
        from scipy.optimize import lsq_linear
        n = self.n
        basis = np.eye(self.cols)
        basis[:n, :n] = _ocv_basis(n)
        gram_q = np.einsum("ki,kl,lj->ij", basis, self.gram, basis, optimize=False)
        rhs_q = np.einsum("ki,k->i", basis, self.rhs)
        norm = np.sqrt(np.diag(gram_q))
        norm[norm == 0] = 1.0
        gram_n = gram_q / norm[:, None] / norm[None, :]
        gram_n[np.diag_indices_from(gram_n)] += 1e-12
        try:
            r = cholesky(gram_n, lower=False)
        except np.linalg.LinAlgError:
            raise FitError("the fit did not converge: the parameters cannot be told apart by these tests "
                           "(a singular problem; fewer RC pairs or a coarser SOC grid may help)") from None
        d = solve_triangular(r, rhs_q / norm, trans="T")
        sol = lsq_linear(r, d, bounds=(self.lo * norm, self.hi * norm), method="trf", lsq_solver="exact",
                         tol=1e-12, max_iter=2000)
        if not np.all(np.isfinite(sol.x)):
            raise FitError(f"the fit did not converge: the linear solve gave non-finite values ({sol.message})")
        return basis @ (sol.x / norm)


def _initial_taus(pairs: int, lo: float, hi: float) -> np.ndarray:
    """Time constants spread over decades inside [lo, hi]."""
    guess = np.geomspace(10.0, 10.0 * 20.0 ** (pairs - 1), pairs) if pairs > 1 else np.array([30.0])
    return np.clip(guess, lo * 1.5, hi / 1.5)


def fit_group(traces: list[Trace], layout: Layout, max_evaluations: int = 400) -> LinearFit:
    """Fit these tests together; FitError if the optimiser does not converge."""
    from scipy.optimize import least_squares
    problem = _Problem(traces, layout)
    pairs = layout.rc_pairs
    theta = np.zeros(0)
    if layout.thetas():
        lo_b, hi_b, start = [], [], []
        if pairs:
            dt = np.concatenate([np.diff(t.test.time_s) for t in traces])
            lo = max(0.5 * float(np.median(dt)), 1e-3)
            hi = max(float(t.test.time_s[-1] - t.test.time_s[0]) for t in traces)
            if not hi > 4 * lo:
                raise FitError(f"the tests are too short ({hi:g} s) to fit an RC pair next to samples {2 * lo:g} s apart")
            lo_b += [np.log(lo)] * pairs
            hi_b += [np.log(hi)] * pairs
            start += list(np.log(_initial_taus(pairs, lo, hi)))
        if layout.arrhenius:
            k_lo, k_hi = (k / K_SCALE for k in K_BOUNDS_K)
            lo_b += [k_lo] * (1 + 2 * pairs)
            hi_b += [k_hi] * (1 + 2 * pairs)
            start += [K_START_K["r"] / K_SCALE] * (1 + pairs) + [K_START_K["tau"] / K_SCALE] * pairs
        res = least_squares(problem.residual, np.array(start), jac=problem.jacobian, bounds=(lo_b, hi_b),
                            method="trf", x_scale="jac", xtol=1e-10, ftol=1e-12, gtol=1e-10, max_nfev=max_evaluations)
        if res.status <= 0 or not np.all(np.isfinite(res.x)):
            raise FitError(f"the fit did not converge after {res.nfev} evaluations: {res.message} "
                           "(fewer RC pairs, a coarser SOC grid or more evaluations may help)")
        theta = res.x
    problem.evaluate(theta)
    p = problem.bounded()
    tau, r0_K, r_K, tau_K = problem.split(theta)
    order = np.argsort(tau)
    n, nr, nf = problem.n, problem.nr, problem.nf
    rc = p[nf:].reshape(pairs, layout.rc_columns()) if pairs else np.zeros((0, 1))
    return LinearFit(p[:n], p[n:nr], rc[order], tau[order], r0_K, r_K[order], tau_K[order], problem.evaluations,
                     p[nr:nf] if layout.ocv_dT else None)
