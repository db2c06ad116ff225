"""The cell preset YAML a fit writes (the format of scenarios/cells/*.yaml)."""
from __future__ import annotations

import math

import numpy as np

__all__ = ["preset_yaml"]


def _num(v: float) -> str:
    return f"{float(v):.9g}"


def _list(values) -> str:
    return "[" + ", ".join(_num(v) for v in values) + "]"


def _curve(grid: np.ndarray, temps_C: list[float], rows: list[np.ndarray], indent: str) -> str:
    """A table over SOC; 2-D (one row per temperature) when there are several temperatures;
    a number when every value is the same single one."""
    if len(rows) == 1:
        if rows[0].size == 1:
            return _num(rows[0][0])
        return f"\n{indent}  axis: soc\n{indent}  x: {_list(grid)}\n{indent}  y: {_list(rows[0])}"
    if all(r.size == 1 for r in rows):  # constants per temperature: a flat row over SOC
        rows = [np.full(2, r[0]) for r in rows]
        grid = np.array([0.0, 1.0])
    lines = [f"\n{indent}  axis: soc", f"{indent}  x: {_list(grid)}", f"{indent}  temp_C: {_list(temps_C)}",
             f"{indent}  y:"]
    lines += [f"{indent}    - {_list(r)}   # {_num(t)} °C" for t, r in zip(temps_C, rows)]
    return "\n".join(lines)


def _arrhenius(grid: np.ndarray, row: np.ndarray, k: float, indent: str) -> str:
    """A curve over SOC (or a constant) times the plant's Arrhenius factor around 25 °C."""
    from ._fit_ecm import REF_TEMP_C
    law = f"{indent}  arrhenius_K: {_num(k)}\n{indent}  ref_temp_C: {_num(REF_TEMP_C)}"
    if row.size == 1:
        return f"\n{indent}  poly: [{_num(row[0])}]\n{law}"
    return f"\n{indent}  axis: soc\n{indent}  x: {_list(grid)}\n{indent}  y: {_list(row)}\n{law}"


def _key(name: str, value: str) -> str:
    return f"{name}:{value}" if value.startswith("\n") else f"{name}: {value}"


def preset_yaml(fit) -> str:
    """YAML text of a packsim.fit.FitResult (a cell preset, loadable with `preset:`)."""
    groups = fit.temperatures
    temps = [g.temp_C for g in groups]
    grid = fit.soc_grid
    out = ["# Cell preset fitted by `packsim fit` from:"]
    for f in fit.files:
        temp = "" if f.temp_C is None else f" at {f.temp_C:.1f} °C"
        out.append(f"#   {f.name}{temp}: {f.samples} samples, voltage error {f.rms_mV:.2f} mV RMS, "
                   f"{f.max_mV:.2f} mV max")
    for f in fit.validation:
        out.append(f"#   held out, not fitted: {f.name}: {f.samples} samples, voltage error {f.rms_mV:.2f} mV RMS, "
                   f"{f.max_mV:.2f} mV max")
    out.append("# Thermal parameters are not fitted: heat_capacity_J_per_K and g_ambient_W_per_K keep")
    out.append("# packsim's defaults unless a scenario overrides them.")
    out.append(f"capacity_Ah: {_num(fit.capacity_Ah)}   # {fit.capacity_source}")
    docv = groups[0].docv_dT_V_per_K if len(groups) == 1 else None
    if docv is not None:  # OCV(soc, T) = OCV(soc) + (T - 25 °C)·dOCV/dT(soc): exact between the rows
        from ._fit_ecm import REF_TEMP_C
        rows_C = list(fit.ocv_temps_C)
        out.append(f"# OCV with its fitted temperature coefficient, at the coldest and hottest test temperature "
                   f"(held beyond them); 25 °C: {_list(groups[0].ocv_V)}")
        out.append(_key("ocv_V", _curve(grid, rows_C, [groups[0].ocv_V + (t - REF_TEMP_C) * docv for t in rows_C], "")))
        out.append("# dOCV/dT over SOC, V/K: the same coefficient, for the reversible (entropic) heat")
        out.append(_key("docv_dT_V_per_K", _curve(grid, [None], [docv], "")))
    else:
        out.append(_key("ocv_V", _curve(grid, temps, [g.ocv_V for g in groups], "")))
    if fit.temperature_law == "arrhenius":
        (g,) = groups
        if fit.form == "poly":
            out.append(f"r0_ohm: {{poly: {_list(g.r0)}, axis: discharged_Ah, arrhenius_K: {_num(g.r0_K)}, "
                       f"ref_temp_C: 25}}")
        else:
            out.append(_key("r0_ohm", _arrhenius(grid, g.r0, g.r0_K, "")))
        if fit.rc_pairs:
            out.append("rc_pairs:")
            for k in range(fit.rc_pairs):
                out.append(_key("  - r_ohm", _arrhenius(grid, g.rc_r_ohm[k], g.rc_r_K[k], "    ")))
                out.append(_key("    tau_s", _arrhenius(grid, np.array([g.rc_tau_s[k]]), g.rc_tau_K[k], "    ")))
    elif fit.form == "poly":
        out.append(f"r0_ohm: {{poly: {_list(groups[0].r0)}, axis: discharged_Ah}}")
    else:
        out.append(_key("r0_ohm", _curve(grid, temps, [g.r0 for g in groups], "")))
    if fit.rc_pairs and fit.temperature_law != "arrhenius":
        out.append("rc_pairs:")
        for k in range(fit.rc_pairs):
            r = _curve(grid, temps, [g.rc_r_ohm[k] for g in groups], "    ")
            tau = _curve(grid, temps, [np.array([g.rc_tau_s[k]]) for g in groups], "    ")
            out.append(_key("  - r_ohm", r))
            out.append(_key("    tau_s", tau))
    out.append(f"v_min_V: {_num(math.floor(fit.v_min_V * 100) / 100)}")
    out.append(f"v_max_V: {_num(math.ceil(fit.v_max_V * 100) / 100)}")
    return "\n".join(out) + "\n"
