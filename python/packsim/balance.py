"""``packsim.balance_time``: how long passive balancing takes per resistor, as
``packsim balance-time`` computes it (core/balance/balance_time.hpp).

    bt = packsim.balance_time(resistor=[22, 33, 47, 68, 100])   # preset bench_6s_balancing
    bt = packsim.balance_time("my_pack.yaml", resistor=33, delta_Ah=0.5, cell_V=3.9)
    bt.rows[0].simulated_h, bt.table, print(bt)                  # print: the CLI's table
    packsim.plot.balance_time(bt)                                # time to balance vs resistor

For each resistor: the analytic estimate t = ΔQ / I with I = V_cell / (R + Rds_on), and
the full co-simulation of the pack at rest with the firmware's balancing policy until
the rest voltages are within target_mV.
"""
from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, fields
from typing import Any

from ._overrides import flatten_overrides

__all__ = ["balance_time", "BalanceTimeResult", "BalanceTimeRow", "DEFAULT_PRESET"]

DEFAULT_PRESET = "bench_6s_balancing"  # what `packsim balance-time` uses without a scenario


@dataclass(frozen=True)
class BalanceTimeRow:
    """One resistor. Per-cell current and power at cell_V; times in hours."""
    resistor_ohm: float
    branch_ohm: float          # resistor + FET Rds_on
    current_A: float
    power_W: float
    board_power_W: float       # every high cell balancing at cell_V
    analytic_h: float
    simulated: bool
    simulated_h: float
    end_reason: str            # within_target | charge_removed | bms_stopped | time_limit | not_started
    peak_board_C: float        # NaN without a board thermal node
    energy_Wh: float           # dissipated in the balancing branches
    charge_removed_Ah: float
    final_spread_Ah: float


@dataclass(frozen=True)
class BalanceTimeResult:
    scenario: str
    delta_Ah: float            # imbalance to remove per high cell
    cell_V: float
    high_cells: int
    target_mV: float
    rows: tuple[BalanceTimeRow, ...]

    @property
    def resistor_ohm(self) -> list[float]:
        return [r.resistor_ohm for r in self.rows]

    @property
    def columns(self) -> dict[str, list]:
        return {f.name: [getattr(r, f.name) for r in self.rows] for f in fields(BalanceTimeRow)}

    @property
    def table(self):
        """One row per resistor: a pandas DataFrame, or a dict of columns without pandas."""
        try:
            import pandas as pd
        except ImportError:
            return self.columns
        return pd.DataFrame(self.columns)

    def __str__(self) -> str:
        """The table ``packsim balance-time`` prints for the same arguments."""
        s = "" if self.high_cells == 1 else "s"
        out = [f"balance-time  {self.scenario}: {self.delta_Ah:.3f} Ah to remove, cells at {self.cell_V:.3f} V, "
               f"{self.high_cells} high cell{s}, target {self.target_mV:.0f} mV\n",
               "  R_ohm    I_mA  P_cell_W  board_W  analytic_h  simulated_h  sim/ana  removed_Ah  peak_board_C  "
               "energy_Wh  end\n"]
        for w in self.rows:
            line = (f"{w.resistor_ohm:7.1f}  {w.current_A * 1e3:6.2f}  {w.power_W:8.3f}  {w.board_power_W:7.2f}  "
                    f"{w.analytic_h:10.2f}")
            if w.simulated:
                peak = "-" if math.isnan(w.peak_board_C) else f"{w.peak_board_C:.1f}"
                ratio = w.simulated_h / w.analytic_h if w.analytic_h > 0 else 0.0
                line += (f"  {w.simulated_h:11.2f}  {ratio:7.3f}  {w.charge_removed_Ah:10.3f}  {peak:>12}  "
                         f"{w.energy_Wh:9.3f}  {w.end_reason}")
            out.append(line + "\n")
        out.append("analytic: delta / (V_cell / (R + Rds_on)) at constant current and V_cell. simulated: the pack "
                   "at rest,\nthe BMS policy balancing until the rest voltages are within the target; longer "
                   "because the current\nfalls as the high cells drain and their voltage drops.\n")
        return "".join(out)


