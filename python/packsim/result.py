"""One simulation result, from ``packsim.run`` or from a result HDF5 file.

Both hold the same thing: every dataset of the HDF5 layout (docs/results.md) under its
path (``"time_s"``, ``"truth/cell_voltage_V"``, ``"bms/state"``, ...) as a read-only
NumPy array, the attributes of the file, its groups and datasets, and the events
table. Nothing is hard-wired: a dataset the C++ writer gains appears here unchanged.
"""
from __future__ import annotations

import io
import os
from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np

from ._atomic import replaced_when_done

__all__ = ["Result", "load", "NotAResultError"]

EVENTS = "events"
_EVENT_DTYPE = np.dtype([("time_s", "<f8"), ("kind", object), ("detail", object)])
BUS_TRACE = "bus_trace"


def _text(v: Any) -> Any:
    if isinstance(v, (bytes, np.bytes_)):
        return v.decode("utf-8")
    if isinstance(v, np.ndarray) and v.dtype.kind in "SO" and v.ndim <= 1:
        return [_text(x) for x in v.tolist()]
    if isinstance(v, np.generic):
        return v.item()
    return v


# HDF5's dimension-scale bookkeeping (docs/results.md, "netCDF layout"): structure, not
# metadata a user reads, and object references h5py cannot write back as they are.
_LAYOUT_ATTRS = frozenset({"CLASS", "NAME", "REFERENCE_LIST", "DIMENSION_LIST", "_Netcdf4Dimid",
                           "_Netcdf4Coordinates"})


def _attrs(h5attrs) -> dict[str, Any]:
    return {k: _text(h5attrs[k]) for k in h5attrs.keys() if k not in _LAYOUT_ATTRS}


def _is_scale(obj) -> bool:
    c = obj.attrs.get("CLASS")
    return c is not None and _text(c) == "DIMENSION_SCALE"


def _read_dataset(ds) -> np.ndarray:
    a = ds[()]
    if not isinstance(a, np.ndarray):
        a = np.asarray(a)
    if a.dtype.names:  # compound (the events table): variable-length strings -> str
        fields = []
        for name in a.dtype.names:
            col = a[name]
            if col.dtype.kind in "OS":
                fields.append((name, object))
            else:
                fields.append((name, col.dtype))
        out = np.empty(a.shape, dtype=fields)
        for name in a.dtype.names:
            col = a[name]
            out[name] = [_text(x) for x in col] if col.dtype.kind in "OS" else col
        a = out
    elif a.dtype.kind == "O":
        a = np.array([_text(x) for x in a.ravel()], dtype=object).reshape(a.shape)
    a.setflags(write=False)
    return a


def _read_h5(path: str | os.PathLike | io.BytesIO, prefer: Mapping[str, np.ndarray] | None = None):
    """(datasets, attrs, dims) of a result file; dims: each dataset's dimension names
    (its attached dimension scales, docs/results.md "netCDF layout"). Datasets in `prefer`
    with the same shape and dtype as in the file are taken from there instead of being
    read (no copy)."""
    try:
        import h5py
    except ImportError as e:  # pragma: no cover - h5py is a dependency
        raise ImportError("reading packsim results needs h5py (pip install h5py)") from e
    prefer = prefer or {}
    datasets: dict[str, np.ndarray] = {}
    attrs: dict[str, dict[str, Any]] = {}
    dims: dict[str, tuple[str, ...]] = {}
    with h5py.File(path, "r") as f:
        attrs[""] = _attrs(f.attrs)

        # Walked by link name, not by object: /time_s is also linked as /truth/time_s
        # (one dataset, several names). Dimension scales other than /time_s are the
        # coordinates of the netCDF layout, not results.
        def walk(group, prefix: str) -> None:
            for key in sorted(group.keys()):
                obj = group[key]
                name = prefix + key
                if isinstance(obj, h5py.Dataset) and _is_scale(obj) and name != "time_s":
                    continue
                a = _attrs(obj.attrs)
                if a:
                    attrs[name] = a
                if isinstance(obj, h5py.Group):
                    walk(obj, name + "/")
                    continue
                dims[name] = _dim_names(obj)
                p = prefer.get(name)
                if p is not None and p.shape == obj.shape and p.dtype == obj.dtype:
                    datasets[name] = p
                else:
                    datasets[name] = _read_dataset(obj)

        walk(f, "")
    return datasets, attrs, dims


def _dim_names(ds) -> tuple[str, ...]:
    """The names of the dimension scales attached to each axis of an h5py dataset
    ("" for an axis without one)."""
    out = []
    for d in ds.dims:
        try:
            out.append(d[0].name.rsplit("/", 1)[-1] if len(d) else "")
        except (KeyError, IndexError, RuntimeError):
            out.append("")
    return tuple(out)


