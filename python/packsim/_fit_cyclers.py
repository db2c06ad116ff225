"""Cycler exports for packsim.fit: Arbin, Maccor, Neware and BioLogic text files, the
format found from the header, columns mapped by name, units taken from the header and the
sign turned to packsim's (positive current discharges).

| format | found by | time | current | voltage | sign as logged |
|---|---|---|---|---|---|
| Arbin (MITS Pro CSV export) | `Test_Time(…)`, `Step_Index`, `Current(…)` | `Test_Time(s|h|min)` | `Current(A|mA)` | `Voltage(V|mV)` | charge positive: inverted |
| Maccor (text/CSV export) | `Rec#`, `Amps`, `Volts`, a state column `State` / `MD` | `TestTime`, `Test Time (sec)` / `(Hr)`, or `d hh:mm:ss` text | `Amps` | `Volts` | magnitude; `D` discharge, `C` charge, `R`/`O`/`S` rest |
| Neware (BTS CSV export) | `Step Type` / `Status`, `Total Time`, `Current(…)`, `Voltage(…)` | `Total Time` (`h:mm:ss`, `d-hh:mm:ss`, or seconds), `Total Time(s)` | `Current(A|mA)` | `Voltage(V|mV)` | magnitude with `…DChg` / `…Chg` / `Rest` steps, else charge positive: inverted |
| BioLogic (EC-Lab `.mpt` text) | first line `EC-Lab ASCII FILE`, `Nb header lines : N` | `time/s` | `<I>/mA`, `I/mA` (or `/A`) | `Ewe/V`, `<Ewe>/V`, `Ecell/V` | charge (oxidation) positive: inverted |

The temperature, when the file has one: Arbin `Aux_Temperature_1(C)` / `Temperature(C)`,
Maccor `Temp 1`, Neware `T1(℃)` / `Auxiliary Temperature(℃)`, BioLogic `Temperature/°C`.
Every value problem is a FitError naming the file, its line and the column. A BioLogic
binary `.mpr` is refused with the advice to export it as text.
"""
from __future__ import annotations

import csv
import re
from dataclasses import dataclass, field

import numpy as np

__all__ = ["CyclerData", "read_cycler", "detect"]

SCAN_LINES = 200  # header lines looked at for the format
# unit in a column name -> factor to packsim's unit
CURRENT_UNITS = {"A": 1.0, "mA": 1e-3, "uA": 1e-6, "µA": 1e-6}
VOLTAGE_UNITS = {"V": 1.0, "mV": 1e-3}
TIME_UNITS = {"s": 1.0, "sec": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0, "hr": 3600.0, "Hr": 3600.0}
TEMP_UNITS = {"C": 1.0, "°C": 1.0, "℃": 1.0, "degC": 1.0}


@dataclass
class CyclerData:
    """A cycler file read into packsim's columns (SI, positive current discharges)."""
    format: str
    columns: dict[str, np.ndarray]     # time_s, current_A, voltage_V[, temp_C]
    where: list[str]                   # "file:line" of every row
    source_columns: dict[str, str]     # ours -> the file's column
    note: str = ""                     # how the sign and units were read
    extra: dict[str, list[str]] = field(default_factory=dict)


def _error(msg: str):
    from ._fit_data import FitError
    return FitError(msg)


def _unit(name: str, units: dict[str, float]) -> tuple[str, float] | None:
    """The unit a column name states, `Current(mA)`, `Current (mA)`, `I/mA`, `<I>/mA`."""
    m = re.search(r"\(([^()]*)\)\s*(?:_\d+)?$", name) or re.search(r"/([^/]+)$", name)
    if not m:
        return None
    u = m.group(1).strip()
    return (u, units[u]) if u in units else (u, float("nan"))


def _find(head: list[str], patterns: list[str]) -> int | None:
    for p in patterns:
        rx = re.compile(p, re.IGNORECASE)
        for k, h in enumerate(head):
            if rx.fullmatch(h.strip()):
                return k
    return None


def _lines(path: str) -> list[str]:
    with open(path, "rb") as f:
        raw = f.read()
    for enc in ("utf-8-sig", "cp1252", "latin-1"):
        try:
            return raw.decode(enc).splitlines()
        except UnicodeDecodeError:
            continue
    return raw.decode("latin-1").splitlines()


def _split(line: str, delim: str) -> list[str]:
    return next(csv.reader([line], delimiter=delim)) if line else []


