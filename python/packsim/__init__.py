"""packsim from Python: run battery-pack/BMS scenarios, load and plot their results.

    import packsim
    r = packsim.run("eco_marathon_12s", {"pack.cell.capacity_Ah": 4.5}, seed=7)   # by name or path
    r["truth/cell_voltage_V"]          # [samples, cells] NumPy array
    r.summary["energy_delivered_Wh"]
    r.save("race.h5"); packsim.load("race.h5")
    packsim.plot.plot_all(r, "figures/")
    packsim.check(packsim.bundled_scenarios("faults/*.yaml"))   # as `packsim check`
    packsim.batch("sweep.yaml", client=None)     # as `packsim batch`, or on Dask
    packsim.balance_time(resistor=[22, 33, 47])  # as `packsim balance-time`
    packsim.fit(["hppc.csv"], rc_pairs=2).save("cells/my_cell.yaml")   # as `packsim fit`
    packsim.run("motorcycle_110s")               # a bundled scenario by name (packsim.list_bundled())
    packsim.export("race.h5", "parquet")         # as `packsim export` (csv, mat, parquet)
    packsim.report("race.h5", "race.html")       # as `packsim report`: one self-contained page

The simulation itself is the C++ core (packsim._packsim); this package is a thin layer.
"""
from __future__ import annotations

import glob
import os
from collections.abc import Mapping
from typing import Any

from ._errors import FirmwareError, ScenarioError
from ._overrides import flatten_overrides
from .balance import BalanceTimeResult, BalanceTimeRow, balance_time
from .batch import BatchResult, batch, load_sweep, monte_carlo_seed
from .check import CheckOutcome, CheckReport, FaultLatency, check
from .fit import FitError, FitResult, FitWarning, fit, from_bpx, from_pybamm
from .export import export
from .report import report
from .result import NotAResultError, Result, load

# An installed wheel carries the bundled scenarios inside the package.
_WHEEL_SCENARIOS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenarios")
if os.path.isdir(_WHEEL_SCENARIOS):
    os.environ.setdefault("PACKSIM_SCENARIOS", _WHEEL_SCENARIOS)

# Firmware libraries a scenario names by bare name (bms.firmware.library): the C++ loader
# looks next to the `packsim` executable, which in Python is the interpreter. Add the
# package's _bin folder and, in a build tree (build/python/packsim), the build folder
# where CMake puts them (e.g. the example firmware, libpacksim_example_bms.so).
_PACKAGE = os.path.dirname(os.path.abspath(__file__))
_FIRMWARE_DIRS = [os.path.join(_PACKAGE, "_bin"), os.path.dirname(os.path.dirname(_PACKAGE))]
os.environ["PACKSIM_FIRMWARE_PATH"] = os.pathsep.join(
    [d for d in [os.environ.get("PACKSIM_FIRMWARE_PATH", "")] + _FIRMWARE_DIRS if d])

try:
    from . import _packsim
    __version__: str = _packsim.__version__
    _IMPORT_ERROR: ImportError | None = None
except ImportError as _e:  # results can still be loaded and plotted without it
    _packsim = None  # type: ignore[assignment]
    __version__ = "unknown"
    _IMPORT_ERROR = _e

__all__ = ["run", "show", "load", "Result", "ScenarioError", "apply_overrides", "bundled_scenarios", "bundled_scenario_dir",
           "default_scenario", "check", "CheckReport", "CheckOutcome", "FaultLatency", "batch", "BatchResult",
           "load_sweep", "monte_carlo_seed", "balance_time", "BalanceTimeResult", "BalanceTimeRow", "export", "report", "list_bundled", "__version__"]
__all__ += ["fit", "from_bpx", "from_pybamm", "FitResult", "FitError", "FitWarning", "NotAResultError"]


def __getattr__(name: str):
    # `packsim.plot` without importing matplotlib at `import packsim`
    if name == "plot":
        import importlib
        return importlib.import_module(".plot", __name__)
    raise AttributeError(f"module 'packsim' has no attribute {name!r}")


def _core():
    if _packsim is None:
        raise ImportError("packsim's compiled extension (packsim._packsim) is not available: build it with "
                          "scripts/build.sh and put build/python on PYTHONPATH, or `pip install .` "
                          f"({_IMPORT_ERROR})") from _IMPORT_ERROR
    return _packsim


