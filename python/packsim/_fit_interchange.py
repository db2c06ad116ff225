"""A fitted cell in other tools' formats, and back: BPX (the Battery Parameter eXchange
format, the ``bpx`` package validates it) and PyBaMM's Thevenin equivalent-circuit model.

BPX describes electrochemical models; an equivalent circuit has no section of its own, so
the file is a "Partial" parameterisation whose User-defined section holds the circuit
(names as PyBaMM's Thevenin parameters where one exists):

    Cell capacity [A.h], Lower / Upper voltage cut-off [V], Reference temperature [K]
    Test temperature [degC]                       without a temperature law: the tests' temperature
    Open-circuit voltage [V]        {x: soc, y}   at the reference temperature
    Entropic change [V/K]           {x: soc, y}   dOCV/dT (only when fitted), with
    OCV rows temperature [degC]     {x, y}        the preset's 2-D OCV rows (coldest, hottest test)
    R0 [Ohm]                        {x: soc, y}   at the reference temperature
    R0 Arrhenius constant [K]                     R(T) = R(T_ref)·exp(K·(1/T - 1/T_ref))
    R1 [Ohm] ({x, y} or a number), Tau1 [s], R1 / Tau1 Arrhenius constant [K], R2 ...

PyBaMM's Thevenin model takes R0, R_k and C_k = tau_k / R_k as functions of (cell
temperature in °C, current, SoC) and the OCV of SoC only (dOCV/dT there is the entropic
heat's, not the voltage's); packsim's laws are written as those functions.
"""
from __future__ import annotations

import json
import math
import os
import warnings
from typing import Any

import numpy as np

from ._fit_data import FitError, FitWarning
from ._fit_ecm import REF_TEMP_C

__all__ = ["to_bpx", "from_bpx", "to_pybamm", "from_pybamm", "BPX_VERSION"]

BPX_VERSION = "1.1.0"
PYBAMM_FULL_SOC = 1.0 - 1e-6   # PyBaMM's Thevenin model refuses to start at SoC 1 (its "Maximum SoC" event)
KELVIN = 273.15
_TABLE_KEYS = ("Open-circuit voltage [V]", "R0 [Ohm]")


def _exportable(fit) -> Any:
    if fit.form != "table":
        raise FitError("export: R0 must be a table over SOC (form table), not a polynomial")
    if fit.temperature_law == "table" or len(fit.temperatures) != 1:
        raise FitError("export: a fit per temperature (temperature_law table) has no single law to write; "
                       "fit jointly (temperature_law arrhenius) or at one temperature")
    return fit.temperatures[0]


def _table(grid: np.ndarray, y: np.ndarray) -> dict:
    return {"x": [float(v) for v in grid], "y": [float(v) for v in y]}


