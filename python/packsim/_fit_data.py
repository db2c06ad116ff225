"""Cell test data for packsim.fit: CSV files or pandas DataFrames read into arrays, checked
row by row (every problem is one FitError naming the file and line).

A test is ``time_s, current_A, voltage_V[, temp_C]`` (columns found by name, in any order,
other columns ignored); positive current discharges; time strictly increasing.
"""
from __future__ import annotations

import csv
import difflib
import math
import os
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["FitError", "FitWarning", "CellTest", "read_test", "rest_mask"]

REQUIRED = ("time_s", "current_A", "voltage_V")
OPTIONAL = ("temp_C",)
MIN_ROWS = 10
REST_MIN_S = 10.0          # a rest: |current| this small for at least this long
REST_REL_CURRENT = 0.01    # of the file's largest |current|
REST_MIN_CURRENT_A = 1e-3


class FitError(ValueError):
    """Bad test data or a fit that failed: nothing was written."""


class FitWarning(UserWarning):
    """A fit that succeeded on data that cannot determine everything (e.g. the capacity)."""


# Units a column's name may state that are not the unit packsim fit reads it in: the
# values would be a thousand (or 60, 3600) times off. Words of the name, case-sensitive
# (mA is milliamperes, MA would be megaamperes).
FOREIGN_UNITS = {"current_A": ("mA", "uA", "µA", "kA"), "voltage_V": ("mV", "kV", "uV", "µV"),
                 "time_s": ("ms", "min", "h", "hr", "hrs", "hour", "hours", "minutes"),
                 "temp_C": ("K", "F", "degF", "Kelvin", "Fahrenheit")}


@dataclass
class CellTest:
    """One test file as arrays (SI, positive current discharges)."""
    name: str
    time_s: np.ndarray
    current_A: np.ndarray
    voltage_V: np.ndarray
    temp_C: np.ndarray | None
    rows: list[str]          # where each sample is: "file:line" or "<DataFrame k>: row n"
    current_column: str = "current_A"   # the name of the current's column in the data
    reader: str = ""         # a cycler export: its format, and how its sign and units were read
    # Current steps logged at the sample they happen at, that sample reading the new current
    # (packsim's own results; a cycler logging each step's start): the current of a sample is
    # held over the interval after it. Else the mean of the interval's ends (_fit_ecm.held_current).
    steps_on_samples: bool = False

    @property
    def start_temp_C(self) -> float | None:
        """The test's temperature: temp_C at its start, the cell rested in its chamber
        (self-heating under load does not make it another test temperature)."""
        return None if self.temp_C is None else float(self.temp_C[0])


def _closest(name: str, have: list[str]) -> str:
    near = difflib.get_close_matches(name, have, n=1, cutoff=0.5)
    return f"; did you mean '{near[0]}'?" if near else ""


def _column_names(columns: dict[str, str] | None) -> dict[str, str]:
    """Our column -> the name in the data (``columns`` maps ours to theirs)."""
    names = {c: c for c in REQUIRED + OPTIONAL}
    for ours, theirs in (columns or {}).items():
        if ours not in names:
            raise FitError(f"columns: unknown column '{ours}'{_closest(ours, list(names))} "
                           f"(the columns are {', '.join(names)})")
        names[ours] = str(theirs)
    return names


def _check_units(label: str, names: dict[str, str], present: list[str]) -> None:
    """A column whose name states another unit than ours (current_mA read as current_A)."""
    for ours, theirs in names.items():
        if theirs not in present:
            continue
        words = re.findall(r"[A-Za-zµ]+", theirs)
        foreign = [w for w in words if w in FOREIGN_UNITS[ours]]
        if foreign and theirs != ours:
            unit = ours.rsplit("_", 1)[1]
            raise FitError(f"{label}: column '{theirs}' is read as {ours}, but its name says {foreign[0]}: "
                           f"packsim fit reads {ours} in {unit} (values in {foreign[0]} would be off by a factor "
                           f"of 1000 or more); convert the column to {unit} first")