def _delimiter(line: str) -> str:
    return "\t" if line.count("\t") >= max(line.count(","), 1) else ","


def detect(path: str) -> tuple[str, int, str] | None:
    """(format, 0-based header line, delimiter) of a cycler export, or None (a plain CSV)."""
    if path.lower().endswith(".mpr"):
        raise _error(f"{path}: a BioLogic binary .mpr file: export it as text from EC-Lab (File > Export as Text, "
                     "an .mpt file) and fit that")
    lines = _lines(path)
    if lines and lines[0].strip().startswith("EC-Lab ASCII FILE"):
        for n, line in enumerate(lines[:SCAN_LINES]):
            m = re.match(r"\s*Nb header lines\s*:\s*(\d+)", line)
            if m:
                k = int(m.group(1)) - 1
                if not 0 < k < len(lines):
                    raise _error(f"{path}:{n + 1}: 'Nb header lines : {m.group(1)}' points past the file's "
                                 f"{len(lines)} lines")
                return "BioLogic", k, "\t"
        raise _error(f"{path}:1: an EC-Lab text file without its 'Nb header lines : N' line: cannot find the columns")
    for n, line in enumerate(lines[:SCAN_LINES]):
        d = _delimiter(line)
        head = [h.strip() for h in _split(line, d)]
        names = " ".join(head)
        if any(h.startswith("Test_Time") for h in head) and "Step_Index" in head \
                and any(h.startswith("Current") for h in head):
            return "Arbin", n, d
        if ("Rec#" in head or "Rec" in head) and "Amps" in head and "Volts" in head:
            return "Maccor", n, d
        if any(h in ("Step Type", "Step_Type", "Status") for h in head) and re.search(r"Current\s*\(", names) \
                and re.search(r"Voltage\s*\(", names) and any(h.startswith("Total Time") for h in head):
            return "Neware", n, d
    return None


def _clock_s(text: str) -> float | None:
    """Elapsed time as text: `hh:mm:ss(.f)`, `d hh:mm:ss`, `1d 02:03:04`, `1-02:03:04`."""
    t = text.strip()
    m = re.fullmatch(r"(?:(\d+)\s*d?\s*[- ]\s*)?(\d+):(\d{1,2}):(\d{1,2}(?:\.\d*)?)", t)
    if not m:
        return None
    days = int(m.group(1)) if m.group(1) else 0
    return days * 86400.0 + int(m.group(2)) * 3600.0 + int(m.group(3)) * 60.0 + float(m.group(4))


class _Table:
    """The rows under a header line, with their line numbers."""

    def __init__(self, path: str, lines: list[str], header: int, delim: str, decimal_comma: bool = False):
        self.path = path
        self.head = [h.strip() for h in _split(lines[header], delim)]
        self.rows, self.where = [], []
        for n in range(header + 1, len(lines)):
            if not lines[n].strip():
                continue
            row = _split(lines[n], delim)
            if len(row) < len(self.head):
                raise _error(f"{path}:{n + 1}: {len(row)} fields, the header (line {header + 1}) has {len(self.head)}")
            self.rows.append(row)
            self.where.append(f"{path}:{n + 1}")
        self.header_line = header + 1
        self.decimal_comma = decimal_comma

    def need(self, what: str, patterns: list[str], hint: str) -> int:
        k = _find(self.head, patterns)
        if k is None:
            raise _error(f"{self.path}:{self.header_line}: no {what} column ({hint}; header: {', '.join(self.head)})")
        return k

    def text(self, k: int) -> list[str]:
        return [row[k].strip() for row in self.rows]

    def numbers(self, k: int) -> np.ndarray:
        out = np.empty(len(self.rows))
        for r, row in enumerate(self.rows):
            v = row[k].strip()
            if self.decimal_comma:
                v = v.replace(",", ".")
            try:
                out[r] = float(v)
            except ValueError:
                raise _error(f"{self.where[r]}: column '{self.head[k]}': '{v}' is not a number") from None
            if not np.isfinite(out[r]):
                raise _error(f"{self.where[r]}: column '{self.head[k]}': {v} is not a finite number")
        return out

    def times(self, k: int, scale: float) -> np.ndarray:
        """Seconds from a number column (times scale) or `hh:mm:ss` text."""
        out = np.empty(len(self.rows))
        for r, row in enumerate(self.rows):
            v = row[k].strip()
            try:
                out[r] = float(v.replace(",", ".") if self.decimal_comma else v) * scale
                continue
            except ValueError:
                pass
            s = _clock_s(v)
            if s is None:
                raise _error(f"{self.where[r]}: column '{self.head[k]}': '{v}' is neither a number nor a time "
                             "(hh:mm:ss, d hh:mm:ss)")
            out[r] = s
        return out

    def scaled(self, k: int, units: dict[str, float], quantity: str, default: str | None = None) -> tuple[np.ndarray, str]:
        u = _unit(self.head[k], units)
        if u is None:
            if default is None:
                raise _error(f"{self.path}:{self.header_line}: column '{self.head[k]}' states no unit of {quantity}")
            u = (default, units[default])
        if not np.isfinite(u[1]):
            raise _error(f"{self.path}:{self.header_line}: column '{self.head[k]}': unit '{u[0]}' is not one packsim "
                         f"fit reads for {quantity} ({', '.join(units)})")
        return self.numbers(k) * u[1], u[0]


