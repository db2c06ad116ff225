"""Results in the formats other tools read: ``packsim export result.h5 --format csv``.

    packsim.export("race.h5", "csv")                # -> race_csv/{samples,events,summary}.csv
    packsim.export(r, "mat", "race.mat")            # MATLAB (scipy.io.savemat)
    packsim.export(r, "parquet")                    # -> <name>.parquet (pyarrow, via pandas)

csv      a folder: samples.csv (one row per sample, column per 1-D dataset and per
         channel of 2-D ones, ``truth/cell_voltage_V[3]`` 1-based), events.csv,
         summary.csv (name, value) and one file per other table of the result
         (``bus_trace.csv``, ``vehicle_laps.csv``, ``vehicle_stages.csv``, ...) and
         per group of datasets over another axis (``inputs.csv``: a batch case's
         drawn cell values, one row per cell)
mat      one variable per dataset, named by path with "/" -> "_"
         (``truth_cell_voltage_V``, [samples, channels]); ``events``, ``summary`` and
         every other table as structs of columns, ``attrs`` with the file's attributes
         (scenario_yaml, seed, ...)
parquet  the samples table (columns as in csv); the file's attributes, the summary,
         the events and the other tables (``inputs`` too) as JSON in the schema's
         key-value metadata

Values are exported as stored (firmware units stay mV, 0.1 degC, ... as in their names).
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
from typing import Any

import numpy as np

from ._export_output import ExportOutputError, check_output, temporary_name
from .result import NotAResultError, Result, _need, load

__all__ = ["export", "FORMATS"]

FORMATS = ("csv", "mat", "parquet")


def _default_output(source: str | None, name: str, fmt: str) -> str:
    stem = os.path.splitext(source)[0] if source else name
    return stem + ("_csv" if fmt == "csv" else "." + fmt)


def _json_default(v: Any) -> Any:
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray):
        return v.tolist()
    return str(v)


def _tables(r: Result) -> dict[str, np.ndarray]:
    """The result's tables other than the events (compound datasets: the bus trace, the
    vehicle's laps and stages, ...) by their path in the file."""
    return {path: a for path, a in r.datasets.items() if a.dtype.names and path != "events"}


def _axis_tables(r: Result) -> dict[str, dict[str, np.ndarray]]:
    """Datasets over an axis other than time -- a batch case's drawn cell values,
    /inputs/cell_capacity_Ah ... on `cell` (docs/results.md) -- as tables, one per group
    and axis, one row per element: the axis (1-based, named as its dimension scale), then
    each dataset by name. The samples table holds only channels over time, so without
    these they would be left out of csv and parquet. A table is named by its group
    (``inputs``), or group_axis where a group has datasets on several axes."""
    by_axis: dict[tuple[str, str], dict[str, np.ndarray]] = {}
    for path, a in r.datasets.items():
        if a.dtype.names or a.ndim != 1 or "/" not in path or r._on_time(path, a):
            continue
        group, name = path.rsplit("/", 1)
        axis = (r._file_dims(path) or ("",))[0] or f"{name}_index"
        cols = by_axis.setdefault((group, axis), {axis: np.arange(1, a.shape[0] + 1, dtype=np.int32)})
        cols[name] = a  # one axis, one length: the dimension scale's
    groups = [g for g, _ in by_axis]
    return {(g if groups.count(g) == 1 else f"{g}_{axis}").replace("/", "_"): cols
            for (g, axis), cols in by_axis.items()}


def _table_name(path: str) -> str:
    return path.replace("/", "_")


def _columns(a: np.ndarray) -> dict[str, np.ndarray]:
    return {n: (np.array([str(x) for x in a[n]], dtype=object) if a.dtype[n].kind == "O" else np.asarray(a[n]))
            for n in a.dtype.names}


def _to_csv(r: Result, out: str) -> list[str]:
    pd = _need("pandas")
    os.makedirs(out, exist_ok=True)
    files = [os.path.join(out, n) for n in ("samples.csv", "events.csv", "summary.csv")]
    r.to_dataframe("samples").to_csv(files[0])
    r.to_dataframe("events").to_csv(files[1], index=False)
    pd.DataFrame({"name": list(r.summary), "value": list(r.summary.values())}).to_csv(files[2], index=False)
    for path, a in _tables(r).items():
        files.append(os.path.join(out, _table_name(path) + ".csv"))
        pd.DataFrame(_columns(a)).to_csv(files[-1], index=False)
    for name, cols in _axis_tables(r).items():
        files.append(os.path.join(out, name + ".csv"))
        pd.DataFrame(cols).to_csv(files[-1], index=False)
    return files


def _to_mat(r: Result, out: str) -> list[str]:
    try:
        from scipy.io import savemat
    except ImportError as e:
        raise ImportError("exporting to .mat needs scipy (pip install scipy)") from e
    data: dict[str, Any] = {}
    tables = _tables(r)
    for path, a in r.datasets.items():
        if path == "events" or path in tables:
            continue
        data[path.replace("/", "_")] = np.asarray(a)
    for path, a in tables.items():
        data[_table_name(path)] = _columns(a)
    ev = r.events_array
    data["events"] = {"time_s": np.asarray(ev["time_s"], dtype=float),
                      "kind": np.array([str(x) for x in ev["kind"]], dtype=object),
                      "detail": np.array([str(x) for x in ev["detail"]], dtype=object)}
    data["summary"] = {k: v for k, v in r.summary.items()}
    data["attrs"] = {k: v for k, v in r.attrs.get("", {}).items()}
    savemat(out, data, appendmat=False, long_field_names=True, do_compression=True, oned_as="column")
    return [out]


