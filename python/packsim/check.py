"""``packsim.check``: scenarios as regression tests, as ``packsim check`` runs them.

    report = packsim.check()                          # every bundled scenario
    report = packsim.check("scenarios/faults")        # files and folders, like the CLI
    report = packsim.check(r)                         # a Result of packsim.run, no rerun
    report = packsim.check(path, {"pack.cell.capacity_Ah": 4.5})   # with overrides
    report.passed, report.n_failed, print(report)     # the CLI's text, line for line
    report[0].latencies[0].detection_latency_s        # seconds from injection to BMS fault

Each scenario's ``expect:`` block is judged (core/check/check.hpp) and every injected
fault gets its detection latency: the first BMS fault raised after the injection and
when the relay opened. A scenario that cannot be loaded or run is an outcome with an
``error``, never an exception, as in the CLI.
"""
from __future__ import annotations

import os
from collections.abc import Iterable, Iterator, Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any, Union

from ._overrides import flatten_overrides
from .result import Result

__all__ = ["check", "CheckReport", "CheckOutcome", "FaultLatency"]

ScenarioLike = Union[str, "os.PathLike[str]", Mapping[str, Any], Result]


@dataclass(frozen=True)
class FaultLatency:
    """How the BMS answered one injected fault. Latencies in seconds; None when no BMS
    fault followed / the relay never opened."""
    injected: str                       # the fault_injected event's detail
    injected_at_s: float
    detected_fault: str | None          # first BMS fault raised at or after the injection
    detection_latency_s: float | None
    relay_open_latency_s: float | None
    line: str                           # as `packsim check` prints it after "injected "


@dataclass(frozen=True)
class CheckOutcome:
    """One scenario's verdict. ``error`` is the load/run error message (then ``passed`` is
    False and the rest empty); ``failures`` one line per unmet expectation."""
    name: str
    passed: bool
    error: str | None
    failures: tuple[str, ...]
    latencies: tuple[FaultLatency, ...]
    verdict: str
    nothing_to_check: bool = False      # no expect: block: status "RAN", neither passed nor failed
    warnings: tuple[str, ...] = ()      # the run's config warnings, as `packsim run` prints them

    @property
    def status(self) -> str:
        if self.error is not None:
            return "ERROR"
        return "FAIL" if not self.passed else "RAN" if self.nothing_to_check else "PASS"

    def __str__(self) -> str:
        """The CLI's lines for this scenario."""
        head = f"{self.status:<5} {self.name}"
        if self.error is not None:
            return f"{head}\n      {self.error}\n"
        out = [f"{head}  -- {self.verdict}\n"]
        out += [f"      injected {f.line}\n" for f in self.latencies]
        out += [f"      failed: {f}\n" for f in self.failures]
        out += [f"      warning: {w}\n" for w in self.warnings]
        return "".join(out)


class CheckReport:
    """The outcomes in order. ``passed`` (and ``bool(report)``) is True when every scenario
    passed; ``str(report)`` is what ``packsim check`` prints for the same files."""

    def __init__(self, outcomes: Iterable[CheckOutcome]) -> None:
        self.outcomes: list[CheckOutcome] = list(outcomes)

    @property
    def passed(self) -> bool:
        return all(o.passed for o in self.outcomes)

    @property
    def n_passed(self) -> int:
        return sum(o.passed and not o.nothing_to_check for o in self.outcomes)

    @property
    def n_failed(self) -> int:
        return sum(not o.passed for o in self.outcomes)

    @property
    def n_unchecked(self) -> int:
        """Scenarios that ran without an ``expect:`` block (nothing to judge)."""
        return sum(o.passed and o.nothing_to_check for o in self.outcomes)

    @property
    def failed(self) -> list[CheckOutcome]:
        return [o for o in self.outcomes if not o.passed]

    def __bool__(self) -> bool:
        return self.passed

    def __len__(self) -> int:
        return len(self.outcomes)

    def __iter__(self) -> Iterator[CheckOutcome]:
        return iter(self.outcomes)

    def __getitem__(self, i: int) -> CheckOutcome:
        return self.outcomes[i]

    def __str__(self) -> str:
        tail = f", {self.n_unchecked} ran with nothing to check" if self.n_unchecked else ""
        return "".join(str(o) for o in self.outcomes) + f"{self.n_passed} passed, {self.n_failed} failed{tail}\n"

    def __repr__(self) -> str:
        return f"<packsim.CheckReport: {self.n_passed} passed, {self.n_failed} failed>"

    def to_dataframe(self):
        """One row per scenario (name, status, verdict, failures, error) when pandas is
        installed; see ``latencies_dataframe`` for the injected faults."""
        from .result import _need
        pd = _need("pandas")
        return pd.DataFrame({
            "name": [o.name for o in self.outcomes],
            "status": [o.status for o in self.outcomes],
            "passed": [o.passed for o in self.outcomes],
            "verdict": [o.verdict for o in self.outcomes],
            "failures": ["; ".join(o.failures) for o in self.outcomes],
            "error": [o.error for o in self.outcomes],
        })

    def latencies_dataframe(self):
        """One row per injected fault of every scenario (pandas)."""
        from .result import _need
        pd = _need("pandas")
        rows = [{"name": o.name, "injected": f.injected, "injected_at_s": f.injected_at_s,
                 "detected_fault": f.detected_fault, "detection_latency_s": f.detection_latency_s,
                 "relay_open_latency_s": f.relay_open_latency_s}
                for o in self.outcomes for f in o.latencies]
        cols = ["name", "injected", "injected_at_s", "detected_fault", "detection_latency_s", "relay_open_latency_s"]
        return pd.DataFrame(rows, columns=cols)