# What every file `packsim run` writes has (docs/results.md): without them a file is
# some other HDF5 (or no HDF5 at all), and reading on would fail later, far from here,
# with a KeyError naming a dataset rather than the file.
_RESULT_ROOT_ATTR = "packsim_version"
_RESULT_DATASETS = ("time_s",)


class NotAResultError(ValueError):
    """The file exists but is not a packsim result file (not HDF5, or not packsim's layout)."""


def load(path: str | os.PathLike) -> "Result":
    """Read a result HDF5 file written by ``packsim run`` or ``Result.save``.

    FileNotFoundError when there is no such file; NotAResultError (a ValueError) naming
    the file when it is not HDF5 or not a packsim result."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"no such result file: {path}")
    try:
        datasets, attrs, dims = _read_h5(path)
    except OSError as e:  # h5py: not an HDF5 file, truncated, unreadable
        raise NotAResultError(f"{path}: not a packsim result file (HDF5 could not open it: {e})") from e
    missing = [d for d in _RESULT_DATASETS if d not in datasets]
    if _RESULT_ROOT_ATTR not in attrs.get("", {}) or missing:
        what = (f"no /{', /'.join(missing)}" if missing else f"no root attribute {_RESULT_ROOT_ATTR}")
        raise NotAResultError(f"{path}: not a packsim result file ({what}; an HDF5 file that packsim run did not write)")
    return Result(datasets, attrs, source=path, dims=dims)


def _from_handle(handle) -> "Result":
    """A Result around a C++ run. The recorded arrays are NumPy views into the C++
    result (no copy). Attributes, the events table, the summary and any dataset the
    binding does not list come from the C++ HDF5 writer itself, which builds the file
    in memory (nothing is written to disk), so names, shapes, dtypes and metadata are
    exactly those of ``packsim run``'s file. That file is built and read the first time
    any of them is asked for: a loop that only reads recorded arrays never pays for it."""
    views = handle.arrays()
    return Result(views, None, handle=handle,
                  complete=lambda: _read_h5(io.BytesIO(handle.image()), prefer=views))


class Result:
    """A packsim result: ``r["truth/cell_voltage_V"]`` is a [samples, cells] array.

    Groups are dicts too: ``r.truth["cell_soc"]``, ``r.bms["state"]``. ``r.summary`` is
    the run summary, ``r.events`` the events as dicts, ``r.scenario_yaml`` and
    ``r.seed`` say what ran. Units are in the dataset names and in ``r.units(path)``.
    """

    def __init__(self, datasets: Mapping[str, np.ndarray], attrs: Mapping[str, Mapping[str, Any]] | None,
                 *, handle=None, source: str | None = None, complete=None,
                 dims: Mapping[str, tuple[str, ...]] | None = None) -> None:
        # complete: returns (datasets, attrs) of the whole result, called on first need;
        # until then `datasets` are the ones at hand (the same arrays it will list).
        self._at_hand = dict(datasets)
        self._complete = complete
        self._ds = None if complete else self._at_hand
        self._at = None if complete else {k: dict(v) for k, v in (attrs or {}).items()}
        self._handle = handle
        self.source = source
        self._dims = dict(dims or {})  # dataset path -> its dimension names in the file

    def _load(self) -> None:
        datasets, attrs, dims = self._complete()
        self._ds, self._at, self._complete = datasets, attrs, None
        self._dims = dims

    @property
    def _datasets(self) -> dict[str, np.ndarray]:
        if self._ds is None:
            self._load()
        return self._ds

    @property
    def _attrs(self) -> dict[str, dict[str, Any]]:
        if self._at is None:
            self._load()
        return self._at

    def _dataset(self, key: str) -> np.ndarray:
        a = self._at_hand.get(key) if self._ds is None else None
        return a if a is not None else self._datasets[key]

    # --- datasets -----------------------------------------------------------------
    @property
    def datasets(self) -> dict[str, np.ndarray]:
        """Every dataset by HDF5 path (a new dict; the arrays are shared, read-only)."""
        return dict(self._datasets)

    @property
    def attrs(self) -> dict[str, dict[str, Any]]:
        """Attributes by HDF5 path; ``""`` is the file root, ``"summary"`` the summary."""
        return {k: dict(v) for k, v in self._attrs.items()}

    def keys(self) -> list[str]:
        return list(self._datasets)

    def __getitem__(self, path: str) -> np.ndarray:
        try:
            return self._dataset(path.strip("/"))
        except KeyError:
            raise KeyError(f"no dataset {path!r} in this result; it has: {', '.join(self._datasets)}") from None

    def __contains__(self, path: object) -> bool:
        return isinstance(path, str) and path.strip("/") in self._datasets

    def __iter__(self) -> Iterator[str]:
        return iter(self._datasets)

    def get(self, path: str, default: Any = None) -> Any:
        try:
            return self._dataset(path.strip("/"))
        except KeyError:
            return default

    def group(self, name: str) -> dict[str, np.ndarray]:
        """The datasets directly inside group `name`, by their short names."""
        prefix = name.strip("/") + "/"
        return {k[len(prefix):]: v for k, v in self._datasets.items()
                if k.startswith(prefix) and "/" not in k[len(prefix):]}

    @property
    def truth(self) -> dict[str, np.ndarray]:
        return self.group("truth")

    @property
    def measured(self) -> dict[str, np.ndarray]:
        return self.group("measured")

    @property
    def bms(self) -> dict[str, np.ndarray]:
        return self.group("bms")

    def units(self, path: str) -> str | None:
        """The dataset's unit (None: it has none, e.g. a flag); a path that is no dataset
        of this result is the KeyError ``r[path]`` raises, not None (a typo read as
        "no unit")."""
        self[path]
        return self._attrs.get(path.strip("/"), {}).get("units")

    @property
    def time_s(self) -> np.ndarray:
        return self._dataset("time_s")

    time = time_s

    @property
    def n_samples(self) -> int:
        return int(self.time_s.shape[0])

    @property
    def n_cells(self) -> int:
        return int(self._dataset("truth/cell_voltage_V").shape[1])

    @property
    def n_series(self) -> int:
        """Series positions the monitor ICs read (one voltage per parallel group)."""
        return int(self._dataset("measured/cell_voltage_mV").shape[1])

    @property
    def n_thermistors(self) -> int:
        return int(self._dataset("measured/temperature_dC").shape[1])

    # --- metadata ------------------------------------------------------------------
    @property
    def summary(self) -> dict[str, Any]:
        return dict(self._attrs.get("summary", {}))

    @property
    def events_array(self) -> np.ndarray:
        """The events table as a structured array (time_s, kind, detail)."""
        ev = self._datasets.get(EVENTS)
        return ev if ev is not None else np.empty(0, dtype=_EVENT_DTYPE)

    @property
    def bus_trace(self) -> np.ndarray:
        """The monitor-bus transactions (scenario ``output.bus_trace: true``) as a
        structured array: ``time_s``, ``bus``, ``direction`` ("out" MCU -> part, "in"),
        ``count``, ``bytes`` (hex), ``what`` (the part's decoding); docs/results.md.
        Raises KeyError when the run did not trace its buses."""
        tr = self._datasets.get(BUS_TRACE)
        if tr is None:
            raise KeyError("no bus trace in this result: run the scenario with output.bus_trace: true")
        return tr

    @property
    def events(self) -> list[dict[str, Any]]:
        ev = self.events_array
        return [{name: (float(row[name]) if name == "time_s" else row[name]) for name in ev.dtype.names}
                for row in ev]

    def _root(self, key: str, default: Any = None) -> Any:
        return self._attrs.get("", {}).get(key, default)

    @property
    def scenario_yaml(self) -> str:
        return self._root("scenario_yaml", "")

    @property
    def scenario_name(self) -> str:
        return self._root("scenario_name", "")

    @property
    def seed(self) -> int:
        return int(self._root("seed", 0))

    @property
    def version(self) -> str:
        return self._root("packsim_version", "")

    @property
    def fault_names(self) -> list[str]:
        """Fault bit i of ``bms/fault_active`` / ``fault_latched`` is ``fault_names[i]``."""
        bits = self._attrs.get("bms", {}).get("fault_bits", "")
        return [b for b in bits.split(",") if b] if isinstance(bits, str) else list(bits)

    def faults(self, which: str = "latched") -> dict[str, np.ndarray]:
        """{fault name: bool array over samples} from ``bms/fault_<which>``."""
        if which not in ("active", "latched"):  # not "no dataset 'bms/fault_latchd'", a name never typed
            raise ValueError(f"which must be 'active' or 'latched', not {which!r}")
        word = self[f"bms/fault_{which}"].astype(np.uint64)
        return {name: ((word >> np.uint64(i)) & np.uint64(1)).astype(bool)
                for i, name in enumerate(self.fault_names)}

    def __repr__(self) -> str:
        s = self.summary
        trip = f", tripped at {s.get('trip_time_s'):.1f} s ({s.get('trip_reason')})" if s.get("tripped") else ""
        where = f" from {self.source}" if self.source else ""
        return (f"<packsim.Result {self.scenario_name!r} seed={self.seed}: {self.n_samples} samples, "
                f"{self.n_cells} cells, {len(self._datasets)} datasets{trip}{where}>")

    # --- export --------------------------------------------------------------------
    def save(self, path: str | os.PathLike) -> None:
        """Write the result as HDF5. A result of ``packsim.run`` is written by the C++
        writer, byte for byte what ``packsim run -o`` writes; a loaded result is written
        back with h5py (same datasets, dtypes and attributes)."""
        path = os.fspath(path)
        if self._handle is not None:
            self._handle.save(path)
        else:
            _write_h5(path, self._datasets, self._attrs)

    def to_dataframe(self, kind: str = "samples"):
        """A pandas DataFrame.

        kind="samples": one row per sample indexed by time_s; a column per 1-D dataset
        (by path) and per channel of 2-D ones (``"truth/cell_voltage_V[3]"``, 1-based).
        kind="cells": tidy, one row per (time_s, cell) with a column per per-cell
        dataset of ``truth/`` (``cell_voltage_V``, ``cell_soc``, ...).
        kind="events": the events table.
        kind="bus_trace": the monitor-bus transactions (``output.bus_trace: true``).
        """
        pd = _need("pandas")
        if kind == "events":
            ev = self.events_array
            return pd.DataFrame({n: ev[n] for n in ev.dtype.names})
        if kind == "bus_trace":
            tr = self.bus_trace
            return pd.DataFrame({n: tr[n] for n in tr.dtype.names})
        t = self.time_s
        n = t.shape[0]
        if kind == "samples":
            cols: dict[str, np.ndarray] = {}
            for path, a in self._datasets.items():
                if path == "time_s" or not self._on_time(path, a):
                    continue
                if a.ndim == 1:
                    cols[path] = a
                elif a.ndim == 2:
                    for j in range(a.shape[1]):
                        cols[f"{path}[{j + 1}]"] = a[:, j]
            return pd.DataFrame(cols, index=pd.Index(t, name="time_s"))
        if kind == "cells":
            cells = self.n_cells
            cols = {"time_s": np.repeat(t, cells), "cell": np.tile(np.arange(1, cells + 1), n)}
            for name, a in self.truth.items():
                if a.ndim == 2 and a.shape == (n, cells):
                    cols[name] = a.reshape(-1)
            return pd.DataFrame(cols)
        raise ValueError(f"kind must be 'samples', 'cells', 'events' or 'bus_trace', not {kind!r}")

    def _on_time(self, path: str, a: np.ndarray) -> bool:
        """Whether a dataset is a channel over the samples (its first axis is /time_s).
        By the file's dimension scales where there are any: a batch case's per-cell
        /inputs (axis `cell`) have as many rows as samples when cells == samples, and
        must not become a column of the samples then."""
        if a.dtype.names or a.ndim == 0 or a.shape[0] != self.time_s.shape[0]:
            return False
        dims = self._file_dims(path)
        return not dims or dims[0] in ("time_s", "")

    def _file_dims(self, path: str) -> tuple[str, ...]:
        if self._complete is not None:
            self._load()
        return self._dims.get(path, ())

    def to_xarray(self):
        """An xarray DataTree shaped like the file (what ``xr.open_datatree(path,
        engine="h5netcdf")`` reads from it): the groups ``truth``, ``measured``, ``bms``,
        ``hardware``, ``summary`` (attributes only) and, for a batch case, ``inputs`` (its
        drawn cell values on ``cell``, docs/results.md), every variable under its name in
        the file (``dt["truth/cell_voltage_V"]``, ``dt["bms"]["state"]``), the dimensions
        named as the file's dimension scales (``time_s``, ``cell``, ``series``,
        ``thermistor``, ``device``, ``telemetry_byte``; a 2-D channel with another axis
        ``<name>_index``) with 1-based coordinates, the attributes of every group and
        dataset, and the events on ``event``. Enumerated channels (those with a
        ``names`` attribute: ``bms/state``, ``bms/precharge_phase``,
        ``bms/balance_status``) are pandas categoricals of their names; their codes
        stay in the Result (``r["bms/state"]``)."""
        xr = _need("xarray")
        n = self.n_samples
        sizes = {"cell": self.n_cells, "series": self.n_series, "thermistor": self.n_thermistors}
        groups: dict[str, dict] = {}
        for path, a in self._datasets.items():
            if "/" not in path or a.dtype.names or a.ndim == 0 or a.shape[0] != n:
                continue
            group, name = path.split("/", 1)
            if "/" in name:
                continue
            attrs = dict(self._attrs.get(path, {}))
            data: Any = a
            if a.ndim == 1:
                dims: tuple[str, ...] = ("time_s",)
                codes = _enum_names(attrs.get("names"))
                if codes:
                    data = _categorical(a, codes)
            elif a.ndim == 2:
                known = self._file_dims(path)
                dims = ("time_s", known[1] if len(known) == 2 and known[1] else _axis(path, a.shape[1], sizes))
            else:
                continue
            groups.setdefault(group, {})[name] = (dims, data, attrs)
        tree = {}
        for group, variables in groups.items():
            coords = {}
            for dims, data, _ in variables.values():
                for d, k in zip(dims[1:], np.shape(data)[1:]):
                    coords[d] = (d, np.arange(1, k + 1, dtype=np.int32))
            tree["/" + group] = xr.Dataset(variables, coords=coords, attrs=dict(self._attrs.get(group, {})))
        if self.summary:
            tree["/summary"] = xr.Dataset(attrs=self.summary)
        drawn = {k.split("/", 1)[1]: (("cell",), a, dict(self._attrs.get(k, {})))
                 for k, a in self._datasets.items() if k.startswith("inputs/") and a.ndim == 1}
        if drawn:  # a batch case's drawn cell values (docs/results.md)
            tree["/inputs"] = xr.Dataset(drawn, coords={"cell": ("cell", np.arange(1, self.n_cells + 1, dtype=np.int32))},
                                         attrs=dict(self._attrs.get("inputs", {})))
        ev = self.events_array
        root = xr.Dataset({"events": (("event",), ev)} if ev.size else {},
                          coords={"time_s": ("time_s", self.time_s, dict(self._attrs.get("time_s", {"units": "s"}))),
                                  "event": ("event", np.arange(1, ev.size + 1, dtype=np.int32))},
                          attrs=dict(self._attrs.get("", {})))
        tree["/"] = root
        return xr.DataTree.from_dict(tree)


def _axis(path: str, k: int, sizes: dict[str, int]) -> str:
    """The dimension scale of a [n, k] dataset's second axis by the rules the writer
    follows (docs/results.md, "netCDF layout"), for a result made without a file."""
    special = {"measured/temperature_dC": "thermistor", "bms/comm_bad": "device", "bms/telemetry": "telemetry_byte"}
    if path in special:
        return special[path]
    if path.startswith("truth/") and k == sizes["cell"]:
        return "cell"
    if k == sizes["series"]:
        return "series"
    return path.rsplit("/", 1)[-1] + "_index"


def _enum_names(text: Any) -> dict[int, str]:
    """{code: name} from a ``names`` attribute ("0=init,1=standby,...")."""
    out: dict[int, str] = {}
    for item in str(text or "").split(","):
        code, _, name = item.partition("=")
        if name and code.strip().lstrip("-").isdigit():
            out[int(code)] = name.strip()
    return out


def _categorical(codes: np.ndarray, names: dict[int, str]):
    """A pandas Categorical of the names of `codes` (a code without a name keeps its
    number as its name); the categories in code order."""
    pd = _need("pandas")
    known = sorted(set(names) | set(np.unique(codes).tolist()))
    labels = [names.get(c, str(c)) for c in known]
    index = np.searchsorted(np.asarray(known), codes)
    return pd.Categorical.from_codes(index, categories=labels)


def _need(module: str):
    import importlib
    try:
        return importlib.import_module(module)
    except ImportError as e:
        raise ImportError(f"this needs {module}, which is not installed (pip install {module})") from e


def _write_h5(path: str, datasets: Mapping[str, np.ndarray], attrs: Mapping[str, Mapping[str, Any]]) -> None:
    import h5py

    def put_attrs(obj, a: Mapping[str, Any]) -> None:
        for k, v in a.items():
            obj.attrs[k] = v

    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with replaced_when_done(path) as tmp, h5py.File(tmp, "w", track_order=False) as f:
        put_attrs(f, attrs.get("", {}))
        for p, a in datasets.items():
            if a.dtype.names:
                dt = np.dtype([(n, h5py.string_dtype("utf-8") if a.dtype[n].kind == "O" else a.dtype[n])
                               for n in a.dtype.names])
                f.create_dataset(p, data=a.astype(dt), dtype=dt)
            else:
                f.create_dataset(p, data=a)
        for p, a in attrs.items():
            if p and p in f:
                put_attrs(f[p], a)
            elif p:
                put_attrs(f.create_group(p), a)
