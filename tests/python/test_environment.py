"""Under CI every optional dependency is installed (scripts/install-deps.sh), so no test
that would `importorskip` one is silently skipped there."""
from __future__ import annotations

import importlib
import os

import pytest

# Modules some tests import only when present, and xdist (pytest-xdist: scripts/test.sh runs
# the tests on two workers, pytest -n 2); scripts/install-deps.sh installs them all.
OPTIONAL = ["pandas", "xarray", "nbformat", "nbclient", "ipykernel", "distributed", "scikit_build_core", "yaml", "fmpy",
            "bpx", "xdist"]


def _missing() -> list[str]:
    out = []
    for m in OPTIONAL:
        try:
            importlib.import_module(m)
        except ImportError:
            out.append(m)
    return out


def test_optional_test_dependencies_are_installed():
    missing = _missing()
    if missing and os.environ.get("CI", "").lower() not in ("1", "true", "yes"):
        pytest.skip(f"not installed (some tests skip): {', '.join(missing)}; run scripts/install-deps.sh")
    assert not missing, f"scripts/install-deps.sh did not install: {', '.join(missing)}"