def default_scenario() -> str:
    """Path of the scenario ``packsim run`` uses without arguments."""
    return _core().default_scenario_path()


def bundled_scenario_dir() -> str:
    """Folder of the bundled scenarios (``$PACKSIM_SCENARIOS`` overrides it)."""
    return _core().bundled_scenario_dir()


def bundled_scenarios(pattern: str = "*.yaml") -> list[str]:
    """Sorted paths of the bundled scenarios matching a glob pattern relative to their
    folder (``"*.yaml"``, ``"faults/*.yaml"``, ``"**/*.yaml"``)."""
    return sorted(glob.glob(os.path.join(bundled_scenario_dir(), pattern), recursive=True))


def list_bundled(kind: str | None = None) -> list[dict[str, str]]:
    """The bundled scenarios and cell presets as ``packsim list`` prints them: dicts with
    kind ("scenario" or "cell"), name, path and a one-line description. kind filters."""
    rows = [dict(zip(("kind", "name", "path", "description"), t)) for t in _core().bundled_catalog()]
    if kind is not None:
        if kind not in ("scenario", "cell"):
            raise ValueError(f"kind must be 'scenario' or 'cell', not {kind!r}")
        rows = [r for r in rows if r["kind"] == kind]
    return rows


def apply_overrides(yaml_text: str, /, overrides: Mapping[str, Any] | None = None, **more: Any) -> str:
    """The scenario text with overrides applied (what ``run`` simulates and stores)."""
    if not isinstance(yaml_text, str):
        raise TypeError(f"yaml_text must be str, got {type(yaml_text).__name__}")
    return _core().apply_overrides(yaml_text, flatten_overrides(overrides, more))


def _is_yaml_text(s: str) -> bool:
    return "\n" in s or ":" in s and not os.path.exists(s)


def _is_path(x: Any) -> bool:
    """A scenario or sweep argument naming a file (not YAML text)."""
    return isinstance(x, os.PathLike) or isinstance(x, str) and not _is_yaml_text(x)


# The ValueError for base_dir given with a scenario file.
_FILE_BASE_DIR = "base_dir applies to YAML text and dicts; a file's CSV paths resolve against its folder"


def _path_arg(name: str, v: Any) -> str | None:
    """An optional path argument as str (None stays None); TypeError if it is no path."""
    if v is None:
        return None
    if not isinstance(v, (str, os.PathLike)):
        raise TypeError(f"{name} must be a path, got {type(v).__name__}")
    return os.fspath(v)


def _int_arg(name: str, v: Any, minimum: int | None = None) -> int:
    if isinstance(v, bool) or not isinstance(v, int):
        raise TypeError(f"{name} must be an int, got {type(v).__name__}")
    if minimum is not None and v < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {v}")
    return v


def _bool_arg(name: str, v: Any) -> bool:
    if not isinstance(v, bool):
        raise TypeError(f"{name} must be a bool, got {type(v).__name__}")
    return v


def _scenario_args(scenario: Any, pairs: list[tuple[str, str]],
                   base: str | None) -> tuple[str, bool, list[tuple[str, str]], str, str]:
    """(source, is_file, overrides, file_name, base_dir) of a scenario file, YAML text or
    dict, as _packsim.run and _packsim.balance_time take them; base is the caller's
    base_dir (None when not given)."""
    if isinstance(scenario, Mapping):
        # The dict is the scenario: its leaves are set on an empty one, by the same C++
        # code that applies overrides (so values arrive with the same exactness).
        return "", False, flatten_overrides(scenario) + pairs, "<dict>", "." if base is None else base
    if _is_path(scenario):
        path = os.fspath(scenario)
        if not os.path.isfile(path):
            if path.endswith((".yaml", ".yml")):
                raise FileNotFoundError(f"no such scenario file: {path}")
            path = _core().scenario_arg_path(path)  # a bundled scenario by name (ValueError naming the closest)
        if base is not None:
            raise ValueError(_FILE_BASE_DIR)
        return path, True, pairs, "<scenario>", "."
    if isinstance(scenario, str):
        return scenario, False, pairs, "<string>", "." if base is None else base
    raise TypeError(f"scenario must be a path, YAML text or a dict, not {type(scenario).__name__}")


_SEED_MAX = 2**31 - 1  # the scenario's `seed:` range, and the CLI's --seed


