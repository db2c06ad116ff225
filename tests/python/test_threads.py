"""The GIL is released while the C++ simulation runs: other Python threads keep
running, and two threads simulate at once with the same results as one after another."""
from __future__ import annotations

import threading
import time

import numpy as np

import packsim
from packsim import _packsim
from packsim._overrides import flatten_overrides


def test_gil_is_released_during_the_simulation(default_scenario):
    pairs = flatten_overrides({"load.laps": 20})  # long enough for many 5 ms beats

    done = threading.Event()
    span = {}

    def work():
        span["start"] = time.perf_counter()
        _packsim.run(default_scenario, True, pairs)
        span["end"] = time.perf_counter()
        done.set()

    th = threading.Thread(target=work)
    beats = []
    th.start()
    while not done.is_set():
        beats.append(time.perf_counter())
        time.sleep(0.005)
    th.join()
    inside = [b for b in beats if span["start"] <= b <= span["end"]]
    # Holding the GIL, the C++ call would freeze this loop for its whole duration.
    assert len(inside) >= 10, f"main thread ran {len(inside)} times during a {span['end'] - span['start']:.2f} s run"
    gaps = np.diff(inside)
    assert gaps.max() < 0.5 * (span["end"] - span["start"])


def test_two_threads_give_the_serial_results(simple_yaml):
    settings = [{"pack.cell.capacity_Ah": 2.5, "seed": 1}, {"pack.cell.capacity_Ah": 3.5, "seed": 2}]
    serial = [packsim.run(simple_yaml, s, run={"duration_s": 3000}) for s in settings]
    results: list = [None, None]
    errors: list = []
    barrier = threading.Barrier(2)

    def work(i):
        try:
            barrier.wait()
            results[i] = packsim.run(simple_yaml, settings[i], run={"duration_s": 3000})
        except Exception as e:  # pragma: no cover - reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for got, want in zip(results, serial):
        assert got.keys() == want.keys()
        for k in want.keys():
            if want[k].dtype.names is None:
                assert got[k].tobytes() == want[k].tobytes(), k
    assert not np.array_equal(results[0]["truth/cell_soc"], results[1]["truth/cell_soc"])
