"""`pip install .` builds the extension with scikit-build-core from the same CMake project,
and the installed package works on its own: imports from where pip put it, finds the
bundled scenarios inside itself, ships its type hints, simulates what the CMake
build simulates, and installs the `packsim` command (the program shipped in the wheel)
that runs bundled scenarios by name from any folder. Nothing compiled in points into the
source tree."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import packsim
from stored import assert_as_stored

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
    # One build: the wheel, then `pip install` of that wheel (what `pip install .` does).
    # The test command has just compiled the same sources in build/ (RelWithDebInfo, through
    # ccache when installed: scripts/build.sh); `pip install .` builds with that build type
    # and the same cache settings (pyproject.toml, CMakeLists.txt), so its objects are cache
    # hits and only the link is new work. Here the wheel also takes build/'s compilers and
    # pybind11, so that the bindings hit as well.
    site, dist = tmp_path / "site", tmp_path / "dist"
    cmd = [sys.executable, "-m", "pip", "wheel", str(REPO), "--no-deps", "--no-build-isolation", "--no-cache-dir",
           "-w", str(dist), f"--config-settings=build-dir={REPO / 'build-wheel'}", "-q"]
    env = dict(os.environ)
    if shutil.which("ccache") and not os.environ.get("PACKSIM_NO_CCACHE"):
        build = _cmake_build_cache()
        env.update({var: build[key] for var, key in (("CXX", "CMAKE_CXX_COMPILER"), ("CC", "CMAKE_C_COMPILER"))
                    if key in build})
        if "pybind11_DIR" in build:  # the same pybind11 headers, not pip's copy: the bindings hit too
            cmd.append(f"--config-settings=cmake.define.pybind11_DIR={build['pybind11_DIR']}")
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path, env=env)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    wheels = list(dist.glob("packsim-*.whl"))
    assert len(wheels) == 1
    done = subprocess.run([sys.executable, "-m", "pip", "install", str(wheels[0]), "--no-deps", "--no-cache-dir",
                           "--target", str(site), "-q"], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]

    pkg = site / "packsim"
    assert (pkg / "_packsim.pyi").is_file() and (pkg / "py.typed").is_file()
    assert list(pkg.glob("_packsim*.so"))
    program = pkg / "_bin" / "packsim"
    assert program.is_file() and os.access(program, os.X_OK)
    # No path into the source tree is in what the wheel ships. The objects are compiled with
    # debug information (RelWithDebInfo, as build/), whose DW_AT_comp_dir names the folder
    # they were first compiled in; the wheel's binaries are stripped on install
    # (pyproject.toml: install.strip), so no debug section is left, and code, data and
    # strings hold no source path.
    for binary in [program, *pkg.glob("_packsim*.so")]:
        data = binary.read_bytes()
        assert data[:4] == b"\x7fELF", binary
        assert b".debug_info" not in data and b".debug_line" not in data, f"{binary} is not stripped"
        assert str(REPO).encode() not in data, binary

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
    # (compared as stored, to a tolerance: a wheel built with another compiler or build type
    # than build/, e.g. `pip install -C cmake.build-type=Release .`, may differ in the last
    # bits, and a value on a half step of its stored resolution may round either way).
    installed = packsim.load(out)
    here = packsim.run(simple_yaml, seed=3)
    assert installed.seed == here.seed == 3
    floats = [k for k in here.keys() if here[k].dtype.kind == "f"]
    assert floats
    assert_as_stored(installed, here, steps=1.0, rtol=1e-9, only=floats)
    np.testing.assert_array_equal(installed["measured/cell_voltage_mV"], here["measured/cell_voltage_mV"])
    assert installed.events == here.events

    check_installed_command(site, tmp_path)


def _cmake_build_cache() -> dict[str, str]:
    """The CMake cache of the build whose module is under test: its compilers as CMake found
    them (ccache keys on the compiler's name too, and a pip-installed CMake picks g++ where
    Debian's picks c++, the same program, which would miss every object) and its pybind11."""
    cache = Path(packsim._packsim.__file__).resolve().parents[2] / "CMakeCache.txt"
    if not cache.is_file():
        return {}
    found = {}
    for line in cache.read_text().splitlines():
        key, sep, value = line.partition("=")
        if sep and ":" in key and not key.startswith(("//", "#")):
            found[key.split(":", 1)[0]] = value
    return found


def _installed_env(site: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PACKSIM_SCENARIOS", "PACKSIM_PYTHONPATH", "PACKSIM_PYTHON")}
    env["PYTHONPATH"] = str(site)
    return env


def check_installed_command(site: Path, tmp_path: Path) -> None:
    """The console script and `python -m packsim` of an installed package, run from a
    folder with no scenarios in it."""
    script = site / "bin" / "packsim"
    assert script.is_file(), "pip installed no packsim command"
    env = _installed_env(site)
    work = tmp_path / "elsewhere"
    work.mkdir()
    listed = subprocess.run([str(script), "list"], capture_output=True, text=True, cwd=work, env=env)
    assert listed.returncode == 0, listed.stderr
    assert "motorcycle_110s" in listed.stdout and str(site / "packsim" / "scenarios") in listed.stdout
    ran = subprocess.run([sys.executable, "-m", "packsim", "run", "bench_6s_ncr18650_2C", "-o", "b.h5", "-q",
                          "--set", "pack.initial_soc=0.8"], capture_output=True, text=True, cwd=work, env=env)
    assert ran.returncode == 0, ran.stderr
    here = packsim.run("bench_6s_ncr18650_2C", {"pack.initial_soc": 0.8})
    assert_as_stored(packsim.load(work / "b.h5"), here, steps=1.0, only=["truth/cell_voltage_V"])
    # export through the installed command uses the installed package and interpreter
    exp = subprocess.run([str(script), "export", "b.h5", "--format", "csv"], capture_output=True, text=True,
                         cwd=work, env=env)
    assert exp.returncode == 0, exp.stderr
    assert (work / "b_csv" / "samples.csv").is_file()
