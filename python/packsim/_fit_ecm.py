"""The equivalent-circuit model packsim.fit adjusts to test data, and the least-squares
solve (SciPy). The model is the plant's (models/cell/ecm.hpp), at one temperature:

    v_term = OCV(soc) - i·R0(soc) - Σ v_k,   d v_k/dt = (i·R_k(soc) - v_k) / tau_k
    soc    = soc_0 - ∫ i dt / (3600·Q)        (positive current discharges)

For fixed time constants tau_k the terminal voltage is *linear* in everything else — the
OCV table's values, R0's table values or polynomial coefficients, the RC resistances —
because R_k(soc(t)) is a weighted sum of table values and the RC voltage is a linear
filter of i·R_k. So the fit is a variable projection: scipy.optimize.least_squares moves
log(tau_k) and, for every trial, scipy.optimize.lsq_linear finds the linear parameters
(resistances kept positive). Between samples the current is taken as the mean of its two
ends; every file starts with the cell at rest (all v_k = 0). The OCV table is fitted as
its first value and its rises from node to node, bounded below, so it increases strictly
with SOC as the loader requires.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._fit_data import CellTest, FitError

__all__ = ["Layout", "Trace", "LinearFit", "prepare", "fit_group", "soc_trace"]

SMOOTH_WEIGHT = 0.1   # second-difference penalty on table values (fills nodes without data)
R_MIN_OHM = 1e-7      # resistances stay positive (the loader requires > 0)
OCV_STEP_MIN_V = 1e-5  # the OCV table rises strictly with SOC (the loader requires it)


@dataclass(frozen=True)
class Layout:
    """What is fitted: the SOC grid of the tables, R0's form and the RC pairs."""
    soc_grid: np.ndarray
    form: str               # "table" (R0 over the SOC grid) or "poly" (R0 over discharged Ah)
    poly_order: int
    rc_pairs: int
    rc_over_soc: bool       # RC resistances as tables over the grid (else constants)
    capacity_Ah: float

    def r0_columns(self) -> int:
        return self.poly_order + 1 if self.form == "poly" else self.soc_grid.size

    def rc_columns(self) -> int:
        return self.soc_grid.size if self.rc_over_soc else 1


@dataclass
class Trace:
    """One test prepared for the model: SOC, interpolation weights, fixed columns."""
    test: CellTest
    soc: np.ndarray
    fixed: np.ndarray        # [samples, ocv + r0 columns]
    rc_input: np.ndarray     # [samples, rc columns]: i, or i·weights
    dt_s: np.ndarray


@dataclass
class LinearFit:
    """The solution: parameters, tau, and the model voltage of each test."""
    ocv_V: np.ndarray                # at the grid
    r0: np.ndarray                   # table values at the grid, or poly coefficients (highest first)
    rc_r_ohm: np.ndarray             # [pairs, rc columns]
    rc_tau_s: np.ndarray             # [pairs]
    model_V: list[np.ndarray]


def soc_trace(test: CellTest, soc0: float, capacity_Ah: float) -> np.ndarray:
    """Coulomb-counted SOC at every sample (trapezoidal charge)."""
    dq_Ah = 0.5 * (test.current_A[1:] + test.current_A[:-1]) * np.diff(test.time_s) / 3600.0
    return soc0 - np.concatenate(([0.0], np.cumsum(dq_Ah))) / capacity_Ah


def _weights(soc: np.ndarray, grid: np.ndarray) -> np.ndarray:
    s = np.clip(soc, grid[0], grid[-1])  # held flat beyond the grid, as the loader's tables
    j = np.clip(np.searchsorted(grid, s, side="right") - 1, 0, grid.size - 2)
    f = (s - grid[j]) / (grid[j + 1] - grid[j])
    w = np.zeros((soc.size, grid.size))
    rows = np.arange(soc.size)
    w[rows, j] = 1.0 - f
    w[rows, j + 1] += f
    return w