def _temperature(t: _Table, patterns: list[str]) -> tuple[np.ndarray | None, str | None]:
    k = _find(t.head, patterns)
    if k is None:
        return None, None
    values, _ = t.scaled(k, TEMP_UNITS, "temperature", default="C")
    return values, t.head[k]


def _arbin(t: _Table) -> CyclerData:
    kt = t.need("time", [r"Test_Time\s*\(.*\)"], "Test_Time(s)")
    u = _unit(t.head[kt], TIME_UNITS)
    if u is None or not np.isfinite(u[1]):
        raise _error(f"{t.path}:{t.header_line}: column '{t.head[kt]}': not a time unit packsim fit reads "
                     f"({', '.join(TIME_UNITS)})")
    ki = t.need("current", [r"Current\s*\(.*\)"], "Current(A)")
    kv = t.need("voltage", [r"Voltage\s*\(.*\)"], "Voltage(V)")
    i, iu = t.scaled(ki, CURRENT_UNITS, "current")
    v, _ = t.scaled(kv, VOLTAGE_UNITS, "voltage")
    temp, tname = _temperature(t, [r"Aux_Temperature_1\s*\(.*\)", r"Temperature\s*\(.*\)(_\d+)?",
                                   r"Aux_Temperature_\d+\s*\(.*\)"])
    cols = {"time_s": t.times(kt, u[1]), "current_A": -i, "voltage_V": v}
    src = {"time_s": t.head[kt], "current_A": t.head[ki], "voltage_V": t.head[kv]}
    if temp is not None:
        cols["temp_C"], src["temp_C"] = temp, tname
    return CyclerData("Arbin", cols, t.where, src, f"Arbin logs charge current positive: inverted; current in {iu}")


def _maccor(t: _Table) -> CyclerData:
    kt = _find(t.head, [r"Test\s*Time\s*\((sec|s)\)", r"Test\s*Time\s*\((hr|h)\)", r"Test\s*Time\s*\(min\)",
                        r"TestTime", r"Test Time"])
    if kt is None:
        raise _error(f"{t.path}:{t.header_line}: no time column (TestTime, Test Time (sec); header: "
                     f"{', '.join(t.head)})")
    u = _unit(t.head[kt], TIME_UNITS)
    scale = 1.0 if u is None else u[1]
    ki = t.need("current", [r"Amps", r"Current\s*\(A\)", r"Current"], "Amps")
    kv = t.need("voltage", [r"Volts", r"Voltage\s*\(V\)", r"Voltage"], "Volts")
    ks = t.need("state", [r"State", r"MD"], "State or MD: C charge, D discharge, R rest")
    amps, volts = t.numbers(ki), t.numbers(kv)
    state = t.text(ks)
    sign = np.empty(amps.size)
    for r, s in enumerate(state):
        c = s[:1].upper()
        if c == "D":
            sign[r] = 1.0
        elif c == "C":
            sign[r] = -1.0
        elif c in ("R", "O", "S"):
            sign[r] = 1.0
        else:
            raise _error(f"{t.where[r]}: column '{t.head[ks]}': '{s}' is not a Maccor state (C charge, D discharge, "
                         "R rest, O/S other)")
    temp, tname = _temperature(t, [r"Temp\s*1", r"Temp\s*1\s*\(.*\)", r"Temperature.*"])
    cols = {"time_s": t.times(kt, scale), "current_A": sign * np.abs(amps), "voltage_V": volts}
    src = {"time_s": t.head[kt], "current_A": t.head[ki], "voltage_V": t.head[kv]}
    if temp is not None:
        cols["temp_C"], src["temp_C"] = temp, tname
    return CyclerData("Maccor", cols, t.where, src,
                      f"Maccor logs the current's magnitude: its sign from '{t.head[ks]}' (D discharge, C charge)")


