"""Type hints for the compiled extension packsim._packsim (python/src/module.cpp)."""
from typing import Any, Callable, Optional

import numpy as np

__version__: str

class RunHandle:
    """Owns one run's C++ scenario and result; arrays view into it."""
    def arrays(self) -> dict[str, np.ndarray]:
        """{HDF5 dataset path: read-only numpy view of the C++ recording} (no copy)."""
    def save(self, path: str) -> None:
        """Write the result HDF5 exactly as ``packsim run -o PATH`` does."""
    def image(self) -> bytes:
        """The same HDF5 file built in memory (uncompressed), as bytes; nothing is written."""
    @property
    def scenario_yaml(self) -> str: ...
    @property
    def scenario_name(self) -> str: ...
    @property
    def seed(self) -> int: ...
    @property
    def firmware_failure(self) -> str: ...

def run(source: str, is_file: bool, overrides: list[tuple[str, str]], seed: Optional[int] = None,
        file_name: str = "<scenario>", base_dir: str = ".",
        progress: Optional[Callable[[float, float], None]] = None) -> RunHandle:
    """Load a scenario (a file if is_file, else YAML text), apply (dotted key, YAML value)
    overrides and simulate it with the GIL released; progress(t_s, end_s) is called every
    1 % of simulated time. Raises packsim.ScenarioError for bad input, RuntimeError for a
    failed run."""

def show(source: str, is_file: bool, overrides: list[tuple[str, str]], file_name: str = "<scenario>",
         base_dir: str = ".") -> dict[str, Any]: ...
def apply_overrides(yaml_text: str, overrides: list[tuple[str, str]], file_name: str = "<scenario>") -> str:
    """The scenario text with (dotted key, YAML value) overrides applied."""

def bundled_scenario_dir() -> str: ...
def result_channels() -> list[dict[str, Any]]:
    """The result-channel table: [{path, units, axis, dtype, long_name}] in file order."""
def default_scenario_path() -> str: ...
def bundled_catalog() -> list[tuple[str, str, str, str]]:
    """[(kind, name, path, description)] of the bundled scenarios and cell presets."""
def scenario_arg_path(arg: str) -> str:
    """An existing file, else a bundled scenario by name (ValueError naming the closest)."""

# --- `packsim check` (python/src/check_bindings.cpp) -----------------------------------
def check_file(path: str) -> dict[str, Any]:
    """Load, run and judge one scenario file exactly as ``packsim check`` (GIL released).
    {name, passed, error (str | None), failures: [str], latencies: [{injected,
    injected_at_s, detected_fault, detection_latency_s, relay_open_latency_s, line}],
    verdict}; never raises for a bad scenario (error is set)."""

def check_run(handle: RunHandle) -> dict[str, Any]:
    """Judge a finished run against its scenario's expect: block (same dict)."""

def collect_scenario_files(paths: list[str]) -> list[str]:
    """Scenario files under files and folders, as ``packsim check`` finds them."""

# --- sweeps and `packsim batch` (python/src/batch_bindings.cpp) -------------------------
class Sweep:
    """A base scenario and the cases of a sweep; pickles (Dask ships it to workers)."""
    @property
    def name(self) -> str: ...
    @property
    def file(self) -> str: ...
    @property
    def base_path(self) -> str: ...
    @property
    def base_text(self) -> str: ...
    @property
    def output_dir(self) -> str: ...
    @property
    def threads(self) -> int: ...
    @property
    def keys(self) -> list[str]: ...
    @property
    def cases(self) -> list[tuple[int, str, list[tuple[str, str]]]]:
        """[(index, id, [(dotted key, YAML value), ...]), ...] in sweep order."""
    def result_path(self, index: int) -> str: ...
    def summary_csv_path(self) -> str: ...
    def case_yaml(self, index: int) -> str:
        """The scenario text of case ``index``."""
    def __len__(self) -> int: ...

def load_sweep(path: str, output_dir: str = "") -> Sweep:
    """Load a sweep YAML file strictly; raises packsim.ScenarioError."""

def load_sweep_text(text: str, file: str, base_dir: str, output_dir: str = "") -> Sweep:
    """Load sweep YAML text named ``file``; relative paths resolve against base_dir."""

def monte_carlo_seed(master_seed: int, sample: int) -> int:
    """The scenario seed of Monte Carlo sample ``sample``."""

def validate_sweep_case(sweep: Sweep, index: int) -> None:
    """Load case ``index`` strictly without running it (ScenarioError if invalid)."""

def run_sweep_case(sweep: Sweep, index: int, resume: bool = True) -> dict[str, Any]:
    """Run one case as ``packsim batch`` does; never raises. {ok, skipped, wall_s,
    error, summary: [(name, text)]}."""

def run_batch(sweep: Sweep, threads: int = 0, resume: bool = True, progress: bool = False) -> dict[str, Any]:
    """Every case on a C++ thread pool, as ``packsim batch`` (GIL released).
    {total, ok, failed, skipped, threads, wall_s, csv_path, cases: [outcome dicts]}."""

def write_summary_csv(sweep: Sweep, outcomes: list[dict[str, Any]]) -> str:
    """Write summary.csv from one outcome dict per case; returns its path."""

# --- `packsim balance-time` (python/src/balance_bindings.cpp) ---------------------------
def balance_time(source: str, is_file: bool, overrides: list[tuple[str, str]], resistors_ohm: list[float],
                 delta_Ah: Optional[float], cell_V: Optional[float], high_cells: int, target_mV: Optional[float],
                 max_hours: float, simulate: bool, when: Optional[str], during_charge: bool,
                 file_name: str = "<scenario>", base_dir: str = ".") -> dict[str, Any]:
    """Time to balance per resistor as ``packsim balance-time`` (GIL released).
    {scenario, delta_Ah, delta_given, cell_V, high_cells, target_mV, resistor_rating_W, board_max_C, when,
    when_overridden, during_charge, warnings, text (the CLI's table), rows: [one dict per resistor
    with the fields of packsim.balance.BalanceTimeRow]}. ValueError for a bad option."""

def preset_path(name: str) -> str:
    """A bundled scenario by name (scenarios/ or scenarios/balance/); ValueError if none."""
def rc_response(time_s: np.ndarray, x: np.ndarray, tau_s: np.ndarray) -> np.ndarray:
    """One RC branch under a zero-order hold: v[k+1] = a·v[k] + (1 - a)·x[k], a = exp(-dt_k/tau_k)."""
def rc_sensitivity(time_s: np.ndarray, x: np.ndarray, tau_s: np.ndarray,
                   dlogtau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(v, dv/dtheta) of rc_response for parameters theta_j with d log tau_k / d theta_j = dlogtau[k, j]."""
def simulate_cell(preset_yaml: str, time_s: np.ndarray, current_A: np.ndarray, held_A: np.ndarray,
                  temp_C: np.ndarray, initial_soc: float, file: str = "<preset>") -> np.ndarray:
    """Terminal voltage of a cell preset over a record (exact zero-order hold of the plant's equations)."""
