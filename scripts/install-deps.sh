#!/usr/bin/env bash
# Installs what a fresh Debian machine lacks to build and test packsim.
# Idempotent: packages already present are skipped, so running it twice is cheap.
set -euo pipefail

APT_PACKAGES=(
  build-essential cmake ninja-build pkg-config ccache
  libsundials-dev libsuitesparse-dev libyaml-cpp-dev libhdf5-dev libeigen3-dev libgtest-dev libgmock-dev
  pybind11-dev libcli11-dev
  libzip-dev                  # packsim fmu: writes the FMU archive
  libunicorn-dev libcapstone-dev  # bms.firmware.target: cortex-m4: the ARM emulator and the disassembler of its cycle model
  gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib
  # scripts/fuzz.sh: clang with libFuzzer (compiler-rt) and the OpenMP that SUNDIALS' CMake config asks for
  clang libclang-rt-14-dev libomp-14-dev
  chromium chromium-driver    # tests/python/test_report_browser.py: the report pages in headless Chromium
)
# Python: the package's needs, the optional ones its tests exercise (tables, notebooks,
# Dask), and the build tools `pip install .` uses without build isolation.
PIP_PACKAGES=(numpy h5py pytest matplotlib plotly selenium pyyaml pandas xarray h5netcdf scipy pyarrow tqdm ipywidgets nbformat nbclient ipykernel
              "dask[distributed]" scikit-build-core pybind11
              fmpy   # the FMI 2.0 headers the FMU library builds against, and the FMU tests' importer
              bpx    # packsim fit --bpx / packsim.from_bpx: writes and validates the Battery Parameter eXchange format
              pytest-xdist)  # scripts/test.sh runs the Python tests on two worker processes (pytest -n 2)

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "install-deps: apt-get install ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

PY=${PYTHON:-python3}
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
echo "install-deps: all dependencies present"