def prepare(test: CellTest, soc0: float, layout: Layout) -> Trace:
    soc = soc_trace(test, soc0, layout.capacity_Ah)
    w = _weights(soc, layout.soc_grid)
    i = test.current_A[:, None]
    if layout.form == "poly":
        x_Ah = (1.0 - soc) * layout.capacity_Ah
        r0_cols = -i * np.vander(x_Ah, layout.poly_order + 1)
    else:
        r0_cols = -i * w
    rc_input = i * w if layout.rc_over_soc else i.copy()
    # OCV columns: w @ _ocv_basis, i.e. for node j the weights of nodes j and above
    return Trace(test, soc, np.hstack([np.cumsum(w[:, ::-1], axis=1)[:, ::-1], r0_cols]), rc_input, np.diff(test.time_s))


def _ocv_basis(n: int) -> np.ndarray:
    """OCV values = basis @ (OCV at the first node, then the rise to each next node): the
    rises are bounded below, so the fitted OCV increases strictly with SOC."""
    return np.tril(np.ones((n, n)))


def _rc_filter(x: np.ndarray, time_s: np.ndarray, tau_s: float) -> np.ndarray:
    """Exact response of d u/dt = (x - u)/tau from u = 0, x held at the mean of the
    samples on each side of a step, for any sampling. With a_k = exp(-dt_k/tau) the step
    is u[k+1] = a_k·u[k] + (1 - a_k)·x̄_k; scaled by exp(t/tau) it becomes a running sum,
    taken in chunks of at most 50 tau so that the scale never overflows."""
    beta = -np.expm1(-np.diff(time_s) / tau_s)[:, None] * (0.5 * (x[1:] + x[:-1]))
    s = (time_s - time_s[0]) / tau_s
    u = np.zeros_like(x)
    start, n = 0, time_s.size
    while start < n - 1:
        end = min(max(int(np.searchsorted(s, s[start] + 50.0, side="right")) - 1, start + 1), n - 1)
        if end == start + 1:
            u[end] = np.exp(s[start] - s[end]) * u[start] + beta[start]
        else:
            ss = s[start + 1:end + 1] - s[start]
            acc = np.cumsum(np.exp(ss)[:, None] * beta[start:end], axis=0)
            u[start + 1:end + 1] = np.exp(-ss)[:, None] * (u[start] + acc)
        start = end
    return u


def _smoothing(layout: Layout, i_scale_A: float) -> tuple[np.ndarray, int]:
    """Second-difference rows on every table block (OCV, R0 table, RC tables)."""
    n = layout.soc_grid.size
    d2 = np.zeros((max(n - 2, 0), n))
    for k in range(n - 2):
        d2[k, k:k + 3] = (1.0, -2.0, 1.0)
    blocks = [(0, SMOOTH_WEIGHT)]
    if layout.form == "table":
        blocks.append((n, SMOOTH_WEIGHT * i_scale_A))
    start = n + layout.r0_columns()
    if layout.rc_over_soc:
        blocks += [(start + p * n, SMOOTH_WEIGHT * i_scale_A) for p in range(layout.rc_pairs)]
    cols = start + layout.rc_pairs * layout.rc_columns()
    rows = np.zeros((d2.shape[0] * len(blocks), cols))
    for b, (c0, weight) in enumerate(blocks):
        rows[b * d2.shape[0]:(b + 1) * d2.shape[0], c0:c0 + n] = weight * (d2 @ _ocv_basis(n) if b == 0 else d2)
    return rows, cols


def _bounds(layout: Layout, cols: int) -> tuple[np.ndarray, np.ndarray]:
    n = layout.soc_grid.size
    lo = np.full(cols, R_MIN_OHM)
    hi = np.full(cols, np.inf)
    lo[0], hi[0] = 0.1, 10.0                        # OCV at the first node (the loader wants > 0)
    lo[1:n] = OCV_STEP_MIN_V                        # its rise to each next node
    if layout.form == "poly":
        lo[n:n + layout.r0_columns()] = -np.inf     # polynomial coefficients: any sign
    return lo, hi


