"""Type hints for the compiled extension packsim._packsim (python/src/module.cpp)."""
from typing import Optional

import numpy as np

__version__: str

class RunHandle:
    """Owns one run's C++ scenario and result; arrays view into it."""
    def arrays(self) -> dict[str, np.ndarray]:
        """{HDF5 dataset path: read-only numpy view of the C++ recording} (no copy)."""
    def save(self, path: str) -> None:
        """Write the result HDF5 exactly as ``packsim run -o PATH`` does."""
    @property
    def scenario_yaml(self) -> str: ...
    @property
    def scenario_name(self) -> str: ...
    @property
    def seed(self) -> int: ...

def run(source: str, is_file: bool, overrides: list[tuple[str, str]], seed: Optional[int] = None,
        file_name: str = "<scenario>", base_dir: str = ".") -> RunHandle:
    """Load a scenario (a file if is_file, else YAML text), apply (dotted key, YAML value)
    overrides and simulate it with the GIL released. Raises packsim.ScenarioError for bad
    input, RuntimeError for a failed run."""

def apply_overrides(yaml_text: str, overrides: list[tuple[str, str]], file_name: str = "<scenario>") -> str:
    """The scenario text with (dotted key, YAML value) overrides applied."""

def bundled_scenario_dir() -> str: ...
def default_scenario_path() -> str: ...
