"""Shared fixtures: the packsim package under test, the CLI binary built next to it,
small inline scenarios and one cached run of the bundled default race; and, under
pytest-xdist (scripts/test.sh runs `pytest -n 2 --dist loadgroup`), which tests share a worker."""
from __future__ import annotations

import os
import shutil
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

import packsim  # noqa: E402

REPO = Path(__file__).resolve().parents[2]


def _cli_binary() -> Path | None:
    env = os.environ.get("PACKSIM_BINARY")
    if env:
        return Path(env)
    # The CLI of the same build tree as the extension: <build>/python/packsim/_packsim*.so
    try:
        ext = Path(packsim._packsim.__file__).resolve()
        candidate = ext.parents[2] / "packsim"
        if candidate.is_file():
            return candidate
    except (AttributeError, TypeError):
        pass
    found = shutil.which("packsim")
    return Path(found) if found else None


@pytest.fixture(scope="session")
def cli() -> Path:
    b = _cli_binary()
    if b is None or not b.is_file():
        pytest.fail("no packsim CLI binary found (build it, or set PACKSIM_BINARY)")
    return b


@pytest.fixture(scope="session")
def default_scenario() -> str:
    return packsim.default_scenario()


# A 3-cell pack on a constant discharge: fast, and simple enough for closed forms.
# Linear OCV, no RC pair, coulombic efficiency and self-discharge left at their
# neutral defaults, noise-free sensors except the seeded cell-ADC noise.
SIMPLE = """\
name: simple3
seed: 5
pack:
  series: 3
  initial_soc: 0.9
  cell:
    capacity_Ah: 2.0
    ocv_V: {poly: [0.8, 3.4]}
    r0_ohm: 0.02
    v_min_V: 3.0
hardware:
  cell_adc: {noise_mV_rms: 0.5}
  thermistors: {at_groups: [1, 3]}
load: {current_A: 2.0}
run: {duration_s: 600}
output: {interval_s: 1.0}
"""


@pytest.fixture
def simple_yaml() -> str:
    return SIMPLE


@pytest.fixture(scope="session")
def race(default_scenario) -> packsim.Result:
    """The bundled default race, run once per session."""
    return packsim.run(default_scenario)


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook, which reads the marks into the test ids
def pytest_collection_modifyitems(config, items):
    """Under `--dist loadgroup` the tests of a module that share a module-scoped fixture (a
    run of every bundled scenario, an FMU, a fit, a Monte Carlo batch) go to one worker, so
    the fixture is built once, not once per worker; every other test goes to whichever
    worker is free. Fixtures build into tmp_path_factory folders, which are per worker, so
    this saves CPU and is not needed for correctness. Without xdist the mark is inert."""
    for item in items:
        defs = getattr(getattr(item, "_fixtureinfo", None), "name2fixturedefs", {})
        if any(d and d[-1].scope in ("module", "class") for d in defs.values()):
            item.add_marker(pytest.mark.xdist_group(item.nodeid.split("::")[0]))
