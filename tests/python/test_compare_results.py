"""scripts/compare_results.py: the bit-identical proof finds every kind of difference
(a flipped bit, a NaN payload, a signed zero, an attribute, an event string, a missing
dataset) and ignores only the attributes it lists."""
from __future__ import annotations

import importlib.util
from pathlib import Path

import h5py
import numpy as np
import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "compare_results.py"
spec = importlib.util.spec_from_file_location("compare_results", SCRIPT)
compare_results = importlib.util.module_from_spec(spec)
spec.loader.exec_module(compare_results)


def write(path: Path, edit=None) -> Path:
    """A small result-like file; `edit(f)` changes it before closing."""
    with h5py.File(path, "w") as f:
        f.attrs["packsim_version"] = "0.1.0"
        f.attrs["seed"] = 42
        g = f.create_group("truth")
        d = g.create_dataset("cell_voltage_V", data=np.array([[3.7, np.nan], [0.0, 3.6]]))
        d.attrs["units"] = "V"
        t = f.create_dataset("time_s", data=np.arange(2.0))
        t.make_scale("time_s")
        d.dims[0].attach_scale(t)
        ev = np.array([(1.0, "fault_active", "estop: E-switch pulled")],
                      dtype=[("time_s", "f8"), ("kind", h5py.string_dtype()), ("detail", h5py.string_dtype())])
        f.create_dataset("events", data=ev)
        f.create_group("summary").attrs["trip_reason"] = "estop"
        if edit:
            edit(f)
    return path


def diffs(tmp_path, edit):
    return compare_results.compare_files(write(tmp_path / "a.h5"), write(tmp_path / "b.h5", edit))


def set_value(path, index, value):
    def edit(f):
        a = f[path][()]
        a[index] = value
        f[path][...] = a
    return edit


def test_identical_files_are_the_same(tmp_path):
    assert diffs(tmp_path, None) == []


def test_the_version_string_is_ignored_and_listed(tmp_path):
    assert diffs(tmp_path, lambda f: f.attrs.modify("packsim_version", "0.2.0")) == []
    assert "/ @packsim_version" in compare_results.__doc__


def test_one_flipped_bit_is_a_difference(tmp_path):
    x = np.nextafter(3.6, 4.0)
    d = diffs(tmp_path, set_value("truth/cell_voltage_V", (1, 1), x))
    assert len(d) == 1 and d[0].startswith("/truth/cell_voltage_V: values differ (first at flat index 3")


@pytest.mark.parametrize("value", [-0.0, np.frombuffer(np.uint64(0x7FF8000000000001).tobytes(), "f8")[0]],
                         ids=["signed zero", "NaN payload"])
def test_values_equal_as_numbers_but_not_as_bits_differ(tmp_path, value):
    index = (1, 0) if value == 0 else (0, 1)
    assert diffs(tmp_path, set_value("truth/cell_voltage_V", index, value))


def test_the_same_nan_is_the_same(tmp_path):
    assert diffs(tmp_path, set_value("truth/cell_voltage_V", (0, 1), np.nan)) == []


def test_attributes_events_and_missing_objects_differ(tmp_path):
    d = diffs(tmp_path, lambda f: f["summary"].attrs.modify("trip_reason", "estop2"))
    assert len(d) == 1 and d[0].startswith("/summary @trip_reason: ") and "estop2" in d[0]

    def other_event(f):
        ev = f["events"][()]
        ev[0]["detail"] = "estop: E-switch pulled for 1 ms"
        f["events"][...] = ev
    assert any(d.startswith("/events: values differ") for d in diffs(tmp_path, other_event))
    assert diffs(tmp_path, lambda f: f.create_dataset("extra", data=[1])) == ["/extra only in new"]
    assert diffs(tmp_path, lambda f: f["truth/cell_voltage_V"].attrs.__delitem__("units")) == \
        ["/truth/cell_voltage_V @units only in base"]


def test_bundled_scenarios_are_what_check_runs(tmp_path):
    (tmp_path / "cells").mkdir()
    (tmp_path / "cells" / "preset.yaml").write_text("x: 1\n")
    (tmp_path / "faults").mkdir()
    (tmp_path / "faults" / "b.yaml").write_text("x: 1\n")
    (tmp_path / "a.yaml").write_text("x: 1\n")
    found = compare_results.bundled_scenarios(str(tmp_path))
    assert [Path(p).relative_to(tmp_path).as_posix() for p in found] == ["a.yaml", "faults/b.yaml"]
