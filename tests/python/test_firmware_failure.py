"""A firmware that fails (does not load, breaks the contract, crashes, hangs) is a failed
run in Python and in a batch too, as `packsim run` exits 1 for it (tests/core/
firmware_failure_test.cpp covers each cause at the CLI): packsim.run raises
FirmwareError carrying the run, a batch counts the case failed and writes no file for it;
a scenario that expects the failure (expect: {firmware_fault: true}) runs as before."""
from pathlib import Path

import pytest

import packsim


def _bench_on(lib: Path, extra: str = "") -> str:
    bench = packsim.bundled_scenarios("bench_6s_ncr18650_2C.yaml")[0]
    return (f"extends: {bench}\nname: fw_fail\nbms: {{tick_ms: 10, firmware: {{library: {lib}}}}}\n"
            "load: {current_A: 1.0}\nrun: {duration_s: 2}\n" + extra)


def test_a_firmware_that_does_not_load_raises_with_the_run(tmp_path):
    lib = tmp_path / "not_a_library.so"
    lib.write_text("this is not a shared library\n")
    with pytest.raises(packsim.FirmwareError, match="not_a_library.so") as err:
        packsim.run(_bench_on(lib))
    assert isinstance(err.value, RuntimeError)
    r = err.value.result
    assert r is not None and r.summary["duration_s"] == pytest.approx(2.0)
    assert any(e["kind"] == "firmware_fault" for e in r.events)
    # Meant to fail: the same run, no error.
    r2 = packsim.run(_bench_on(lib, "expect: {firmware_fault: true}\n"))
    assert r2.summary["duration_s"] == pytest.approx(2.0)


def test_a_batch_counts_a_failed_firmware_as_a_failed_case(tmp_path):
    lib = tmp_path / "not_a_library.so"
    lib.write_text("this is not a shared library\n")
    base = tmp_path / "fw.yaml"
    base.write_text(_bench_on(lib))
    sweep = tmp_path / "sweep.yaml"
    sweep.write_text(f"base: {base}\ngrid: {{pack.initial_soc: [0.8, 0.9]}}\n")
    res = packsim.batch(str(sweep), output_dir=str(tmp_path / "out"))
    assert res.n_failed == 2 and res.n_ok == 0 and not res.ok
    assert all("not_a_library.so" in o["error"] for o in res.outcomes)
    assert not list((tmp_path / "out").glob("case_*.h5"))