def _outcome(d: Mapping[str, Any], name: str | None = None) -> CheckOutcome:
    return CheckOutcome(
        name=name if name is not None else d["name"],
        passed=bool(d["passed"]),
        error=d["error"],
        failures=tuple(d["failures"]),
        latencies=tuple(FaultLatency(**f) for f in d["latencies"]),
        verdict=d["verdict"],
        nothing_to_check=bool(d.get("nothing_to_check", False)),
        warnings=tuple(d.get("warnings", ())),
    )


def _error(name: str, message: str) -> CheckOutcome:
    return CheckOutcome(name=name, passed=False, error=message, failures=(), latencies=(), verdict="")


def check(scenarios: ScenarioLike | Iterable[str | os.PathLike[str]] | None = None, /,
          overrides: Mapping[str, Any] | None = None, *, seed: int | None = None,
          base_dir: str | os.PathLike[str] | None = None, threads: int | None = None,
          **more: Any) -> CheckReport:
    """Run scenarios and judge their ``expect:`` blocks, like ``packsim check``.

    scenarios: None (every bundled scenario), a scenario file or folder, a list of them
               (folders are searched recursively as by the CLI), YAML text, a dict, or a
               Result of ``packsim.run`` (judged as it is, nothing is rerun).
    overrides, seed, base_dir, **more: as for ``packsim.run``, applied to every scenario.
    threads:   scenarios checked at once (default: every core); the outcomes are the
               same and in the same order whatever the number.
    """
    from . import _FILE_BASE_DIR, _core, _int_arg, _is_path, _path_arg, _validate_seed
    core = _core()
    seed = _validate_seed(seed)
    pairs = flatten_overrides(overrides, more)
    if threads is not None:
        _int_arg("threads", threads, 1)
    _path_arg("base_dir", base_dir)

    if isinstance(scenarios, Result):
        if pairs or seed is not None or base_dir is not None:
            raise ValueError("a Result is judged as it ran: overrides, seed and base_dir do not apply")
        if scenarios._handle is None:
            raise ValueError("only a Result of packsim.run can be checked (a loaded file holds no scenario "
                             "to judge against); check its scenario instead: "
                             "packsim.check(result.scenario_yaml, seed=result.seed)")
        return CheckReport([_outcome(core.check_run(scenarios._handle))])
    if isinstance(scenarios, Mapping) or isinstance(scenarios, str) and not _is_path(scenarios):
        from . import _run_handle
        name = "<dict>" if isinstance(scenarios, Mapping) else "<string>"
        try:
            handle = _run_handle(scenarios, pairs, seed, base_dir)
        except (ValueError, RuntimeError) as e:  # ScenarioError is a ValueError
            return CheckReport([_error(name, str(e))])
        return CheckReport([_outcome(core.check_run(handle))])

    if scenarios is None:
        paths = [core.bundled_scenario_dir()]
    elif _is_path(scenarios):
        paths = [os.fspath(scenarios)]  # type: ignore[arg-type]
    elif isinstance(scenarios, Iterable) and not isinstance(scenarios, (str, bytes)):
        paths = []
        for p in scenarios:
            if not isinstance(p, (str, os.PathLike)):
                raise TypeError(f"scenario paths must be str or os.PathLike, got {type(p).__name__}")
            paths.append(os.fspath(p))
    else:
        raise TypeError("scenarios must be None, a path, a list of paths, YAML text, a dict or a Result, "
                        f"not {type(scenarios).__name__}")
    if base_dir is not None:
        raise ValueError(_FILE_BASE_DIR)
    files = core.collect_scenario_files(paths)
    if not files:
        raise ValueError(f"no scenario files found in {', '.join(paths) or 'an empty list'}")

    def one(path: str) -> CheckOutcome:
        if not pairs and seed is None:
            return _outcome(core.check_file(path))  # the CLI's own function
        try:
            handle = core.run(path, True, pairs, seed)
        except Exception as e:  # the CLI reports load and run errors per scenario too
            return _error(path, str(e))
        return _outcome(core.check_run(handle), name=path)

    n = min(threads or os.cpu_count() or 1, len(files))
    if n == 1:
        return CheckReport(one(f) for f in files)
    with ThreadPoolExecutor(max_workers=n) as pool:  # the GIL is released while each runs
        return CheckReport(pool.map(one, files))