def _validate_seed(seed: Any) -> int | None:
    if seed is None:
        return None
    if isinstance(seed, bool) or not isinstance(seed, int) and not hasattr(seed, "__index__"):
        raise TypeError(f"seed must be an int, got {type(seed).__name__}")
    seed = int(seed.__index__())
    if not 0 <= seed <= _SEED_MAX:
        raise ValueError(f"seed must be in [0, {_SEED_MAX}] (a scenario's seed: range), got {seed}")
    return seed


def run(scenario: str | os.PathLike | Mapping[str, Any] | None = None, /,
        overrides: Mapping[str, Any] | None = None, *,
        seed: int | None = None, base_dir: str | os.PathLike | None = None, progress: Any = False,
        **more: Any) -> Result:
    """Run one scenario and return its Result.

    scenario:  a path to a YAML file, a bundled scenario's name (``"motorcycle_110s"``,
               see ``list_bundled()``), YAML text, or a dict of the scenario itself;
               None runs the bundled default (like ``packsim run``).
    overrides: a dict merged into the scenario, nested (``{"pack": {"cell":
               {"capacity_Ah": 3.0}}}``) or with dotted keys (``{"pack.cell.capacity_Ah":
               3.0}``, list elements as ``"pack.cell.rc_pairs.0.r_ohm"``). Keyword
               arguments are more overrides, applied after it: ``run(path, load={"laps": 2})``.
               Dicts merge key by key; lists and values replace. Unknown keys are
               ScenarioErrors naming the closest valid key.
    seed:      the noise seed, exactly as ``packsim run --seed`` (the stored scenario
               text stays as written).
    base_dir:  where relative CSV paths of YAML text or a dict resolve (default: the
               current folder; a file's own folder for a path).

    progress:  True: a progress bar over simulated time (tqdm.auto: a widget in Jupyter,
               nothing on stdout); or a callable progress(t_s, end_s), called every 1 %.

    The GIL is released while the simulation runs: threads run scenarios in parallel.
    """
    pairs, seed = flatten_overrides(overrides, more), _validate_seed(seed)
    if progress is False or progress is None:
        return _checked(_run_handle(scenario, pairs, seed, base_dir))
    if progress is True:
        from ._progress import tqdm_progress
        with tqdm_progress() as report:
            return _checked(_run_handle(scenario, pairs, seed, base_dir, report))
    if not callable(progress):
        raise TypeError(f"progress must be a bool or a callable(t_s, end_s), got {type(progress).__name__}")
    return _checked(_run_handle(scenario, pairs, seed, base_dir, progress))


def _checked(handle) -> Result:
    """The run's Result, or FirmwareError (carrying it) when its firmware failed unexpectedly."""
    from .result import _from_handle
    result = _from_handle(handle)
    if handle.firmware_failure:
        raise FirmwareError(handle.firmware_failure, result)
    return result


def show(scenario: str | os.PathLike | Mapping[str, Any] | None = None, /,
         overrides: Mapping[str, Any] | None = None, *, base_dir: str | os.PathLike | None = None,
         **more: Any) -> dict[str, Any]:
    """The scenario as it would run (``packsim show``): after presets, ``extends:``,
    overrides and defaults, every value with where it came from.

    Takes the scenario and overrides as ``run()`` does. Returns a dict:
    ``values``: ``{dotted key: {"value": YAML text, "origin": "file:line" | "preset NAME (file:line)"
    | "--set KEY=VALUE" | "default" | "default (what it was derived from)", "stated": bool}}``;
    ``warnings``: the list of warnings ``run`` also reports (config_warning events);
    ``text``: the text ``packsim show`` prints; ``yaml``: the runnable ``--format yaml`` form.
    """
    core = _core()
    pairs = flatten_overrides(overrides, more)
    base = _path_arg("base_dir", base_dir)
    if scenario is None:
        scenario = core.default_scenario_path()
    source, is_file, pairs, name, base = _scenario_args(scenario, pairs, base)
    return core.show(source, is_file, pairs, name, base)


def _run_handle(scenario: Any, pairs: list[tuple[str, str]], seed: int | None, base_dir: Any, progress: Any = None):
    """run() up to the C++ RunHandle; overrides already flattened, seed validated."""
    core = _core()
    base = _path_arg("base_dir", base_dir)
    if scenario is None:
        scenario = core.default_scenario_path()
    source, is_file, pairs, name, base = _scenario_args(scenario, pairs, base)
    return core.run(source, is_file, pairs, seed, name, base, progress)