def to_bpx(fit, title: str = "packsim fit") -> dict:
    """A BPX document (a dict, JSON-ready) of a fitted cell; validated with ``bpx`` when it
    is installed."""
    g = _exportable(fit)
    grid = fit.soc_grid
    ecm: dict[str, Any] = {
        "description": (f"Thevenin equivalent circuit with {fit.rc_pairs} RC pair(s) fitted by packsim fit: "
                        "v = OCV(soc) + (T - T_ref)*dOCV/dT(soc) - I*R0(soc)*f0(T) - sum v_k, "
                        "dv_k/dt = (I*R_k(soc)*f_k(T) - v_k)/(tau_k*g_k(T)), f, g = exp(K*(1/T - 1/T_ref)); "
                        "positive current discharges; soc = 1 - discharged/capacity"),
        "Cell capacity [A.h]": float(fit.capacity_Ah),
        "Lower voltage cut-off [V]": float(fit.v_min_V),
        "Upper voltage cut-off [V]": float(fit.v_max_V),
        "Reference temperature [K]": REF_TEMP_C + KELVIN,
        "Number of RC elements": int(fit.rc_pairs),
        "Open-circuit voltage [V]": _table(grid, g.ocv_V),
        "R0 [Ohm]": _table(grid, g.r0),
        "R0 Arrhenius constant [K]": float(g.r0_K),
    }
    if fit.temperature_law == "none" and g.temp_C is not None:
        ecm["Test temperature [degC]"] = float(g.temp_C)   # the tests' temperature (no law over it)
    if g.docv_dT_V_per_K is not None:
        ecm["Entropic change [V/K]"] = _table(grid, g.docv_dT_V_per_K)
        # the preset's OCV rows (the coldest and hottest training sample), in °C to keep them exact
        ecm["OCV rows temperature [degC]"] = {"x": [0.0, 1.0], "y": [float(t) for t in fit.ocv_temps_C]}
    for k in range(fit.rc_pairs):
        r = g.rc_r_ohm[k]
        ecm[f"R{k + 1} [Ohm]"] = float(r[0]) if r.size == 1 else _table(grid, r)
        ecm[f"Tau{k + 1} [s]"] = float(g.rc_tau_s[k])
        ecm[f"R{k + 1} Arrhenius constant [K]"] = float(g.rc_r_K[k]) if g.rc_r_K is not None else 0.0
        ecm[f"Tau{k + 1} Arrhenius constant [K]"] = float(g.rc_tau_K[k]) if g.rc_tau_K is not None else 0.0
    doc = {"Header": {"BPX": BPX_VERSION, "Title": title, "Model": "Partial",
                      "Description": "An equivalent-circuit (Thevenin) cell in the User-defined section"},
           "Parameterisation": {"User-defined": ecm}}
    _validate(doc, "export")
    return doc


def _validate(doc: dict, where: str) -> None:
    try:
        import bpx
    except ImportError:
        raise FitError(f"{where}: BPX needs the bpx package (pip install bpx, or bash scripts/install-deps.sh)") from None
    try:
        bpx.parse_bpx_obj(json.loads(json.dumps(doc)))
    except Exception as e:  # pydantic's ValidationError, a ValueError or TypeError of the schema
        lines = [line.strip() for line in str(e).splitlines() if line.strip() and "errors.pydantic.dev" not in line]
        raise FitError(f"{where}: not a valid BPX document: {'; '.join(lines)}") from None


