"""From a cell's test data to a cell preset: ``packsim.fit`` (and ``packsim fit``).

    import packsim
    f = packsim.fit(["hppc_25C.csv", "cc_1C_25C.csv"], rc_pairs=2)
    f.files[0].rms_mV              # voltage error per test
    f.r0_ohm(0.5)                  # the fitted R0 at SOC 0.5 (first temperature)
    f.save("cells/my_cell.yaml")   # then `cell: {preset: my_cell}` in a scenario
    f.plot("fit.png")              # measured vs model, and the residual

Tests are CSV files or pandas DataFrames with ``time_s, current_A, voltage_V[, temp_C]``
(positive current discharges), each starting with the cell at rest at ``initial_soc``.
Tests at several temperatures (temp_C at their start more than 3 °C apart) are fitted one
temperature at a time and written as 2-D tables over SOC × temperature. See docs/fit.md.
"""
from __future__ import annotations

import os
import tempfile
import warnings
from dataclasses import replace
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._atomic import replaced_when_done
from ._fit_data import REST_REL_CURRENT as REST_REL
from ._fit_data import FitError, FitWarning, read_test, rest_mask
from ._fit_ecm import REF_TEMP_C, SMOOTH_WEIGHT, Layout, fit_group, held_current, prepare, soc_trace
from ._fit_preset import preset_yaml

__all__ = ["fit", "from_bpx", "from_pybamm", "FitResult", "FitAtTemperature", "FileFit", "FitError", "FitWarning", "FORMS", "TEMPERATURE_LAWS", "parse_soc_grid",
           "arrhenius_factor"]

FORMS = ("table", "poly")
TEMPERATURE_LAWS = ("arrhenius", "table")
LOW_SOC = 0.1   # the band reported on its own: where a cell's OCV and resistance bend most
# Smoothness weights tried when held-out tests are given: the one with the lowest error on them is kept.
SMOOTHING_CANDIDATES = (0.001, 0.01, 0.1, 1.0, 10.0)
TEMP_GROUP_C = 3.0       # tests whose temperatures are closer share one fit
SOC_MARGIN = 0.05        # counted SOC may leave 0..1 by this much (a CV top-up, an over-discharge)
# Denser near empty, where a cell's OCV and resistance bend most.
DEFAULT_SOC_GRID = np.concatenate(([0.0, 0.01, 0.02, 0.035, 0.05, 0.075], np.linspace(0.1, 1.0, 19)))


@dataclass
class FileFit:
    """One test: how well the fitted model reproduces it."""
    name: str
    temp_C: float | None
    samples: int
    rms_mV: float
    max_mV: float
    time_s: np.ndarray = field(repr=False)
    current_A: np.ndarray = field(repr=False)
    voltage_V: np.ndarray = field(repr=False)
    model_V: np.ndarray = field(repr=False)
    soc: np.ndarray = field(repr=False)
    low_soc_rms_mV: float | None = None   # RMS over the samples below 10 % SOC (None: none there)
    reader: str = ""                      # a cycler export: its format, sign and units as read

    def rms_over_time_mV(self, below_soc: float | None = None) -> float | None:
        """RMS of the voltage error over time, each sample weighted by the time it stands
        for (half of each interval beside it): for files logged unevenly (a cycler logging
        on change, a decimated record) the figure of the evenly sampled test; rms_mV weighs
        every sample alike. below_soc: over the samples below that SOC only (None: none there)."""
        t = self.time_s
        w = np.zeros(t.size)
        if t.size > 1:
            half = 0.5 * np.diff(t)
            w[:-1] += half
            w[1:] += half
        else:
            w[:] = 1.0
        if below_soc is not None:
            w = np.where(self.soc < below_soc, w, 0.0)
            if not np.any(w > 0):
                return None
        err_V = self.model_V - self.voltage_V
        return 1e3 * float(np.sqrt(np.sum(w * err_V ** 2) / np.sum(w)))


@dataclass
class FitAtTemperature:
    """The parameters fitted at one temperature (None: the tests had no temp_C); with the
    arrhenius law, at its reference 25 °C with the Arrhenius constants (K) of each."""
    temp_C: float | None
    ocv_V: np.ndarray        # at FitResult.soc_grid
    r0: np.ndarray           # table values at the grid, or polynomial coefficients (highest first)
    rc_r_ohm: np.ndarray     # [pairs, grid] or [pairs, 1]
    rc_tau_s: np.ndarray     # [pairs]
    r0_K: float = 0.0        # R(T)/R(25 °C) = exp(K·(1/T_K - 1/298.15)); 0: no temperature law
    rc_r_K: np.ndarray | None = None   # [pairs]
    rc_tau_K: np.ndarray | None = None  # [pairs]
    docv_dT_V_per_K: np.ndarray | None = None  # at the grid: OCV(soc,T) = ocv_V + (T - 25 °C)·this; None: none