def _number(text: str, where: str, column: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise FitError(f"{where}: column '{column}': '{text.strip()}' is not a number") from None
    if not math.isfinite(v):
        raise FitError(f"{where}: column '{column}': {text.strip()} is not a finite number")
    return v


def _read_csv(path: str, names: dict[str, str]) -> tuple[dict[str, np.ndarray], list[str]]:
    """Columns as lists and the location ("file:line") of every row."""
    if not os.path.isfile(path):
        raise FitError(f"{path}: no such file")
    with open(path, newline="", encoding="utf-8-sig") as f:
        lines = [(n, line) for n, line in enumerate(f, start=1)
                 if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise FitError(f"{path}: empty file (expected a header {','.join(REQUIRED)}[,temp_C])")
    header_line, header = lines[0]
    head = [h.strip() for h in next(csv.reader([header]))]
    cols = {}
    for ours, theirs in names.items():
        if theirs in head:
            cols[ours] = head.index(theirs)
        elif ours in REQUIRED:
            raise FitError(f"{path}:{header_line}: no column '{theirs}'{_closest(theirs, head)} "
                           f"(header: {', '.join(head)}; choose columns by name with columns=/--columns)")
    _check_units(path, names, head)
    body = lines[1:]
    rows = list(csv.reader([line for _, line in body]))
    where = [f"{path}:{n}" for n, _ in body]
    short = [k for k, row in enumerate(rows) if len(row) < len(head)]
    if short:
        raise FitError(f"{where[short[0]]}: {len(rows[short[0]])} fields, the header has {len(head)}")
    data = {}
    for c, k in cols.items():
        text = [row[k] for row in rows]
        try:  # numpy's own conversion; a failure is found again row by row for its message
            values = np.array(text, dtype=float)
        except ValueError:
            values = None
        if values is None or not np.all(np.isfinite(values)):
            values = np.array([_number(v, loc, names[c]) for v, loc in zip(text, where)])
        data[c] = values
    return data, where


def _read_frame(df: Any, label: str, names: dict[str, str]) -> tuple[dict[str, list[float]], list[str]]:
    head = [str(c) for c in df.columns]
    data: dict[str, list[float]] = {}
    where = [f"{label}: row {k}" for k in range(len(df))]
    _check_units(label, names, head)
    for ours, theirs in names.items():
        if theirs not in head:
            if ours in REQUIRED:
                raise FitError(f"{label}: no column '{theirs}'{_closest(theirs, head)} (columns: {', '.join(head)})")
            continue
        try:
            values = np.asarray(df[theirs], dtype=float)
        except (TypeError, ValueError):
            raise FitError(f"{label}: column '{theirs}' is not numeric") from None
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise FitError(f"{where[bad[0]]}: column '{theirs}': {values[bad[0]]} is not a finite number")
        data[ours] = list(values)
    return data, where


def read_test(source: Any, index: int, columns: dict[str, str] | None = None,
              invert_current: bool = False) -> CellTest:
    """One test from a CSV path or a pandas DataFrame, checked."""
    names = _column_names(columns)
    reader = ""
    if isinstance(source, (str, os.PathLike)):
        label = os.fspath(source)
        if not os.path.isfile(label):
            raise FitError(f"{label}: no such file")
        from ._fit_cyclers import read_cycler
        cycler = None if columns else read_cycler(label)  # --columns: the file read as a plain CSV
        if cycler is not None:
            if invert_current:
                raise FitError(f"{label}: {cycler.format} export, whose sign packsim fit takes from the format "
                               f"({cycler.note}); --invert-current / invert_current does not apply")
            data, where = cycler.columns, cycler.where
            names = dict(names, **cycler.source_columns)
            reader = f"{cycler.format} export: {cycler.note}"
        else:
            data, where = _read_csv(label, names)
    elif hasattr(source, "columns") and hasattr(source, "__getitem__"):
        label = f"<DataFrame {index}>"
        data, where = _read_frame(source, label, names)
    else:
        raise TypeError(f"test data must be a CSV path or a pandas DataFrame, got {type(source).__name__}")
    if len(where) < MIN_ROWS:
        raise FitError(f"{label}: {len(where)} data rows; a test needs at least {MIN_ROWS}")
    t = np.asarray(data["time_s"])
    step = np.diff(t)
    if (step <= 0).any():
        k = int(np.flatnonzero(step <= 0)[0]) + 1
        raise FitError(f"{where[k]}: time_s {t[k]:g} is not after the previous row's {t[k - 1]:g} "
                       "(time must increase strictly)")
    v = np.asarray(data["voltage_V"])
    bad = np.flatnonzero((v <= 0) | (v > 10))
    if bad.size:
        raise FitError(f"{where[bad[0]]}: voltage_V {v[bad[0]]:g} is outside (0, 10] V")
    i = np.asarray(data["current_A"]) * (-1.0 if invert_current else 1.0)
    temp = np.asarray(data["temp_C"]) if "temp_C" in data else None
    if temp is not None:
        bad = np.flatnonzero((temp < -60) | (temp > 150))
        if bad.size:
            raise FitError(f"{where[bad[0]]}: temp_C {temp[bad[0]]:g} is outside [-60, 150] °C")
    return CellTest(label, t, i, v, temp, where, names["current_A"], reader)


def rest_mask(test: CellTest) -> np.ndarray:
    """Samples inside a rest: |current| small for at least REST_MIN_S in a row."""
    limit = max(REST_REL_CURRENT * float(np.max(np.abs(test.current_A))), REST_MIN_CURRENT_A)
    quiet = np.abs(test.current_A) <= limit
    mask = np.zeros_like(quiet)
    k = 0
    n = quiet.size
    while k < n:
        if not quiet[k]:
            k += 1
            continue
        end = k
        while end + 1 < n and quiet[end + 1]:
            end += 1
        if test.time_s[end] - test.time_s[k] >= REST_MIN_S:
            mask[k:end + 1] = True
        k = end + 1
    return mask
