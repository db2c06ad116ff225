"""scripts/install-deps.sh: its argument handling, that its `--run` set (README command 1)
holds what the packsim program needs and none of what only the tests need, and where the
Python packages go on Debian's own python3. Runs the script's --help / --list paths only:
nothing is installed."""
from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "scripts" / "install-deps.sh"


def deps(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["bash", str(SCRIPT), *args], capture_output=True, text=True, timeout=30)


def listed(*mode: str) -> tuple[set[str], set[str]]:
    done = deps("--list", *mode)
    assert done.returncode == 0, done.stderr
    lines = dict(line.split(":", 1) for line in done.stdout.splitlines())
    assert set(lines) == {"apt", "pip"}, done.stdout
    return set(lines["apt"].split()), set(lines["pip"].split())


def test_help_names_every_mode_and_installs_nothing():
    done = deps("--help")
    assert done.returncode == 0, done.stderr
    for mode in ("--run", "--python", "--list"):
        assert mode in done.stdout
    assert "install-deps:" not in done.stdout + done.stderr  # what it says when it installs or checks


def test_an_unknown_argument_is_refused_with_exit_2_and_the_allowed_ones():
    done = deps("--runn")
    assert done.returncode == 2
    assert "unknown argument '--runn'" in done.stderr and "--run" in done.stderr
    assert "install-deps: apt-get install" not in done.stdout + done.stderr


def test_the_sets_nest_and_the_run_set_leaves_out_what_only_the_tests_need():
    run_apt, run_pip = listed("--run")
    py_apt, py_pip = listed("--python")
    test_apt, test_pip = listed()
    assert (test_apt, test_pip) == listed("--test")  # no argument: everything the test command needs
    assert run_apt < py_apt < test_apt and set() == run_pip < py_pip < test_pip
    for only_tests in ("libgtest-dev", "gcc-arm-none-eabi", "clang", "chromium"):
        assert only_tests in test_apt and only_tests not in py_apt
    assert {"pybind11-dev", "python3-dev"} <= py_apt - run_apt
    assert {"pytest", "fmpy"} <= test_pip - py_pip and {"numpy", "scikit-build-core"} <= py_pip


# What each REQUIRED dependency of the program's configuration is found by: a file its
# Debian package installs. The packaging test of record is dpkg: who owns that file.
FOUND_BY = {
    "SUNDIALS": "/SUNDIALSConfig.cmake",
    "yaml-cpp": "/yaml-cpp-config.cmake",
    "HDF5": "/hdf5_hl.h",
    "Eigen3": "/Eigen3Config.cmake",
    "CLI11": "/CLI11Config.cmake",
    "unicorn": "/unicorn.pc",
    "capstone": "/capstone.pc",
    "libzip": "/libzip.pc",
}


def required_dependencies() -> set[str]:
    """Every find_package(X REQUIRED) and pkg_check_modules(... REQUIRED ... module) that
    configuring the program runs (the tests' GoogleTest is under PACKSIM_BUILD_TESTS)."""
    names = set()
    for cmake in (REPO / "CMakeLists.txt", *REPO.glob("core/**/CMakeLists.txt"), *REPO.glob("models/**/CMakeLists.txt"),
                  *REPO.glob("bms/**/CMakeLists.txt")):
        text = cmake.read_text()
        names |= {m for m in re.findall(r"find_package\((\S+)[^)]*\bREQUIRED\b", text) if m != "PkgConfig"}
        names |= {m.split()[-1] for m in re.findall(r"pkg_check_modules\(\w+ REQUIRED ([^)]*)\)", text)}
    return names


def test_the_run_set_holds_the_package_of_every_required_dependency():
    assert required_dependencies() == set(FOUND_BY), "a new required dependency: add it to install-deps' --run set"
    if not shutil.which("dpkg"):
        pytest.skip("not a Debian system: no dpkg to say which package owns a file")
    done = subprocess.run(["dpkg", "-S", *(f"*{file}" for file in FOUND_BY.values())], capture_output=True, text=True, timeout=30)
    owners = {}
    for line in done.stdout.splitlines():
        pkgs, _, path = line.partition(": ")
        for name, file in FOUND_BY.items():
            if path.endswith(file):
                owners.setdefault(name, set()).update(p.split(":")[0] for p in pkgs.split(", "))
    missing = set(FOUND_BY) - set(owners)
    if missing:
        pytest.skip(f"not installed here: {', '.join(sorted(missing))}")
    run_apt, _ = listed("--run")
    for name, pkgs in owners.items():
        assert pkgs & run_apt, f"{name} ({FOUND_BY[name]}) comes from {pkgs}, not in install-deps --run"


def test_debian_s_own_python3_gets_the_project_venv_and_a_chosen_python_is_used_as_it_is():
    """Debian's python3 refuses `pip install` (externally managed, PEP 668): the Python
    packages are to go into the project's .venv. PYTHON=... (or pyenv, conda, an active
    venv) is used as it is."""
    import os
    debian = Path("/usr/bin/python3")
    marker = subprocess.run([str(debian), "-c", "import sysconfig; print(sysconfig.get_path('stdlib'))"],
                            capture_output=True, text=True).stdout.strip() if debian.exists() else ""
    if not marker or not (Path(marker) / "EXTERNALLY-MANAGED").exists():
        pytest.skip("no externally managed /usr/bin/python3 on this machine")
    env = {k: v for k, v in os.environ.items() if k != "PYTHON"}
    env["PATH"] = "/usr/bin:/bin"
    done = subprocess.run(["bash", str(SCRIPT), "--list", "--python"], capture_output=True, text=True, timeout=30, env=env)
    assert done.returncode == 0, done.stderr
    assert f"pip (into {REPO / '.venv'}: /usr/bin/python3 is externally managed, PEP 668): numpy" in done.stdout
    env["PYTHON"] = str(debian)
    chosen = subprocess.run(["bash", str(SCRIPT), "--list", "--python"], capture_output=True, text=True, timeout=30, env=env)
    assert "\npip: numpy" in "\n" + chosen.stdout and ".venv" not in chosen.stdout
    # --run has no Python packages: no venv either
    env.pop("PYTHON")
    run = subprocess.run(["bash", str(SCRIPT), "--list", "--run"], capture_output=True, text=True, timeout=30, env=env)
    assert ".venv" not in run.stdout


def test_without_root_and_without_sudo_it_says_so_and_fails_before_apt(tmp_path):
    """A minimal Debian 12 has no sudo: a user who is not root gets one clear line naming
    what is missing and how to run it, exit 1, and apt-get is never called."""
    import os
    fake = tmp_path / "bin"
    fake.mkdir()
    calls = tmp_path / "calls"
    for name, body in {"id": "echo 1000",                      # not root
                       "dpkg-query": "exit 1",                 # nothing installed
                       "apt-get": f"echo apt-get >> {calls}",  # must not be reached
                       }.items():
        (fake / name).write_text(f"#!/bin/sh\n{body}\n")
        (fake / name).chmod(0o755)
    for tool in ("grep",):  # what the script runs on the way; no sudo on this PATH
        (fake / tool).symlink_to(shutil.which(tool))
    done = subprocess.run([shutil.which("bash"), str(SCRIPT), "--run"], capture_output=True, text=True, timeout=30,
                          env={**os.environ, "PATH": str(fake)})
    assert done.returncode == 1, done.stdout + done.stderr
    assert "needs root, and there is no sudo here" in done.stderr
    assert "libsundials-dev" in done.stderr and "su -c 'bash scripts/install-deps.sh --run'" in done.stderr
    assert not calls.exists()