@dataclass
class FitResult:
    """What packsim.fit returns: parameters, per-test errors and the preset's YAML text."""
    capacity_Ah: float
    soc_grid: np.ndarray
    form: str
    rc_pairs: int
    temperatures: list[FitAtTemperature]
    files: list[FileFit]
    v_min_V: float
    v_max_V: float
    capacity_source: str = "given"   # or how it was measured
    temperature_law: str = "none"    # none, table (a fit per temperature) or arrhenius (one joint fit)
    evaluations: int = 0             # model evaluations the optimiser used
    warnings: list[str] = field(default_factory=list)  # what the data could not determine
    smoothing: float = SMOOTH_WEIGHT  # weight of the second-difference penalty on the tables
    validation: list[FileFit] = field(default_factory=list)  # held-out tests: the preset's error on them
    smoothing_scores: list[tuple[float, float]] = field(default_factory=list)  # (weight, held-out RMS mV) tried; NaN: no valid cell
    ocv_temps_C: tuple[float, float] | None = None  # with an OCV temperature coefficient: the rows of the
                                                    # preset's 2-D OCV (the training samples' coldest, hottest)

    @property
    def yaml(self) -> str:
        """The cell preset (scenarios/cells format)."""
        return preset_yaml(self)

    @property
    def params(self) -> dict[str, Any]:
        """The parameters as plain values, per temperature."""
        return {"capacity_Ah": self.capacity_Ah, "soc_grid": self.soc_grid.tolist(), "form": self.form,
                "temperatures": [{"temp_C": g.temp_C, "ocv_V": g.ocv_V.tolist(),
                                  ("r0_poly" if self.form == "poly" else "r0_ohm"): g.r0.tolist(),
                                  "rc_r_ohm": g.rc_r_ohm.tolist(), "rc_tau_s": g.rc_tau_s.tolist(),
                                  **({"arrhenius_K": {"r0": g.r0_K, "rc_r": g.rc_r_K.tolist(),
                                                      "rc_tau": g.rc_tau_K.tolist()}, "ref_temp_C": REF_TEMP_C}
                                     if self.temperature_law == "arrhenius" else {}),
                                  **({"docv_dT_V_per_K": g.docv_dT_V_per_K.tolist()}
                                     if g.docv_dT_V_per_K is not None else {})}
                                 for g in self.temperatures]}

    def r0_ohm(self, soc: Any, temperature: int = 0, temp_C: float | None = None) -> np.ndarray:
        """Fitted R0 at the given SOC(s), at the index-th temperature (with the arrhenius law:
        at temp_C, default 25 °C)."""
        g = self.temperatures[temperature]
        soc = np.asarray(soc, dtype=float)
        r = np.polyval(g.r0, (1.0 - soc) * self.capacity_Ah) if self.form == "poly" else np.interp(soc, self.soc_grid, g.r0)
        return r * arrhenius_factor(g.r0_K, temp_C)

    def ocv_V(self, soc: Any, temperature: int = 0, temp_C: float | None = None) -> np.ndarray:
        """Fitted OCV at the given SOC(s); with a temperature coefficient at temp_C (default
        25 °C), held at the preset's coldest / hottest row beyond them as the preset is."""
        g = self.temperatures[temperature]
        soc = np.asarray(soc, dtype=float)
        v = np.interp(soc, self.soc_grid, g.ocv_V)
        if g.docv_dT_V_per_K is None or temp_C is None:
            return v
        t = float(np.clip(temp_C, *self.ocv_temps_C)) if self.ocv_temps_C else float(temp_C)
        return v + (t - REF_TEMP_C) * np.interp(soc, self.soc_grid, g.docv_dT_V_per_K)

    def docv_dT_V_per_K(self, soc: Any, temperature: int = 0) -> np.ndarray | None:
        """The fitted OCV temperature coefficient at the given SOC(s), V/K (None: not fitted)."""
        d = self.temperatures[temperature].docv_dT_V_per_K
        return None if d is None else np.interp(np.asarray(soc, dtype=float), self.soc_grid, d)

    def save(self, path: str | os.PathLike) -> None:
        """Write the preset; a temporary file renamed when complete (no partial file)."""
        _write_atomic(os.fspath(path), self.yaml.encode())

    def plot(self, path: str | os.PathLike | None = None, dpi: int = 110):
        """Measured vs model voltage and the residual per test; written as PNG if a path is given."""
        from ._fit_report import report_figure
        fig = report_figure(self)
        if path is not None:
            if not os.path.isdir(os.path.dirname(os.path.abspath(os.fspath(path)))):
                raise FitError(f"{os.fspath(path)}: no such folder")
            with tempfile.TemporaryDirectory(dir=os.path.dirname(os.path.abspath(os.fspath(path)))) as d:
                tmp = os.path.join(d, "report.png")
                fig.savefig(tmp, dpi=dpi)
                os.replace(tmp, os.fspath(path))
        return fig

    def bpx(self, title: str = "packsim fit") -> dict:
        """The cell as a BPX document (a JSON-ready dict): the equivalent circuit in its
        User-defined section (docs/fit.md). Needs the bpx package, which validates it."""
        from ._fit_interchange import to_bpx
        return to_bpx(self, title)

    def save_bpx(self, path: str | os.PathLike, title: str = "packsim fit") -> None:
        """Write the BPX document as JSON (a temporary file renamed when complete)."""
        import json
        _write_atomic(os.fspath(path), (json.dumps(self.bpx(title), indent=1) + "\n").encode())

    def pybamm_parameters(self, thermal: dict | None = None):
        """pybamm.ParameterValues for PyBaMM's Thevenin model
        (pybamm.equivalent_circuit.Thevenin(options={"number of rc elements": rc_pairs})).
        Needs PyBaMM."""
        from ._fit_interchange import to_pybamm
        return to_pybamm(self, thermal)

    def summary(self) -> str:
        """The fit report as text, one line per test."""
        lines = [f"capacity {self.capacity_Ah:.4g} Ah ({self.capacity_source}), {self.rc_pairs} RC pair(s), "
                 f"R0 form {self.form}"]
        for g in self.temperatures:
            at = "" if g.temp_C is None else f" at {g.temp_C:.1f} °C"
            taus = ", ".join(f"{t:.4g}" for t in g.rc_tau_s)
            lines.append(f"  tau_s{at}: [{taus}]")
            if self.temperature_law == "arrhenius":
                lines.append(f"  Arrhenius K (ref {REF_TEMP_C:g} °C): R0 {g.r0_K:.0f} K, RC R "
                             f"[{', '.join(f'{k:.0f}' for k in g.rc_r_K)}] K, tau [{', '.join(f'{k:.0f}' for k in g.rc_tau_K)}] K")
        lines += [_file_line(f) for f in self.files]
        if self.validation:
            lines.append("  held out (not fitted):")
            lines += ["  " + _file_line(f) for f in self.validation]
        if self.smoothing_scores:
            tried = ", ".join(f"{w:g}: {rms:.2f} mV" if np.isfinite(rms) else f"{w:g}: no valid cell"
                              for w, rms in self.smoothing_scores)
            lines.append(f"  smoothing {self.smoothing:g}, the lowest held-out RMS of those tried ({tried})")
        return "\n".join(lines)


