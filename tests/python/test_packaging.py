"""`pip install .` builds the extension with scikit-build-core from the same CMake project,
and the installed package works on its own: imports from where pip put it, finds the
bundled scenarios inside itself, ships its type hints, and simulates what the CMake
build simulates."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import packsim

REPO = Path(__file__).resolve().parents[2]

PROBE = """
import json, os, sys
import packsim
out = sys.argv[1]
r = packsim.run(sys.stdin.read(), seed=3)
r.save(out)
print(json.dumps({
    "package": packsim.__file__,
    "extension": packsim._packsim.__file__,
    "scenarios": packsim.bundled_scenario_dir(),
    "default_exists": os.path.isfile(packsim.default_scenario()),
    "version": packsim.__version__,
}))
"""


@pytest.mark.slow
def test_pip_install_builds_a_working_package(tmp_path, simple_yaml):
    # No build isolation: the build tools of this environment (scripts/install-deps.sh
    # installs scikit-build-core and pybind11), and a persistent CMake build folder so a
    # rerun only rebuilds what changed. The wheel builds the extension target alone.
    site = tmp_path / "site"
    cmd = [sys.executable, "-m", "pip", "install", str(REPO), "--no-deps", "--no-build-isolation", "--no-cache-dir",
           "--target", str(site), f"--config-settings=build-dir={REPO / 'build-wheel'}", "-q"]
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]

    pkg = site / "packsim"
    assert (pkg / "_packsim.pyi").is_file() and (pkg / "py.typed").is_file()
    assert list(pkg.glob("_packsim*.so"))

    # A fresh interpreter that sees only the installed package (not the build tree).
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PACKSIM_SCENARIOS")}
    env["PYTHONPATH"] = str(site)
    out = tmp_path / "installed.h5"
    probe = subprocess.run([sys.executable, "-c", PROBE, str(out)], input=simple_yaml, capture_output=True,
                           text=True, cwd=tmp_path, env=env)
    assert probe.returncode == 0, probe.stderr
    import json
    info = json.loads(probe.stdout.strip().splitlines()[-1])
    assert Path(info["package"]).parent == pkg and Path(info["extension"]).parent == pkg
    assert Path(info["scenarios"]) == pkg / "scenarios" and info["default_exists"]
    assert info["version"] == packsim.__version__

    # Same scenario and seed as the CMake build's module: same datasets, same values
    # (the wheel is a Release build, the CMake tree RelWithDebInfo: allow rounding).
    installed = packsim.load(out)
    here = packsim.run(simple_yaml, seed=3)
    assert installed.keys() == here.keys() and installed.seed == here.seed == 3
    for k in here.keys():
        a, b = installed[k], here[k]
        assert a.dtype == b.dtype and a.shape == b.shape, k
        if a.dtype.kind == "f":
            np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-12, err_msg=k)
    np.testing.assert_array_equal(installed["measured/cell_voltage_mV"], here["measured/cell_voltage_mV"])
    assert installed.events == here.events