# Parquet keeps key-value metadata in the file's footer, which readers decode whole:
# Arrow (pyarrow, pandas, Polars, DuckDB's Arrow path) refuses a footer whose strings
# exceed 100 MB ("Couldn't deserialize thrift: ... Exceeded size limit"). A long run's
# monitor-bus trace as JSON passes that (a 40-minute race: 185 MB), and the file
# written would be one no reader opens. Below this, with room for the schema's own text.
_PARQUET_METADATA_LIMIT = 90_000_000


def _metadata_too_big(meta: dict[bytes, bytes], tables: dict[str, np.ndarray]) -> str | None:
    """The error text when the footer's metadata would pass what readers accept, else None."""
    total = sum(len(k) + len(v) for k, v in meta.items())
    if total <= _PARQUET_METADATA_LIMIT:
        return None
    rows = ", ".join(f"{path} ({len(a):,} rows)" for path, a in tables.items())
    return (f"the metadata of this result ({total / 1e6:,.0f} MB as JSON"
            + (f"; its tables: {rows}" if rows else "") + ") is more than a Parquet footer holds for its "
            f"readers ({_PARQUET_METADATA_LIMIT / 1e6:,.0f} MB; Arrow refuses a larger one): nothing written; "
            "export it as csv (one file per table) or mat")


def _to_parquet(r: Result, out: str) -> list[str]:
    _need("pyarrow")
    import pyarrow as pa
    import pyarrow.parquet as pq
    table = pa.Table.from_pandas(r.to_dataframe("samples"), preserve_index=True)
    meta = dict(table.schema.metadata or {})
    meta[b"packsim.attrs"] = json.dumps(r.attrs.get("", {}), default=_json_default).encode()
    meta[b"packsim.summary"] = json.dumps(r.summary, default=_json_default).encode()
    meta[b"packsim.events"] = json.dumps(r.events, default=_json_default).encode()
    others = _tables(r)
    tables = {path: [dict(zip(a.dtype.names, row)) for row in a.tolist()] for path, a in others.items()}
    for name, cols in _axis_tables(r).items():
        tables[name] = [dict(zip(cols, row)) for row in zip(*(c.tolist() for c in cols.values()))]
    meta[b"packsim.tables"] = json.dumps(tables, default=_json_default).encode()
    too_big = _metadata_too_big(meta, others)
    if too_big:
        raise ValueError(too_big)
    pq.write_table(table.replace_schema_metadata(meta), out)
    return [out]


_WRITERS = {"csv": _to_csv, "mat": _to_mat, "parquet": _to_parquet}


def export(result: Result | str | os.PathLike, format: str, output: str | os.PathLike | None = None) -> list[str]:
    """Write a result (a Result or a result HDF5 file) as csv, mat or parquet; returns
    the files written. output: the file (mat, parquet) or folder (csv); default next
    to the result file (or named after the scenario for a run not saved)."""
    from . import _path_arg
    if format not in _WRITERS:
        raise ValueError(f"format must be one of {', '.join(FORMATS)}, not {format!r}")
    if not isinstance(result, (Result, str, os.PathLike)):
        raise TypeError(f"result must be a packsim.Result or a result file path, got {type(result).__name__}")
    output = _path_arg("output", output)
    r = result if isinstance(result, Result) else load(result)
    out = output if output is not None else _default_output(r.source, r.scenario_name, format)
    parent = os.path.dirname(os.path.abspath(out))
    os.makedirs(parent, exist_ok=True)
    check_output(out, format, r.source)
    # Written under a temporary name of its own and renamed when complete: a failed
    # export leaves nothing half-written behind. An earlier CSV export (check_output: only
    # that) is replaced whole.
    tmp = temporary_name(out, format)
    try:
        written = _WRITERS[format](r, tmp)
        if format == "csv" and os.path.isdir(out):
            shutil.rmtree(out)
        os.replace(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True) if os.path.isdir(tmp) else (os.path.exists(tmp) and os.remove(tmp))
        raise
    return [out + f[len(tmp):] for f in written]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="packsim export", description="convert a packsim result file")
    ap.add_argument("result", help="result HDF5 file")
    ap.add_argument("--format", required=True, choices=FORMATS)
    ap.add_argument("-o", "--output", help="output file (mat, parquet) or folder (csv)")
    a = ap.parse_args(argv)
    if not os.path.isfile(a.result):
        print(f"packsim export: error: {a.result}: no such result file", file=sys.stderr)
        return 2
    try:
        files = export(a.result, a.format, a.output)
    except (NotAResultError, ExportOutputError) as e:  # bad input: exit 2, as every command
        print(f"packsim export: error: {e}", file=sys.stderr)
        return 2
    except (ImportError, OSError, ValueError) as e:
        print(f"packsim export: error: {e}", file=sys.stderr)
        return 1
    for f in files:
        print(f)
    return 0


if __name__ == "__main__":
    sys.exit(main())