def _file_line(f: FileFit) -> str:
    low = "" if f.low_soc_rms_mV is None else f", below 10 % SOC RMS {f.low_soc_rms_mV:.2f} mV"
    read = f"\n    {f.reader}" if f.reader else ""
    return f"  {f.name}: {f.samples} samples, RMS {f.rms_mV:.2f} mV, max {f.max_mV:.2f} mV{low}{read}"


def arrhenius_factor(k: float, temp_C: float | None) -> float:
    """exp(K·(1/T_K - 1/T_ref,K)), T_ref = 25 °C: the plant's factor (models/cell/curve.hpp)."""
    if temp_C is None or k == 0.0:
        return 1.0
    return float(np.exp(k * (1.0 / (temp_C + 273.15) - 1.0 / (REF_TEMP_C + 273.15))))


def _write_atomic(path: str, data: bytes) -> None:
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise FitError(f"{path}: no such folder {folder}")
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".packsim-fit-", suffix=".tmp")
    with replaced_when_done(path, tmp), os.fdopen(fd, "wb") as f:
        f.write(data)


def parse_soc_grid(spec: Any) -> np.ndarray:
    """A SOC grid from a list, an array, or text ``"0:0.05:1"`` (start:step:stop) or ``"0,0.2,0.5,1"``."""
    if isinstance(spec, str):
        try:
            if ":" in spec:
                start, step, stop = (float(p) for p in spec.split(":"))
                if not step > 0:
                    raise FitError(f"soc_grid '{spec}': the step must be > 0")
                grid = np.arange(start, stop + step / 2, step)
            else:
                grid = np.array([float(p) for p in spec.split(",")])
        except ValueError:
            raise FitError(f"soc_grid '{spec}': expected start:step:stop or comma-separated values") from None
    else:
        grid = np.asarray(spec, dtype=float).ravel()
    if grid.size < 2 or not np.all(np.isfinite(grid)) or np.any(np.diff(grid) <= 0):
        raise FitError(f"soc_grid: needs at least 2 strictly increasing values, got {grid.tolist()}")
    if grid[0] < -0.5 or grid[-1] > 1.5:
        raise FitError(f"soc_grid: values must lie in [-0.5, 1.5], got {grid[0]:g} .. {grid[-1]:g}")
    return grid