def _number(name: str, v: Any, *, positive: bool = False, allow_none: bool = True) -> float | None:
    if v is None and allow_none:
        return None
    if isinstance(v, bool) or not isinstance(v, (int, float)) and not hasattr(v, "__float__"):
        raise TypeError(f"{name} must be a number, got {type(v).__name__}")
    x = float(v)
    if not math.isfinite(x):
        raise ValueError(f"{name} must be finite, got {x}")
    if positive and x <= 0:
        raise ValueError(f"{name} must be > 0, got {x}")
    return x


def _resistors(resistor: Any) -> list[float]:
    if resistor is None:
        return []
    if isinstance(resistor, (str, bytes, Mapping)):
        raise TypeError(f"resistor must be a number or a list of numbers (ohm), got {type(resistor).__name__}")
    if isinstance(resistor, Iterable):
        values = [_number("resistor", r, positive=True, allow_none=False) for r in resistor]
        if not values:
            raise ValueError("resistor: give at least one value (or None for the scenario's own)")
        return values  # type: ignore[return-value]
    return [_number("resistor", resistor, positive=True, allow_none=False)]  # type: ignore[list-item]


def balance_time(scenario: str | os.PathLike[str] | Mapping[str, Any] | None = None, /,
                 overrides: Mapping[str, Any] | None = None, *, preset: str | None = None,
                 resistor: float | Iterable[float] | None = None, delta_Ah: float | None = None,
                 cell_V: float | None = None, high_cells: int = 1, target_mV: float = 5.0,
                 max_hours: float = 72.0, simulate: bool = True,
                 base_dir: str | os.PathLike[str] | None = None, **more: Any) -> BalanceTimeResult:
    """Time to balance per balancing resistor, like ``packsim balance-time``.

    scenario:   a scenario file, YAML text or a dict; or
    preset:     a bundled scenario by name (``scenarios/`` or ``scenarios/balance/``);
                neither: the ``bench_6s_balancing`` preset.
    overrides, **more: as for ``packsim.run``.
    resistor:   ohm, one value or a list (``[22, 33, 47]``); default: the scenario's.
    delta_Ah:   imbalance to remove per high cell (default: the scenario's initial spread).
    cell_V:     voltage of the high cells at the start and of the analytic estimate
                (needs delta_Ah; default: OCV at the initial SOC).
    high_cells: series cells that start high by delta_Ah.
    target_mV:  balanced when max - min cell voltage is below this.
    max_hours:  simulation cap.
    simulate:   False: the analytic estimate only (the CLI's ``--analytic-only``).
    """
    from . import _bool_arg, _core, _int_arg, _path_arg, _scenario_args
    core = _core()
    res = _resistors(resistor)
    delta = _number("delta_Ah", delta_Ah, positive=True)
    volts = _number("cell_V", cell_V, positive=True)
    target = _number("target_mV", target_mV, positive=True, allow_none=False)
    hours = _number("max_hours", max_hours, positive=True, allow_none=False)
    _int_arg("high_cells", high_cells)
    _bool_arg("simulate", simulate)
    if volts is not None and delta is None:
        raise ValueError("cell_V needs delta_Ah (the imbalance it applies to)")
    if preset is not None and not isinstance(preset, str):
        raise TypeError(f"preset must be a str, got {type(preset).__name__}")
    base = _path_arg("base_dir", base_dir)
    pairs = flatten_overrides(overrides, more)

    if scenario is not None and preset is not None:
        raise ValueError("give a scenario or a preset, not both")
    if scenario is None:
        scenario = core.preset_path(preset or DEFAULT_PRESET)
    source, is_file, pairs, name, base = _scenario_args(scenario, pairs, base)
    d = core.balance_time(source, is_file, pairs, res, delta, volts, high_cells, target, hours, simulate, name, base)
    rows = tuple(BalanceTimeRow(**r) for r in d.pop("rows"))
    return BalanceTimeResult(rows=rows, **d)
