#!/usr/bin/env bash
# Installs what a fresh Debian machine lacks to build, run and test packsim.
# Idempotent: packages already present are skipped, so running it twice is cheap.
#
#   scripts/install-deps.sh            everything the test command (scripts/test.sh) needs (CI)
#   scripts/install-deps.sh --run      only what building the packsim program and `packsim run` need
#                                      (README command 1: TARGETS=packsim scripts/build.sh)
#   scripts/install-deps.sh --python   --run, plus what the Python module and `pip install .` need
#   scripts/install-deps.sh --list [--run|--python]   print the packages of that set, install nothing
set -euo pipefail

usage() {
  sed -n '5,9s/^#   /  /p' "$0"
}

mode=test
list=0
for arg in "$@"; do
  case $arg in
    --run) mode=run ;;
    --python) mode=python ;;
    --test) mode=test ;;
    --list) list=1 ;;
    -h | --help) echo "usage:"; usage; exit 0 ;;
    *) echo "install-deps: unknown argument '$arg'; expected one of --run, --python, --test, --list, --help" >&2
       echo "usage:" >&2; usage >&2; exit 2 ;;
  esac
done

# The packsim program (CMakeLists.txt: every REQUIRED find_package / pkg_check_modules).
# libsundials-dev is most of this set's download: Debian's package depends on PETSc, hypre,
# MPI and gfortran, which packsim does not use (README, "Quick start").
APT_RUN=(
  build-essential cmake ninja-build pkg-config ccache
  libsundials-dev libsuitesparse-dev libyaml-cpp-dev libhdf5-dev libeigen3-dev libcli11-dev
  libzip-dev                  # packsim fmu: writes the FMU archive
  libunicorn-dev libcapstone-dev  # bms.firmware.target: cortex-m4: the ARM emulator and the disassembler of its cycle model
)
# The Python module packsim._packsim (pybind11, the interpreter's headers).
# python3-venv: Debian's python3 is "externally managed" (PEP 668): pip refuses to install
# into it, so the Python packages go into the project's .venv (below).
APT_PYTHON=(pybind11-dev python3-dev python3-venv)
# What only the tests need.
APT_TEST=(
  libgtest-dev libgmock-dev
  gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib  # the Cortex-M4 builds of the core and the example firmware
  # scripts/fuzz.sh: clang with libFuzzer (compiler-rt) and the OpenMP that SUNDIALS' CMake config asks for
  clang libclang-rt-14-dev libomp-14-dev
  chromium chromium-driver    # tests/python/test_report_browser.py: the report pages in headless Chromium
)
# Python: the package's needs and the build tools `pip install --no-build-isolation .` uses.
PIP_PYTHON=(numpy h5py pyyaml scikit-build-core pybind11)
# The optional ones the tests exercise (plots, tables, notebooks, Dask, the FMU, BPX).
PIP_TEST=(pytest matplotlib plotly selenium pandas xarray h5netcdf scipy pyarrow tqdm ipywidgets nbformat nbclient ipykernel
          "dask[distributed]"
          fmpy   # the FMI 2.0 headers the FMU library builds against, and the FMU tests' importer
          bpx    # packsim fit --bpx / packsim.from_bpx: writes and validates the Battery Parameter eXchange format
          pytest-xdist)  # scripts/test.sh runs the Python tests on two worker processes (pytest -n 2)

APT_PACKAGES=("${APT_RUN[@]}")
PIP_PACKAGES=()
if [ "$mode" != run ]; then
  APT_PACKAGES+=("${APT_PYTHON[@]}")
  PIP_PACKAGES+=("${PIP_PYTHON[@]}")
fi
if [ "$mode" = test ]; then
  APT_PACKAGES+=("${APT_TEST[@]}")
  PIP_PACKAGES+=("${PIP_TEST[@]}")
fi

PY=${PYTHON:-python3}
# Debian's own python3 refuses `pip install` (PEP 668: its stdlib folder holds an
# EXTERNALLY-MANAGED file). Then the Python packages go into .venv in the source folder,
# made with the system's packages visible; scripts/build.sh and scripts/test.sh put its
# bin/ first on PATH when it exists, so `python3` there is the venv's (activate it with
# `. .venv/bin/activate` for your own shell). A Python of your own (pyenv, conda, a venv
# you activated, or PYTHON=...) is used as it is.
# (Asked before apt too, for --list; again after it, which may have brought python3.)
find_venv() {
  VENV=""
  if [ -z "${PYTHON:-}" ] && [ ${#PIP_PACKAGES[@]} -gt 0 ] && "$PY" -c '
import os, sys, sysconfig
managed = os.path.exists(os.path.join(sysconfig.get_path("stdlib"), "EXTERNALLY-MANAGED"))
sys.exit(0 if managed and sys.prefix == sys.base_prefix else 1)' 2>/dev/null; then
    VENV="$(cd "$(dirname "$0")/.." && pwd)/.venv"
  fi
}
find_venv

if [ "$list" = 1 ]; then
  echo "apt: ${APT_PACKAGES[*]}"
  if [ -n "$VENV" ]; then
    echo "pip (into $VENV: $("$PY" -c 'import sys; print(sys.executable)') is externally managed, PEP 668): ${PIP_PACKAGES[*]}"
  else
    echo "pip: ${PIP_PACKAGES[*]}"
  fi
  exit 0
fi

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  # A minimal Debian has no sudo (the installer adds it only when no root password is set).
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    if ! command -v sudo >/dev/null 2>&1; then
      echo "install-deps: installing ${missing[*]} needs root, and there is no sudo here: run this script as root (su -c 'bash scripts/install-deps.sh $*') or install sudo" >&2
      exit 1
    fi
    SUDO="sudo"
  fi
  echo "install-deps: apt-get install ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

find_venv
if [ -n "$VENV" ]; then
  if [ ! -x "$VENV/bin/python3" ]; then
    echo "install-deps: $("$PY" -c 'import sys; print(sys.executable)') is externally managed (PEP 668): the Python packages go into $VENV"
    "$PY" -m venv --system-site-packages "$VENV"
  fi
  PY=$VENV/bin/python3
fi
need_pip=()
for p in "${PIP_PACKAGES[@]}"; do
  case $p in
    pyyaml) mod=yaml ;;
    "dask[distributed]") mod=distributed ;;
    pytest-xdist) mod=xdist ;;
    *) mod=${p//-/_} ;;
  esac
  "$PY" -c "import $mod" 2>/dev/null || need_pip+=("$p")
done
if [ ${#need_pip[@]} -gt 0 ]; then
  echo "install-deps: pip install ${need_pip[*]}"
  "$PY" -m pip install -q "${need_pip[@]}"
fi
echo "install-deps: all dependencies of the '$mode' set present"
