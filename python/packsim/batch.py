"""``packsim.batch``: run a sweep, on this machine or on a Dask distributed cluster.

    res = packsim.batch("sweeps/resistor.yaml")              # C++ thread pool, as `packsim batch`
    res = packsim.batch(sweep, client=distributed.Client(...))  # one Dask task per case
    res.table            # pandas DataFrame (or a dict of columns without pandas)
    res.paths            # result file of each case (None for a failed one)
    res.load(3)          # that case's Result

A sweep is a base scenario plus what to vary (grid, zip, Monte Carlo seeds from one
master seed; core/batch/sweep.hpp). The C++ core expands it into cases. Locally the
cases run on the CLI's thread pool; with a Dask client every case is one task that runs
exactly the C++ function the pool runs, so both give the same result files and the same
summary.csv for the same sweep. Cases whose result is already complete are skipped
(resume). A failing case is recorded with its error and the others finish.

On a real cluster the workers need packsim importable and the base scenario, its CSV
tables and the output folder on a filesystem they share with the client.
"""
from __future__ import annotations

import os
import re
from collections.abc import Mapping, Sequence
from typing import Any, Union

from .result import Result, load

__all__ = ["batch", "load_sweep", "BatchResult", "monte_carlo_seed"]

SweepLike = Union[str, "os.PathLike[str]", Mapping[str, Any], Any]

_INT = re.compile(r"[+-]?\d+\Z")


def _summary_value(text: str) -> Any:
    """A summary field (text, as in summary.csv) as an int, a float or the text."""
    if _INT.match(text):
        return int(text)
    try:
        return float(text)
    except ValueError:
        return text


def _param_value(text: str) -> Any:
    """A varied parameter (flow YAML text) as the Python value YAML reads."""
    try:
        import yaml
        return yaml.safe_load(text)
    except Exception:  # PyYAML missing: numbers still come out as numbers
        return _summary_value(text)


def monte_carlo_seed(master_seed: int, sample: int) -> int:
    """The scenario seed of Monte Carlo sample `sample` of a sweep with `master_seed`."""
    from . import _core, _int_arg
    return _core().monte_carlo_seed(_int_arg("master_seed", master_seed, 0), _int_arg("sample", sample, 0))


def load_sweep(sweep: SweepLike, *, output_dir: str | os.PathLike[str] | None = None,
               base_dir: str | os.PathLike[str] | None = None):
    """Expand a sweep into its cases without running them (a ``packsim._packsim.Sweep``).

    sweep: a sweep YAML file, YAML text, a dict of the same keys, or a Sweep.
    output_dir: replaces the sweep's ``output_dir``.
    base_dir: where the relative ``base`` and ``output_dir`` of text or a dict resolve
              (default: the current folder; a file's own folder for a file).
    """
    from . import _core, _is_path, _path_arg
    core = _core()
    out = _path_arg("output_dir", output_dir) or ""
    base = _path_arg("base_dir", base_dir)
    if isinstance(sweep, core.Sweep):
        if out or base is not None:
            raise ValueError("a loaded Sweep is used as it is: output_dir and base_dir do not apply")
        return sweep
    if isinstance(sweep, Mapping):
        from ._overrides import yaml_value
        text = yaml_value(dict(sweep), "sweep")  # JSON is YAML (a NaN as YAML's .nan: the loader names its range)
        return core.load_sweep_text(text, "<dict>", "." if base is None else base, out)
    if _is_path(sweep):
        path = os.fspath(sweep)
        if not os.path.isfile(path):
            raise FileNotFoundError(f"no such sweep file: {path}")
        if base is not None:
            raise ValueError("base_dir applies to YAML text and dicts; a sweep file's paths resolve against its folder")
        return core.load_sweep(path, out)
    if isinstance(sweep, str):
        return core.load_sweep_text(sweep, "<string>", "." if base is None else base, out)
    raise TypeError(f"sweep must be a path, YAML text, a dict or a Sweep, not {type(sweep).__name__}")


class BatchResult:
    """What a batch run produced, one entry per case in sweep order.

    table:    one row per case: ``case`` (id), each varied key (its value), ``status``
              (ok | failed), the drawn inputs (``drawn_*``, docs/batch.md), every
              summary field, ``error`` and ``path`` — a pandas
              DataFrame when pandas is installed, else a dict of column lists. The same
              content as summary.csv (numbers to the CSV's 10 significant digits; load a
              result file for full precision).
    paths:    result file of each case, None for a failed one.
    csv_path: the summary.csv written beside the results.
    """

    def __init__(self, sweep, outcomes: Sequence[Mapping[str, Any]], csv_path: str, *,
                 threads: int | None, wall_s: float | None, engine: str) -> None:
        self.sweep = sweep
        self.outcomes = list(outcomes)
        self.csv_path = os.path.abspath(csv_path)
        self.threads = threads
        self.wall_s = wall_s
        self.engine = engine
        self.paths: list[str | None] = [os.path.abspath(sweep.result_path(i)) if o["ok"] else None
                                        for i, o in enumerate(self.outcomes)]
        self.columns = _columns(sweep, self.outcomes, self.paths)
        try:
            import pandas as pd
        except ImportError:
            self.table: Any = self.columns
        else:
            self.table = pd.DataFrame(self.columns)

    @property
    def n_ok(self) -> int:
        return sum(bool(o["ok"]) for o in self.outcomes)

    @property
    def n_failed(self) -> int:
        return len(self.outcomes) - self.n_ok

    @property
    def n_skipped(self) -> int:
        """Cases not rerun because their result file was already complete."""
        return sum(bool(o["skipped"]) for o in self.outcomes)

    @property
    def ok(self) -> bool:
        return self.n_failed == 0

    @property
    def errors(self) -> dict[str, str]:
        """{case id: error message} of the failed cases."""
        return {c[1]: o["error"] for c, o in zip(self.sweep.cases, self.outcomes) if not o["ok"]}

    def __len__(self) -> int:
        return len(self.outcomes)

    def load(self, case: int | str) -> Result:
        """The Result of one case, by index or id (``"0003"``)."""
        if isinstance(case, str):
            ids = [c[1] for c in self.sweep.cases]
            if case not in ids:
                raise KeyError(f"no case {case!r} in this sweep")
            case = ids.index(case)
        if isinstance(case, bool) or not isinstance(case, int):
            raise TypeError(f"case must be an index or an id, got {type(case).__name__}")
        path = self.paths[case]
        if path is None:
            raise ValueError(f"case {self.sweep.cases[case][1]} failed: {self.outcomes[case]['error']}")
        return load(path)

    def __repr__(self) -> str:
        how = f"{self.threads} threads" if self.engine == "threads" else "Dask"
        return (f"<packsim.BatchResult {self.sweep.name!r}: {len(self)} cases, {self.n_ok} ok "
                f"({self.n_skipped} already complete), {self.n_failed} failed on {how}; {self.csv_path}>")