def _number(ecm: dict, key: str, where: str, default: float | None = None) -> float:
    if key not in ecm:
        if default is not None:
            return default
        raise FitError(f"{where}: User-defined has no '{key}'")
    v = ecm[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise FitError(f"{where}: User-defined '{key}': {v!r} is not a number")
    return float(v)


def _read_table(ecm: dict, key: str, where: str, grid: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    v = ecm.get(key)
    if not isinstance(v, dict) or not isinstance(v.get("x"), list) or not isinstance(v.get("y"), list):
        raise FitError(f"{where}: User-defined '{key}' must be a table {{x: [soc...], y: [...]}}")
    x, y = np.asarray(v["x"], dtype=float), np.asarray(v["y"], dtype=float)
    if x.size != y.size or x.size < 2 or not np.all(np.isfinite(x)) or not np.all(np.isfinite(y)):
        raise FitError(f"{where}: User-defined '{key}': x and y need the same length (at least 2), finite numbers")
    if grid is not None and not np.array_equal(x, grid):
        raise FitError(f"{where}: User-defined '{key}': its x differs from that of 'Open-circuit voltage [V]' "
                       "(packsim's tables share one SOC grid)")
    return x, y


def from_bpx(source: str | os.PathLike | dict):
    """A FitResult (no test files) from a BPX document or file written by to_bpx."""
    from .fit import FitAtTemperature, FitResult, parse_soc_grid
    where = "BPX" if isinstance(source, dict) else os.fspath(source)
    if isinstance(source, dict):
        doc = source
    else:
        try:
            with open(source, encoding="utf-8") as f:
                doc = json.load(f)
        except OSError as e:
            raise FitError(f"{where}: {e.strerror}") from None
        except json.JSONDecodeError as e:
            raise FitError(f"{where}:{e.lineno}: not JSON ({e.msg})") from None
    _validate(doc, where)
    ecm = doc.get("Parameterisation", {}).get("User-defined")
    if not isinstance(ecm, dict) or "R0 [Ohm]" not in ecm:
        raise FitError(f"{where}: no equivalent circuit in Parameterisation/User-defined (written by packsim fit "
                       "--bpx, with 'R0 [Ohm]', 'Open-circuit voltage [V]', 'R1 [Ohm]', 'Tau1 [s]' ...)")
    grid, ocv = _read_table(ecm, "Open-circuit voltage [V]", where, None)
    grid = parse_soc_grid(grid)
    _, r0 = _read_table(ecm, "R0 [Ohm]", where, grid)
    pairs_value = _number(ecm, "Number of RC elements", where)
    if pairs_value not in range(5):
        raise FitError(f"{where}: User-defined 'Number of RC elements': {pairs_value:g} is not an integer in 0..4")
    pairs = int(pairs_value)
    ref_C = _number(ecm, "Reference temperature [K]", where) - KELVIN
    if abs(ref_C - REF_TEMP_C) > 1e-9:
        raise FitError(f"{where}: User-defined 'Reference temperature [K]' must be {REF_TEMP_C + KELVIN} "
                       "(packsim's laws are around 25 °C)")
    r_rows, taus, r_K, tau_K = [], [], [], []
    for k in range(1, pairs + 1):
        v = ecm.get(f"R{k} [Ohm]")
        r_rows.append(np.array([_number(ecm, f"R{k} [Ohm]", where)]) if not isinstance(v, dict)
                      else _read_table(ecm, f"R{k} [Ohm]", where, grid)[1])
        taus.append(_number(ecm, f"Tau{k} [s]", where))
        r_K.append(_number(ecm, f"R{k} Arrhenius constant [K]", where, 0.0))
        tau_K.append(_number(ecm, f"Tau{k} Arrhenius constant [K]", where, 0.0))
    if len({r.size for r in r_rows}) > 1:
        raise FitError(f"{where}: the RC resistances must all be numbers or all tables over SOC")
    r0_K = _number(ecm, "R0 Arrhenius constant [K]", where, 0.0)
    docv, ocv_rows = None, None
    if "Entropic change [V/K]" in ecm:
        docv = _read_table(ecm, "Entropic change [V/K]", where, grid)[1]
        _, rows_C = _read_table(ecm, "OCV rows temperature [degC]", where, None)
        ocv_rows = (float(rows_C[0]), float(rows_C[1]))
    law = "arrhenius" if (r0_K or any(r_K) or any(tau_K) or docv is not None) else "none"
    temp_C = REF_TEMP_C if law == "arrhenius" else (
        _number(ecm, "Test temperature [degC]", where) if "Test temperature [degC]" in ecm else None)
    g = FitAtTemperature(temp_C, ocv, r0,
                         np.array(r_rows).reshape(pairs, -1) if pairs else np.zeros((0, 1)), np.array(taus, dtype=float),
                         r0_K, np.array(r_K, dtype=float), np.array(tau_K, dtype=float), docv)
    return _loadable(FitResult(_number(ecm, "Cell capacity [A.h]", where), grid, "table", pairs, [g], [],
                               _number(ecm, "Lower voltage cut-off [V]", where),
                               _number(ecm, "Upper voltage cut-off [V]", where),
                               capacity_source=f"from {where}", temperature_law=law, ocv_temps_C=ocv_rows), where)


def _loadable(fit, where: str):
    """The imported cell as packsim's preset loader reads it: its refusal is the error."""
    from ._packsim import simulate_cell
    t = np.array([0.0, 1.0])
    try:
        simulate_cell(fit.yaml, t, np.zeros(2), np.zeros(2), np.full(2, REF_TEMP_C), 1.0)
    except ValueError as e:  # packsim.ScenarioError
        raise FitError(f"{where}: not a valid packsim cell: {e}") from None
    return fit


def to_pybamm(fit, thermal: dict | None = None):
    """pybamm.ParameterValues for pybamm.equivalent_circuit.Thevenin(options={"number of rc
    elements": fit.rc_pairs}). Thermal values (not fitted) default to packsim's cell
    (50 J/K, 0.05 W/K to the ambient through a jig that does not heat); ``thermal``
    overrides any PyBaMM thermal parameter."""
    import pybamm
    g = _exportable(fit)
    grid = fit.soc_grid
    ref_K = REF_TEMP_C + KELVIN

    def law(k: float, T_cell):
        return 1.0 if k == 0.0 else pybamm.exp(k * (1.0 / (T_cell + KELVIN) - 1.0 / ref_K))

    def curve(name: str, y: np.ndarray, soc):
        # held flat beyond the grid, as packsim's tables
        return pybamm.Interpolant(grid, y, pybamm.maximum(pybamm.minimum(soc, grid[-1]), grid[0]), name=name,
                                  interpolator="linear")

    def ocv(soc):
        return curve("packsim OCV", g.ocv_V, soc)

    def r0(T_cell, current, soc):
        return curve("packsim R0", g.r0, soc) * law(g.r0_K, T_cell)

    values: dict[str, Any] = {
        "chemistry": "ecm", "Initial SoC": PYBAMM_FULL_SOC, "Initial temperature [K]": ref_K, "Ambient temperature [K]": ref_K,
        "Cell capacity [A.h]": fit.capacity_Ah, "Nominal cell capacity [A.h]": fit.capacity_Ah,
        "Current function [A]": fit.capacity_Ah,
        "Upper voltage cut-off [V]": fit.v_max_V, "Lower voltage cut-off [V]": fit.v_min_V,
        "Cell thermal mass [J/K]": 50.0, "Cell-jig heat transfer coefficient [W/K]": 0.05,
        "Jig thermal mass [J/K]": 1e9, "Jig-air heat transfer coefficient [W/K]": 1e3,
        "Open-circuit voltage [V]": ocv, "R0 [Ohm]": r0, "RCR lookup limit [A]": 1e6,
    }

    def entropic(ocv_V, T_cell):
        # PyBaMM's entropic change is over the OCV and temperature: the OCV table gives the SOC
        if g.docv_dT_V_per_K is None:
            return pybamm.Scalar(0.0)
        return pybamm.Interpolant(g.ocv_V, g.docv_dT_V_per_K, ocv_V, name="packsim dOCV/dT", interpolator="linear")
    values["Entropic change [V/K]"] = entropic
    for k in range(fit.rc_pairs):
        r_row, tau, rk = g.rc_r_ohm[k], float(g.rc_tau_s[k]), g.rc_r_K[k] if g.rc_r_K is not None else 0.0
        tk = g.rc_tau_K[k] if g.rc_tau_K is not None else 0.0

        def r(T_cell, current, soc, r_row=r_row, rk=rk, k=k):
            base = float(r_row[0]) if r_row.size == 1 else curve(f"packsim R{k + 1}", r_row, soc)
            return base * law(rk, T_cell)

        def c(T_cell, current, soc, r_row=r_row, rk=rk, tau=tau, tk=tk, k=k):
            return tau * law(tk, T_cell) / r(T_cell, current, soc, r_row, rk, k)
        values[f"R{k + 1} [Ohm]"] = r
        values[f"C{k + 1} [F]"] = c
        values[f"Element-{k + 1} initial overpotential [V]"] = 0.0
    values.update(thermal or {})
    return pybamm.ParameterValues(values)


def from_pybamm(params, soc_grid=None, rc_pairs: int | None = None):
    """A FitResult from PyBaMM Thevenin parameter values (a pybamm.ParameterValues or a
    dict): the OCV, R0, R_k and tau_k = R_k·C_k read on the SOC grid at 25 °C, each
    resistance's and time constant's Arrhenius constant from its values at 15 and 35 °C
    (exact for an Arrhenius law; the current at 0 A). A time constant R_k·C_k that varies
    over SoC is taken at its median, with a FitWarning. The entropic change is not read back
    (PyBaMM's is over the OCV, for heat)."""
    import pybamm
    from .fit import DEFAULT_SOC_GRID, FitAtTemperature, FitResult, parse_soc_grid
    p = params if isinstance(params, pybamm.ParameterValues) else pybamm.ParameterValues(params)
    grid = DEFAULT_SOC_GRID if soc_grid is None else parse_soc_grid(soc_grid)
    if rc_pairs is None:
        rc_pairs = 0
        while f"R{rc_pairs + 1} [Ohm]" in p.keys():
            rc_pairs += 1

    def ev(name: str, *args) -> float:
        v = p[name]
        out = v(*[pybamm.Scalar(a) for a in args]) if callable(v) else v
        return float(np.asarray(out.evaluate() if isinstance(out, pybamm.Symbol) else out).ravel()[0])

    def over_soc(name: str, temp_C: float) -> np.ndarray:
        return np.array([ev(name, temp_C, 0.0, s) for s in grid])

    def k_of(values_lo: np.ndarray, values_hi: np.ndarray) -> float:
        lo_C, hi_C = REF_TEMP_C - 10.0, REF_TEMP_C + 10.0
        ratio = float(np.mean(np.log(values_hi / values_lo)))
        return ratio / (1.0 / (hi_C + KELVIN) - 1.0 / (lo_C + KELVIN))

    ocv = np.array([ev("Open-circuit voltage [V]", s) for s in grid])
    r0 = over_soc("R0 [Ohm]", REF_TEMP_C)
    r0_K = k_of(over_soc("R0 [Ohm]", REF_TEMP_C - 10.0), over_soc("R0 [Ohm]", REF_TEMP_C + 10.0))
    rows, taus, r_K, tau_K = [], [], [], []
    for k in range(1, rc_pairs + 1):
        r = {t: over_soc(f"R{k} [Ohm]", t) for t in (REF_TEMP_C - 10.0, REF_TEMP_C, REF_TEMP_C + 10.0)}
        tau = {t: r[t] * over_soc(f"C{k} [F]", t) for t in r}
        t25 = tau[REF_TEMP_C]
        if np.ptp(t25) > 1e-9 * np.max(t25):
            warnings.warn(f"PyBaMM parameters: tau{k} = R{k}·C{k} varies over SoC from {np.min(t25):.4g} to "
                          f"{np.max(t25):.4g} s at 25 °C; packsim's time constants do not: the median is used",
                          FitWarning, stacklevel=3)
            pick = lambda v: np.array([np.median(v)])  # noqa: E731
        else:
            pick = lambda v: v[:1]  # noqa: E731
        rows.append(r[REF_TEMP_C] if np.ptp(r[REF_TEMP_C]) > 0 else r[REF_TEMP_C][:1])
        taus.append(float(pick(t25)[0]))
        r_K.append(k_of(r[REF_TEMP_C - 10.0], r[REF_TEMP_C + 10.0]))
        tau_K.append(k_of(pick(tau[REF_TEMP_C - 10.0]), pick(tau[REF_TEMP_C + 10.0])))
    if len({r.size for r in rows}) > 1:
        rows = [np.full(grid.size, r[0]) if r.size == 1 else r for r in rows]
    temp_law = any(abs(k) > 1e-6 for k in [r0_K, *r_K, *tau_K])
    clean = lambda k: float(k) if abs(k) > 1e-6 else 0.0  # noqa: E731 (rounding of a law that is not there)
    g = FitAtTemperature(REF_TEMP_C if temp_law else None, ocv, r0,
                         np.array(rows).reshape(rc_pairs, -1) if rc_pairs else np.zeros((0, 1)),
                         np.array(taus, dtype=float), clean(r0_K), np.array([clean(k) for k in r_K]),
                         np.array([clean(k) for k in tau_K]))
    return _loadable(FitResult(float(p["Cell capacity [A.h]"]), grid, "table", rc_pairs, [g], [],
                               float(p["Lower voltage cut-off [V]"]), float(p["Upper voltage cut-off [V]"]),
                               capacity_source="from PyBaMM parameters",
                               temperature_law="arrhenius" if temp_law else "none"), "PyBaMM parameters")
