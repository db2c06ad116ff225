"""``packsim.balance_time``: how long passive balancing takes per resistor, as
``packsim balance-time`` computes it (core/balance/balance_time.hpp, docs/balancing.md).

    bt = packsim.balance_time(resistor=[22, 33, 47, 68, 100], when="always")  # bench_6s_balancing
    bt = packsim.balance_time(preset="motorcycle_110s_balancing", resistor=[22, 33, 47],
                              delta_Ah=2, cell_V=3.9, high_cells=36)
    bt.table                        # a pandas DataFrame, one row per resistor
    print(bt)                       # the CLI's table, notes and legend
    packsim.plot.balance_time(bt)   # time to balance and peak board temperature vs R

For each resistor: the analytic estimates (constant current V/(R+Rds_on), and the OCV-droop
form (R+Rds_on)·∫dQ/OCV(Q)) and the full co-simulation with the firmware as the scenario
configures it: when it declared itself balanced (firmware_h) and when the true rest
voltages came within target_mV (true_h).
"""
from __future__ import annotations

import math
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, fields
from typing import Any

from ._overrides import flatten_overrides

__all__ = ["balance_time", "BalanceTimeResult", "BalanceTimeRow", "DEFAULT_PRESET"]

DEFAULT_PRESET = "bench_6s_balancing"  # what `packsim balance-time` uses without a scenario
WHEN = ("charging", "rest", "charging_or_rest", "always")


@dataclass(frozen=True)
class BalanceTimeRow:
    """One resistor. Per-cell current and power at cell_V; times in hours (NaN: never)."""
    resistor_ohm: float
    branch_ohm: float          # resistor + FET Rds_on
    current_A: float
    power_W: float
    board_power_W: float       # the most loaded board, every high cell on it balancing at cell_V
    resistor_W: float          # in the resistor at the cell's v_max_V
    within_rating: bool        # resistor_W <= hardware.balancing.resistor_power_rating_W
    const_I_all_h: float       # all of ΔQ / (V_cell / (R + Rds_on))
    const_I_to_target_h: float  # the charge until the high OCV is within target_mV of the low, / I
    droop_to_target_h: float   # (R + Rds_on)·∫dQ/OCV(Q) until within target_mV (true_h's criterion)
    board_steady_C: float      # T_amb + board_power_W / G of the board node (NaN without one)
    simulated: bool
    firmware_h: float          # the firmware declared balanced (NaN: never; firmware_note says why)
    firmware_note: str
    true_h: float              # the true rest voltages within target_mV
    end_reason: str
    peak_board_C: float        # the hottest board; NaN without a board thermal node
    board_peak_C: tuple        # per monitor board
    paused_fraction: float     # time paused on board temperature (to true_h)
    bled_Ah: float             # every coulomb through the resistors
    pack_useful_Ah: float      # Σ over cells of what each bled up to its charge above the lowest group's rest voltage
    pack_wasted_Ah: float      # Σ over cells of what each bled beyond that
    needed_Ah: float
    pack_heat_Wh: float        # Σ over the balancing branches
    final_spread_Ah: float     # largest minus smallest series-group charge at the end
    final_imbalance_Ah: float  # the most charge a group holds above the lowest group's rest voltage at the end
    tripped: bool
    within_limits: bool        # target reached, no trip, resistor within its rating
    fastest: bool              # the fastest row within limits
    charge_h: float            # during charge: the charge's length (NaN otherwise)
    charge_without_h: float
    charge_added_h: float


@dataclass(frozen=True)
class BalanceTimeResult:
    scenario: str
    delta_Ah: float            # imbalance to remove per high cell (given), or the scenario's highest group's
    delta_given: bool          # delta_Ah and high_cells given; else the scenario's own imbalance
    cell_V: float
    high_cells: int            # high series groups (given, or those the firmware bleeds at the start)
    target_mV: float
    resistor_rating_W: float   # 0: not stated
    board_max_C: float
    when: str                  # bms.balancing.when as simulated
    when_overridden: bool
    during_charge: bool
    warnings: tuple[str, ...]  # config_warning events of the runs
    text: str                  # the CLI's table
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
        return self.text


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