def _columns(sweep, outcomes: Sequence[Mapping[str, Any]], paths: Sequence[str | None]) -> dict[str, list]:
    fields: list[str] = []  # union of the summary fields, first-seen order (as summary.csv)
    for o in outcomes:
        for k, _ in o["summary"]:
            if k not in fields:
                fields.append(k)
    cases = sweep.cases
    params = [dict(c[2]) for c in cases]
    summaries = [dict(o["summary"]) for o in outcomes]
    cols: dict[str, list] = {"case": [c[1] for c in cases]}
    for key in sweep.keys:
        cols[key] = [_param_value(p[key]) if key in p else None for p in params]
    cols["status"] = ["ok" if o["ok"] else "failed" for o in outcomes]
    for f in fields:
        cols[f] = [_summary_value(s[f]) if f in s else None for s in summaries]
    cols["error"] = [o["error"] or None for o in outcomes]
    cols["path"] = list(paths)
    return cols


def _check_client(client: Any) -> None:
    try:
        from distributed import Client
    except ImportError:
        raise TypeError("client must be a dask.distributed.Client (dask[distributed] is not installed)") from None
    if not isinstance(client, Client):
        raise TypeError(f"client must be a dask.distributed.Client, got {type(client).__name__}")


def batch(sweep: SweepLike, client: Any = None, *, output_dir: str | os.PathLike[str] | None = None,
          threads: int | None = None, resume: bool = True, progress: bool = False,
          base_dir: str | os.PathLike[str] | None = None, max_in_flight: int | None = None) -> BatchResult:
    """Run every case of a sweep and return their summaries as a table plus result paths.

    sweep:      a sweep YAML file, YAML text, a dict of the same keys, or a Sweep from
                ``load_sweep`` (see docs/python.md and core/batch/sweep.hpp).
    client:     None: this machine, a C++ thread pool exactly as ``packsim batch``. A
                ``dask.distributed.Client``: one task per case on its cluster.
    output_dir: replaces the sweep's ``output_dir``.
    threads:    local only: threads in the pool (default: the sweep's, else every core).
    resume:     skip cases whose result file is complete and holds the same scenario.
    progress:   print progress (the CLI's bar locally; a line per case on Dask).
    max_in_flight: Dask only: cases submitted at once (default: twice the cluster's
                worker threads); a finished case's future is released before the next
                is submitted, so memory stays bounded for any number of cases. While
                the sweep runs, <output_dir>/summary.running.jsonl lists each finished
                case (packsim/_dask_batch.py).

    The first case is loaded strictly before anything runs: a mistake in the sweep or
    the base scenario raises ScenarioError at once (as ``packsim batch`` exits 2).
    Later failing cases are recorded in the table with their error.
    """
    from . import _bool_arg, _core, _int_arg
    core = _core()
    _bool_arg("resume", resume)
    _bool_arg("progress", progress)
    if threads is not None:
        _int_arg("threads", threads, 1)
    if client is not None:
        _check_client(client)
        if threads is not None:
            raise ValueError("threads applies to local runs; on Dask the cluster's workers set the parallelism")
    if max_in_flight is not None:
        if client is None:
            raise ValueError("max_in_flight applies to Dask runs (give a client); locally the thread count bounds the work")
        _int_arg("max_in_flight", max_in_flight, 1)
    sw = load_sweep(sweep, output_dir=output_dir, base_dir=base_dir)
    if len(sw) > 0:
        core.validate_sweep_case(sw, 0)

    if client is None:
        rep = core.run_batch(sw, threads or 0, resume, progress)
        return BatchResult(sw, rep["cases"], rep["csv_path"], threads=rep["threads"], wall_s=rep["wall_s"],
                           engine="threads")

    from ._dask_batch import run_on_dask
    outcomes, csv_path, wall_s = run_on_dask(core, sw, client, resume=resume, progress=progress,
                                             max_in_flight=max_in_flight)
    return BatchResult(sw, outcomes, csv_path, threads=None, wall_s=wall_s, engine="dask")