def _neware(t: _Table) -> CyclerData:
    kt = _find(t.head, [r"Total\s*Time\s*\((s|sec|h|min)\)", r"Total\s*Time", r"Test\s*Time.*"])
    if kt is None:
        raise _error(f"{t.path}:{t.header_line}: no time column (Total Time; header: {', '.join(t.head)})")
    u = _unit(t.head[kt], TIME_UNITS)
    scale = 1.0 if u is None or not np.isfinite(u[1]) else u[1]
    ki = t.need("current", [r"Current\s*\(.*\)"], "Current(mA) or Current(A)")
    kv = t.need("voltage", [r"Voltage\s*\(.*\)"], "Voltage(V)")
    ks = _find(t.head, [r"Step\s*Type", r"Step_Type", r"Status"])
    i, iu = t.scaled(ki, CURRENT_UNITS, "current")
    v, _ = t.scaled(kv, VOLTAGE_UNITS, "voltage")
    if ks is not None:
        steps = t.text(ks)
        current = np.empty(i.size)
        for r, s in enumerate(steps):
            low = s.lower().replace("_", "").replace(" ", "")
            if "dchg" in low or "discharge" in low:
                current[r] = abs(i[r])
            elif "chg" in low or "charge" in low:
                current[r] = -abs(i[r])
            elif "rest" in low or "pause" in low:
                current[r] = -i[r]
            else:
                raise _error(f"{t.where[r]}: column '{t.head[ks]}': '{s}' is not a step type packsim fit knows "
                             "(…DChg discharge, …Chg charge, Rest)")
        note = f"Neware: the sign from '{t.head[ks]}' (DChg discharge, Chg charge); current in {iu}"
    else:
        current = -i
        note = f"Neware logs charge current positive: inverted; current in {iu}"
    temp, tname = _temperature(t, [r"T1\s*\(.*\)", r"Auxiliary\s*Temperature.*", r"Temperature.*"])
    cols = {"time_s": t.times(kt, scale), "current_A": current, "voltage_V": v}
    src = {"time_s": t.head[kt], "current_A": t.head[ki], "voltage_V": t.head[kv]}
    if temp is not None:
        cols["temp_C"], src["temp_C"] = temp, tname
    return CyclerData("Neware", cols, t.where, src, note)


def _biologic(t: _Table) -> CyclerData:
    kt = t.need("time", [r"time/s"], "time/s")
    ki = t.need("current", [r"<I>/m?A", r"I/m?A"], "<I>/mA or I/mA")
    kv = t.need("voltage", [r"Ewe/V", r"<Ewe>/V", r"Ecell/V", r"<Ecell>/V"], "Ewe/V")
    i, iu = t.scaled(ki, CURRENT_UNITS, "current")
    temp, tname = _temperature(t, [r"Temperature/°C", r"Temperature/C", r"Temperature.*"])
    cols = {"time_s": t.numbers(kt), "current_A": -i,
            "voltage_V": t.numbers(kv)}
    src = {"time_s": t.head[kt], "current_A": t.head[ki], "voltage_V": t.head[kv]}
    if temp is not None:
        cols["temp_C"], src["temp_C"] = temp, tname
    return CyclerData("BioLogic", cols, t.where, src,
                      f"BioLogic logs charge (oxidation) current positive: inverted; current in {iu}")


def read_cycler(path: str) -> CyclerData | None:
    """The file as packsim columns if it is a cycler export, else None (a plain CSV)."""
    found = detect(path)
    if found is None:
        return None
    fmt, header, delim = found
    lines = _lines(path)
    decimal_comma = False
    if fmt == "BioLogic" and header + 1 < len(lines):
        first = _split(lines[header + 1], delim)
        decimal_comma = any(re.fullmatch(r"-?\d+,\d+(E[-+]?\d+)?", f.strip()) for f in first)
    t = _Table(path, lines, header, delim, decimal_comma)
    return {"Arbin": _arbin, "Maccor": _maccor, "Neware": _neware, "BioLogic": _biologic}[fmt](t)