def _per_file(name: str, value: Any, n: int, lo: float, hi: float) -> list[float | None]:
    values = list(value) if isinstance(value, Sequence) and not isinstance(value, str) else [value] * n
    if len(values) != n:
        raise FitError(f"{name}: {len(values)} values for {n} tests")
    for v in values:
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float)) or not lo <= v <= hi):
            raise FitError(f"{name}: {v!r} is not a number in [{lo:g}, {hi:g}]")
    return [None if v is None else float(v) for v in values]


def _check_poly_positive(coefficients: np.ndarray, capacity_Ah: float) -> None:
    """A resistance polynomial must stay positive from full to empty (the loader checks it)."""
    x_Ah = np.linspace(0.0, capacity_Ah, 501)
    r = np.polyval(coefficients, x_Ah)
    if np.min(r) <= 0:
        k = int(np.argmin(r))
        raise FitError(f"the fitted R0 polynomial is not positive over 0..{capacity_Ah:.4g} Ah ({r[k]:.4g} ohm at "
                       f"{x_Ah[k]:.3g} Ah): the tests do not cover that range; use form table or a lower poly_order")


MAX_CELL_CAPACITY_AH = 2000.0   # no single cell holds more: beyond, the current's unit is wrong
MAX_C_RATE = 100.0              # |current| / capacity beyond which a unit is wrong
MIN_PEAK_C_RATE = 0.01          # a test whose largest current is below C/100: likewise


def _check_measured_capacity(test, capacity_Ah: float) -> None:
    if capacity_Ah > MAX_CELL_CAPACITY_AH:
        raise FitError(f"{test.name}: column '{test.current_column}' (read as current_A) removes {capacity_Ah:,.0f} Ah, "
                       f"more than any single cell holds (> {MAX_CELL_CAPACITY_AH:,.0f} Ah): a current logged in mA "
                       "read as A? Convert the column to A, or give --capacity-Ah")


def _check_c_rate(tests, capacity_Ah: float, given: bool) -> None:
    """The current against the capacity: a thousand times off is a unit error."""
    for t in tests:
        peak_A = float(np.max(np.abs(t.current_A)))
        k = int(np.argmax(np.abs(t.current_A)))
        c_rate = peak_A / capacity_Ah
        source = "the given capacity_Ah" if given else "the measured capacity"
        if c_rate > MAX_C_RATE:
            raise FitError(f"{t.rows[k]}: column '{t.current_column}' (read as current_A) reaches {peak_A:.4g} A, "
                           f"{c_rate:,.0f} C of {source} {capacity_Ah:.4g} Ah (at most {MAX_C_RATE:g} C is "
                           "plausible): is the current in mA, or the capacity in mAh?")
        if peak_A > 0 and c_rate < MIN_PEAK_C_RATE and given:
            raise FitError(f"{t.rows[k]}: column '{t.current_column}' (read as current_A) peaks at {peak_A:.4g} A, "
                           f"{c_rate:.2g} C of the given capacity_Ah {capacity_Ah:.4g} Ah: is capacity_Ah in mAh, "
                           "or the current in kA?")


def _is_full_discharge(test) -> bool:
    """One uninterrupted discharge removes at least half of the test's charge and ends at
    the test's lowest voltage (a discharge to the cut-off)."""
    i = test.current_A
    peak = float(np.max(np.abs(i)))
    on = i > REST_REL * peak
    if not on.any():
        return False
    u = held_current(i, test.steps_on_samples)
    dq = u[:-1] * np.diff(test.time_s)
    removed = float(np.max(np.cumsum(dq))) if dq.size else 0.0
    best_q, best_end = 0.0, 0
    k, n = 0, i.size
    while k < n:
        if not on[k]:
            k += 1
            continue
        end = k
        while end + 1 < n and on[end + 1]:
            end += 1
        q = float(np.sum(dq[k:end]))
        if q > best_q:
            best_q, best_end = q, end
        k = end + 1
    v_min = float(np.min(test.voltage_V))
    return removed > 0 and best_q >= 0.5 * removed and test.voltage_V[best_end] <= v_min + 0.02 * abs(v_min)


def _check_soc_range(test, soc: np.ndarray) -> None:
    """Coulomb counting must stay near 0..1: beyond, the sign of the current, the initial
    SOC or the capacity is wrong."""
    for bad, what in ((soc > 1.0 + SOC_MARGIN, "above 1"), (soc < -SOC_MARGIN, "below 0")):
        if bad.any():
            k = int(np.argmax(bad))
            raise FitError(f"{test.rows[k]}: the SOC counted from the current reaches {soc[k]:.3f}, {what}: "
                           "positive current discharges (discharge logged negative: invert_current / "
                           "--invert-current); check initial_soc and capacity_Ah")


def _group_by_temperature(temps: list[float | None]) -> list[list[int]]:
    """Indices of tests sharing one temperature, coldest first."""
    if all(t is None for t in temps):
        return [list(range(len(temps)))]
    if any(t is None for t in temps):
        missing = [k for k, t in enumerate(temps) if t is None]
        raise FitError(f"test {missing[0] + 1} has no temperature (no temp_C column, no temps_C) while others "
                       "have one: give every test a temperature or none")
    order = sorted(range(len(temps)), key=lambda k: temps[k])
    groups = [[order[0]]]
    for k in order[1:]:
        if temps[k] - temps[groups[-1][-1]] > TEMP_GROUP_C:
            groups.append([])
        groups[-1].append(k)
    return groups