class _Problem:
    """The linear least-squares problem for given time constants."""

    def __init__(self, traces: list[Trace], layout: Layout) -> None:
        self.traces = traces
        self.layout = layout
        i_scale = max(float(np.max(np.abs(t.test.current_A))) for t in traces)
        self.smooth, self.cols = _smoothing(layout, i_scale)
        self.lo, self.hi = _bounds(layout, self.cols)
        self.measured = np.concatenate([t.test.voltage_V for t in traces])

    def matrix(self, tau_s: np.ndarray) -> np.ndarray:
        blocks = []
        for t in self.traces:
            rc = [-_rc_filter(t.rc_input, t.test.time_s, tau) for tau in tau_s]
            blocks.append(np.hstack([t.fixed] + rc))
        return np.vstack(blocks + [self.smooth])

    def solve(self, tau_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(parameters, a residual vector whose sum of squares is the misfit). The tall
        problem is reduced through its Gram matrix (Cholesky factor R) to a square one,
        ||A p - b||² = ||R p - d||² + (bᵀb - dᵀd), so the bounded solve is small. The
        sums run in einsum's own loops, not a threaded BLAS: the same data give
        bit-identical parameters on any machine load."""
        from scipy.linalg import cholesky, solve_triangular
        from scipy.optimize import lsq_linear
        a = self.matrix(tau_s)
        b = np.concatenate([self.measured, np.zeros(self.smooth.shape[0])])
        norm = np.sqrt(np.einsum("ki,ki->i", a, a))
        norm[norm == 0] = 1.0
        a /= norm
        gram = np.einsum("ki,kj->ij", a, a)
        gram[np.diag_indices_from(gram)] += 1e-12 * np.trace(gram) / gram.shape[0]
        try:
            r = cholesky(gram, lower=False)
        except np.linalg.LinAlgError:
            raise FitError("the fit did not converge: the parameters cannot be told apart by these tests "
                           "(a singular problem; fewer RC pairs or a coarser SOC grid may help)") from None
        d = solve_triangular(r, np.einsum("ki,k->i", a, b), trans="T")
        unreachable = float(np.sqrt(max(float(np.einsum("k,k->", b, b)) - float(np.einsum("i,i->", d, d)), 0.0)))
        sol = lsq_linear(r, d, bounds=(self.lo * norm, self.hi * norm), method="trf", lsq_solver="exact",
                         tol=1e-12, max_iter=2000)
        if not np.all(np.isfinite(sol.x)):
            raise FitError(f"the fit did not converge: the linear solve gave non-finite values ({sol.message})")
        return sol.x / norm, np.append(r @ sol.x - d, unreachable)


def _initial_taus(pairs: int, lo: float, hi: float) -> np.ndarray:
    """Time constants spread over decades inside [lo, hi]."""
    guess = np.geomspace(10.0, 10.0 * 20.0 ** (pairs - 1), pairs) if pairs > 1 else np.array([30.0])
    return np.clip(guess, lo * 1.5, hi / 1.5)


def fit_group(traces: list[Trace], layout: Layout, max_evaluations: int = 400) -> LinearFit:
    """Fit one temperature's tests; FitError if the optimiser does not converge."""
    from scipy.optimize import least_squares
    problem = _Problem(traces, layout)
    tau = np.zeros(0)
    if layout.rc_pairs:
        dt = np.concatenate([t.dt_s for t in traces])
        lo = max(0.5 * float(np.median(dt)), 1e-3)
        hi = max(float(t.test.time_s[-1] - t.test.time_s[0]) for t in traces)
        if not hi > 4 * lo:
            raise FitError(f"the tests are too short ({hi:g} s) to fit an RC pair next to samples {2 * lo:g} s apart")
        res = least_squares(lambda th: problem.solve(np.exp(th))[1], np.log(_initial_taus(layout.rc_pairs, lo, hi)),
                            bounds=(np.log(lo), np.log(hi)), method="trf", x_scale=1.0, diff_step=1e-4,
                            xtol=1e-10, ftol=1e-12, max_nfev=max_evaluations)
        if res.status <= 0 or not np.all(np.isfinite(res.x)):
            raise FitError(f"the fit did not converge after {res.nfev} evaluations: {res.message} "
                           "(fewer RC pairs, a coarser SOC grid or more evaluations may help)")
        tau = np.exp(res.x)
    p, _ = problem.solve(tau)
    order = np.argsort(tau)
    n = layout.soc_grid.size
    r0_end = n + layout.r0_columns()
    rc = p[r0_end:].reshape(layout.rc_pairs, layout.rc_columns()) if layout.rc_pairs else np.zeros((0, 1))
    model = []
    for t in traces:
        a = np.hstack([t.fixed] + [-_rc_filter(t.rc_input, t.test.time_s, x) for x in tau])
        model.append(a @ p)
    return LinearFit(_ocv_basis(n) @ p[:n], p[n:r0_end], rc[order], tau[order], model)