# The checks of balance-time's options are the CLI's, in its flags' names: said back in
# the names of this function's arguments (a Python user never wrote "--high-cells").
_ARG_OF_FLAG = {"--resistor": "resistor", "--delta-Ah": "delta_Ah", "--cell-V": "cell_V",
                "--high-cells": "high_cells", "--target-mV": "target_mV", "--max-hours": "max_hours",
                "--when": "when", "--during-charge": "during_charge"}
_FLAG = re.compile("|".join(re.escape(f) for f in sorted(_ARG_OF_FLAG, key=len, reverse=True)) + r"\b")


def _python_names(e: ValueError) -> ValueError:
    if type(e) is not ValueError:  # a ScenarioError names the scenario's keys, with its fields
        return e
    text = _FLAG.sub(lambda m: _ARG_OF_FLAG[m.group(0)], str(e))
    return e if text == str(e) else type(e)(text)


def _resistors(resistor: Any) -> list[float]:
    if resistor is None:
        return []
    if getattr(resistor, "ndim", None) == 0:  # a 0-d NumPy array: the number it holds
        resistor = resistor.item()
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
                 cell_V: float | None = None, high_cells: int = 1, target_mV: float | None = None,
                 max_hours: float = 72.0, simulate: bool = True, when: str | None = None,
                 during_charge: bool = False,
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
    target_mV:  truth criterion: true_h is when the rest voltages' max - min is below this
                (it measures; the firmware keeps its own thresholds); default: 1.5 x
                the firmware's own stop_delta_mV (the truth settles about at that threshold).
    max_hours:  simulation cap.
    simulate:   False: the analytic estimates only (the CLI's ``--analytic-only``).
    when:       replace the firmware's bms.balancing.when (``--when``), e.g. "always" for a
                firmware that balances only on the charger; stated in the result.
    during_charge: balance on the scenario's CC-CV charger (``--during-charge``): top
                balancing, and the charge time balancing adds.
    """
    from . import _bool_arg, _core, _int_arg, _path_arg, _scenario_args
    core = _core()
    res = _resistors(resistor)
    delta = _number("delta_Ah", delta_Ah, positive=True)
    volts = _number("cell_V", cell_V, positive=True)
    target = _number("target_mV", target_mV, positive=True)
    hours = _number("max_hours", max_hours, positive=True, allow_none=False)
    _int_arg("high_cells", high_cells)
    _bool_arg("simulate", simulate)
    _bool_arg("during_charge", during_charge)
    if when is not None and when not in WHEN:
        raise ValueError(f"when must be one of {', '.join(WHEN)}, got {when!r}")
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
    try:
        d = core.balance_time(source, is_file, pairs, res, delta, volts, high_cells, target, hours, simulate, when,
                              during_charge, name, base)
    except ValueError as e:
        renamed = _python_names(e)
        if renamed is e:
            raise
        raise renamed from None
    rows = tuple(BalanceTimeRow(**r) for r in d.pop("rows"))
    return BalanceTimeResult(rows=rows, **d)


def _plot_csv(argv: list[str] | None = None) -> int:
    """``python -m packsim.balance_plot CSV PNG``: the figure ``packsim balance-time --plot`` writes."""
    import argparse
    import csv
    p = argparse.ArgumentParser(prog="packsim balance-time --plot")
    p.add_argument("csv")
    p.add_argument("png")
    p.add_argument("--title", default="")
    p.add_argument("--board-max-C", type=float, default=math.nan)
    a = p.parse_args(argv)
    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    cols = {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}
    from .plot import balance_time_figure
    fig = balance_time_figure(cols, title=a.title, board_max_C=a.board_max_C)
    fig.savefig(a.png, dpi=120)
    return 0