def fit(data: Any, *, capacity_Ah: float | None = None, rc_pairs: int = 2, soc_grid: Any = None,
        form: str = "table", poly_order: int = 5, rc_over_soc: bool = False, initial_soc: Any = 1.0,
        temps_C: Any = None, columns: dict[str, str] | None = None, invert_current: bool = False,
        max_evaluations: int = 400, temperature_law: str = "arrhenius", validate: Any = None,
        validate_initial_soc: Any = 1.0, smoothing: float | None = None,
        ocv_temperature: bool | None = None, steps_on_samples: bool = False) -> FitResult:
    """Fit a cell preset to test data.

    data:          a CSV path or pandas DataFrame, or a list of them
    capacity_Ah:   given, or None: measured as the most charge any one test removes, divided
                   by its initial_soc (give a full constant-current discharge to the cut-off;
                   without one a FitWarning says the capacity is likely low)
    rc_pairs:      number of RC pairs (0..4, default 2); constant R and tau unless rc_over_soc
    soc_grid:      SOC nodes of the OCV/R0 tables, a list or "start:step:stop" (default: every
                   0.05, and 0.01, 0.02, 0.035, 0.075 too: denser near empty)
    form:          "table" (R0 over the SOC grid) or "poly" (R0 a polynomial of poly_order over
                   discharged Ah, the form of a hand-fitted Rint; one temperature only)
    initial_soc:   SOC at the start of each test (one value or one per test; default 1 = full)
    temps_C:       temperature of each test (default: its first temp_C value)
    columns:       our column -> the name in the data, e.g. {"voltage_V": "Voltage(V)"}
    invert_current: the data logs discharge as negative current
    max_evaluations: model evaluations the optimiser may use (per fit) before the fit counts
                   as not converged
    temperature_law: tests more than 3 °C apart: "arrhenius" (default) fits them jointly,
                   every sample at its measured temp_C, with R0, the RC resistances and the
                   time constants as Arrhenius laws around 25 °C and one OCV (one test with
                   rests is enough); "table" fits each temperature on its own (each needs a
                   rest) and writes 2-D tables over SOC × temp_C
    ocv_temperature: the OCV's temperature coefficient dOCV/dT over SOC in a joint fit:
                   None (default) fits it when rests lie at temperatures more than 3 °C
                   apart (only a rest tells the OCV at a temperature), True requires it,
                   False leaves it out (one OCV for every temperature)
    steps_on_samples: the data log each current step at the sample it happens at, that
                   sample reading the new current (packsim's own result files; a cycler that
                   logs every step's start): each sample's current is held over the interval
                   after it. Default False: the mean of each interval's two ends, right for
                   steps at random points between samples; on data with steps on the samples
                   it biases R0 low by about Σ_j R_j·(1 - exp(-Δt/τ_j))/2 (docs/fit.md)

    Raises FitError (a ValueError) naming the file and line, or the reason.
    """
    tests_in = list(data) if isinstance(data, (list, tuple)) else [data]
    if not tests_in:
        raise FitError("no test data given")
    if form not in FORMS:
        raise FitError(f"form '{form}' is not one of {', '.join(FORMS)}")
    for name, v, lo, hi in (("rc_pairs", rc_pairs, 0, 4), ("poly_order", poly_order, 0, 9),
                            ("max_evaluations", max_evaluations, 1, 100000)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not lo <= v <= hi:
            raise FitError(f"{name}: {v!r} is not an integer in [{lo}, {hi}]")
    if capacity_Ah is not None and (isinstance(capacity_Ah, bool) or not isinstance(capacity_Ah, (int, float))
                                    or not 0 < capacity_Ah < 1e5):
        raise FitError(f"capacity_Ah: {capacity_Ah!r} is not a number in (0, 1e5)")
    grid = DEFAULT_SOC_GRID if soc_grid is None else parse_soc_grid(soc_grid)
    if not isinstance(steps_on_samples, (bool, np.bool_)):
        raise FitError(f"steps_on_samples: {steps_on_samples!r} is not True or False")
    tests = [read_test(src, k, columns, invert_current) for k, src in enumerate(tests_in)]
    for t in tests:
        t.steps_on_samples = steps_on_samples
    socs0 = _per_file("initial_soc", initial_soc, len(tests), 0.0, 1.0)
    if any(s is None for s in socs0):
        raise FitError("initial_soc: every test needs a starting SOC")
    given_temps = _per_file("temps_C", temps_C, len(tests), -60.0, 150.0)
    temps = [g if g is not None else t.start_temp_C for g, t in zip(given_temps, tests)]

    capacity_source = "given"
    fit_warnings: list[str] = []
    if capacity_Ah is None:
        # a test from initial_soc s to empty removes s·Q
        removed_Ah = [float(np.max(1.0 - soc_trace(t, 1.0, 1.0))) for t in tests]
        per_soc = [q / max(s0, 1e-9) for q, s0 in zip(removed_Ah, socs0)]
        best = int(np.argmax(per_soc))
        capacity_Ah = per_soc[best]
        capacity_source = f"measured: the most charge one test removed, {tests[best].name}"
        if socs0[best] != 1.0:  # the capacity is not the charge removed: say both
            capacity_source = (f"measured: the most charge one test removed over its initial SOC, {tests[best].name}: "
                               f"{removed_Ah[best]:.4g} Ah from SOC {socs0[best]:g}")
        if not capacity_Ah > 0:
            raise FitError("no test discharges the cell: give capacity_Ah (or a full constant-current discharge)")
        _check_measured_capacity(tests[best], capacity_Ah)
        if not _is_full_discharge(tests[best]):
            fit_warnings.append(
                f"the capacity {capacity_Ah:.4g} Ah is from the charge {tests[best].name} removed"
                + (f" ({removed_Ah[best]:.4g} Ah from its initial SOC {socs0[best]:g})" if socs0[best] != 1.0 else "")
                + ", but no test is a full "
                "discharge to the cut-off (one uninterrupted discharge removing most of the charge and ending at "
                "the test's lowest voltage; an HPPC stops short of empty), so it is likely too low: give "
                "--capacity-Ah / capacity_Ah, or add a full constant-current discharge")
    _check_c_rate(tests, float(capacity_Ah), capacity_source == "given")
    layout = Layout(grid, form, int(poly_order), int(rc_pairs), bool(rc_over_soc), float(capacity_Ah))
    for t, s0 in zip(tests, socs0):
        _check_soc_range(t, soc_trace(t, s0, layout.capacity_Ah))

    law = _temperature_law(temperature_law, temps)
    groups = [list(range(len(tests)))] if law == "arrhenius" else _group_by_temperature(temps)
    if form == "poly" and len(groups) > 1:
        raise FitError("form poly fits one temperature; the tests span "
                       f"{min(temps):.1f} to {max(temps):.1f} °C (use form table for 2-D tables, or "
                       "temperature_law arrhenius)")
    if law == "arrhenius":
        layout = replace(layout, arrhenius=True)
    sample_temps = [_sample_temps(t, g) for t, g in zip(tests, given_temps)]
    ocv_temps = _ocv_temperature(ocv_temperature, law, tests, sample_temps)
    if ocv_temps is not None:
        layout = replace(layout, ocv_dT=True, dT_scale_K=max(ocv_temps[1] - ocv_temps[0], 1.0))
    held_out = [read_test(src, len(tests) + k, columns, invert_current) for k, src in enumerate(validate or [])]
    for t in held_out:
        t.steps_on_samples = steps_on_samples
    held_socs0 = _per_file("validate_initial_soc", validate_initial_soc, len(held_out), 0.0, 1.0)
    for t, s0 in zip(held_out, held_socs0):
        _check_soc_range(t, soc_trace(t, s0, layout.capacity_Ah))
    if law != "none" and any(t.temp_C is None for t in held_out):
        raise FitError(f"{next(t.name for t in held_out if t.temp_C is None)}: no temp_C column, while the fit is "
                       "over temperature: a held-out test needs its temperature")
    held_temps = [_model_temps(law, t.start_temp_C, t.temp_C, t) for t in held_out]
    if smoothing is None:
        weights = SMOOTHING_CANDIDATES if held_out else (SMOOTH_WEIGHT,)
    else:
        if isinstance(smoothing, bool) or not isinstance(smoothing, (int, float)) or not 0 <= smoothing <= 1e3:
            raise FitError(f"smoothing: {smoothing!r} is not a number in [0, 1000]")
        weights = (float(smoothing),)
    v_all = np.concatenate([t.voltage_V for t in tests])
    v_min = float(np.clip(np.min(v_all), 0.5, 4.9))
    v_max = float(np.clip(np.max(v_all), v_min + 0.05, 5.0))
    best: FitResult | None = None
    best_score = np.inf
    scores: list[tuple[float, float]] = []
    failed: FitError | None = None
    for weight in weights:
        try:
            result = _fit_with_smoothing(weight, layout, tests, groups, socs0, temps, sample_temps, law,
                                         int(max_evaluations), ocv_temperature, ocv_temps, list(fit_warnings),
                                         (float(capacity_Ah), grid, form, int(rc_pairs), v_min, v_max, capacity_source))
            result.validation = _file_errors(result, held_out, held_socs0, held_temps)
        except FitError as e:
            if len(weights) == 1:
                raise
            # a weight too light for the data (a table left free where no test reaches): one
            # candidate fewer, not a failed fit
            failed = e
            scores.append((weight, float("nan")))
            continue
        score = _pooled_rms_mV(result.validation) if held_out else 0.0
        scores.append((weight, score))
        if best is None or score < best_score:
            best, best_score = result, score
    if best is None:
        assert failed is not None
        raise FitError(f"no smoothing weight tried gives a valid fit ({', '.join(f'{w:g}' for w in weights)}); "
                       f"the last: {failed}")
    best.smoothing_scores = scores if held_out and len(weights) > 1 else []
    for w in best.warnings:   # the data's, and what the kept fit left out
        warnings.warn(w, FitWarning, stacklevel=2)
    best.files = _file_errors(best, tests, socs0, [_model_temps(law, temps[k], sample_temps[k], tests[k])
                                                   for k in range(len(tests))])
    return best


def _fit_with_smoothing(weight: float, layout: Layout, tests, groups, socs0, temps, sample_temps, law: str,
                        max_evaluations: int, ocv_temperature, ocv_temps, fit_warnings: list[str],
                        common: tuple) -> FitResult:
    """The fit with one weight of the tables' second-difference penalty."""
    capacity_Ah, grid, form, rc_pairs, v_min, v_max, capacity_source = common
    lay = replace(layout, smooth_weight=weight)
    fitted, evaluations = _fit_groups(tests, groups, socs0, temps, sample_temps, lay, law, int(max_evaluations))
    if lay.ocv_dT and not _ocv_rows_rise(fitted[0], ocv_temps):
        if ocv_temperature:
            raise FitError("the OCV with its fitted temperature coefficient does not rise with SOC at "
                           f"{ocv_temps[0]:.1f} or {ocv_temps[1]:.1f} °C: the rests do not determine it "
                           "(fit without it: ocv_temperature False / --no-ocv-temperature)")
        dropped = ("the OCV temperature coefficient the rests gave would make the OCV fall with SOC "
                   "at the coldest or hottest test: left out (one OCV for every temperature)")
        if dropped not in fit_warnings:
            fit_warnings.append(dropped)
        lay = replace(lay, ocv_dT=False)
        fitted, more = _fit_groups(tests, groups, socs0, temps, sample_temps, lay, law, int(max_evaluations))
        evaluations += more
    return FitResult(capacity_Ah, grid, form, rc_pairs, fitted, [], v_min, v_max, capacity_source,
                     law, evaluations, fit_warnings, weight, ocv_temps_C=ocv_temps if lay.ocv_dT else None)


def _pooled_rms_mV(files: list[FileFit]) -> float:
    """RMS over every sample of these tests."""
    sq = sum(f.samples * f.rms_mV ** 2 for f in files)
    return float(np.sqrt(sq / max(sum(f.samples for f in files), 1)))


def _fit_groups(tests, groups, socs0, temps, sample_temps, layout: Layout, law: str,
                max_evaluations: int) -> tuple[list[FitAtTemperature], int]:
    """One fit per group of tests (one group for the arrhenius law)."""
    fitted: list[FitAtTemperature] = []
    evaluations = 0
    for members in groups:
        names = ", ".join(tests[k].name for k in members)
        if not any(rest_mask(tests[k]).any() for k in members):
            where = "" if law != "table" or len(groups) == 1 else f" at {temps[members[0]]:.1f} °C"
            raise FitError(f"{names}: no rest{where} (|current| near zero for at least 10 s), so there is no OCV "
                           "information to tell the open-circuit voltage from the resistive drop; "
                           "record a rest before the first pulse and after each step"
                           + ("" if law != "table" else
                              ", or fit all temperatures jointly (temperature_law arrhenius), where one "
                              "test's rests give the OCV for all"))
        traces = [prepare(tests[k], socs0[k], layout, sample_temps[k] if law == "arrhenius" else None)
                  for k in members]
        try:
            sol = fit_group(traces, layout, max_evaluations)
            if layout.form == "poly":
                _check_poly_positive(sol.r0, layout.capacity_Ah)
        except FitError as e:
            raise FitError(f"{names}: {e}") from None
        if law == "arrhenius":
            temp = REF_TEMP_C
        else:
            temp = None if temps[members[0]] is None else float(np.mean([temps[k] for k in members]))
        fitted.append(FitAtTemperature(temp, sol.ocv_V, sol.r0, sol.rc_r_ohm, sol.rc_tau_s, sol.r0_K,
                                       sol.rc_r_K, sol.rc_tau_K, sol.docv_dT))
        evaluations += sol.evaluations
    return fitted, evaluations


def _file_errors(result: FitResult, tests: list, socs0: list, temps: list[np.ndarray]) -> list[FileFit]:
    """Each test re-simulated with the preset as written (C++: the plant's equations under
    an exact zero-order hold, packsim._packsim.simulate_cell) against its measured voltage."""
    from ._packsim import simulate_cell
    text = result.yaml
    files = []
    for test, soc0, temp in zip(tests, socs0, temps):
        try:
            model = simulate_cell(text, test.time_s, test.current_A,
                                  held_current(test.current_A, test.steps_on_samples), temp, soc0)
        except ValueError as e:  # packsim.ScenarioError: the loader refuses the fitted values
            raise FitError(f"the fitted preset is not a valid cell ({e}): the tests do not determine it; "
                           "check capacity_Ah and the current's unit and sign") from None
        err = model - test.voltage_V
        soc = soc_trace(test, soc0, result.capacity_Ah)
        low = soc < LOW_SOC
        files.append(FileFit(test.name, test.start_temp_C if test.temp_C is not None else None, err.size,
                             1e3 * float(np.sqrt(np.mean(err ** 2))), 1e3 * float(np.max(np.abs(err))),
                             test.time_s, test.current_A, test.voltage_V, model, soc,
                             1e3 * float(np.sqrt(np.mean(err[low] ** 2))) if low.any() else None, test.reader))
    return files


def _ocv_temperature(wanted: bool | None, law: str, tests, sample_temps) -> tuple[float, float] | None:
    """Whether the joint fit gets an OCV temperature coefficient: (coldest, hottest training
    sample, the rows of the preset's 2-D OCV) when it does, else None. Only rests tell the
    OCV at a temperature, so their temperatures must lie more than TEMP_GROUP_C apart."""
    if wanted is not None and not isinstance(wanted, bool):
        raise FitError(f"ocv_temperature: {wanted!r} is not True, False or None")
    if wanted is False:
        return None
    rest_temps = [temps[rest_mask(t)] for t, temps in zip(tests, sample_temps) if temps is not None]
    rest_temps = np.concatenate(rest_temps) if rest_temps else np.zeros(0)
    span = float(np.ptp(rest_temps)) if rest_temps.size else 0.0
    if law != "arrhenius" or span <= TEMP_GROUP_C:
        if wanted:
            raise FitError("ocv_temperature: an OCV temperature coefficient needs rests at temperatures more than "
                           f"{TEMP_GROUP_C:g} °C apart in a joint fit over temperatures; these tests' rests span "
                           f"{span:.1f} °C" + ("" if law == "arrhenius" else f" (temperature law: {law})"))
        return None
    every = np.concatenate([t for t in sample_temps if t is not None])
    return float(np.min(every)), float(np.max(every))


def _ocv_rows_rise(g: FitAtTemperature, temps_C: tuple[float, float]) -> bool:
    """The preset's OCV rows at the coldest and hottest temperature rise strictly with SOC
    (the preset loader requires it at every row of a 2-D table)."""
    return all(np.all(np.diff(g.ocv_V + (t - REF_TEMP_C) * g.docv_dT_V_per_K) > 0) for t in temps_C)


def _sample_temps(test, given: float | None) -> np.ndarray | None:
    """Each sample's temperature: the one given for the test, else its measured temp_C."""
    if given is not None:
        return np.full(test.time_s.size, given)
    return None if test.temp_C is None else test.temp_C


def _model_temps(law: str, test_temp: float | None, samples: np.ndarray | None, test) -> np.ndarray:
    """The temperature the fit gave each sample: measured (arrhenius), the test's (table)."""
    if law == "arrhenius" and samples is not None:
        return samples
    return np.full(test.time_s.size, REF_TEMP_C if test_temp is None else test_temp)


def _temperature_law(law: str, temps: list[float | None]) -> str:
    """none (one temperature), table (one fit per temperature) or arrhenius (one joint fit)."""
    if law not in TEMPERATURE_LAWS:
        raise FitError(f"temperature_law '{law}' is not one of {', '.join(TEMPERATURE_LAWS)}")
    known = [t for t in temps if t is not None]
    if len(known) != len(temps) or not known or max(known) - min(known) <= TEMP_GROUP_C:
        if len(known) not in (0, len(temps)):
            missing = [k for k, t in enumerate(temps) if t is None]
            raise FitError(f"test {missing[0] + 1} has no temperature (no temp_C column, no temps_C) while others "
                           "have one: give every test a temperature or none")
        return "none"
    return law


def from_bpx(source: Any) -> FitResult:
    """A fitted cell back from a BPX file (or document) that FitResult.save_bpx wrote;
    .yaml / .save() then give the cell preset."""
    from ._fit_interchange import from_bpx as read
    return read(source)


def from_pybamm(params: Any, soc_grid: Any = None, rc_pairs: int | None = None) -> FitResult:
    """A cell from PyBaMM Thevenin parameter values: OCV, R0, R_k and tau_k = R_k·C_k on the
    SOC grid at 25 °C, Arrhenius constants from 15 and 35 °C. Needs PyBaMM."""
    from ._fit_interchange import from_pybamm as read
    return read(params, soc_grid, rc_pairs)
