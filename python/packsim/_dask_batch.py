"""A sweep on a Dask distributed cluster, one task per case (``packsim.batch(sweep, client)``).

    submit the first `max_in_flight` cases (default: twice the cluster's worker threads)
    for each case as it finishes (any order):
        its outcome (ok, skipped, error, the run summary: ~1 kB) -> journal line, flushed
        its future is released: no result stays on a worker or the client
        submit the next case
    all done: summary.csv (as the thread pool writes it); the journal is removed

Each task runs the C++ function the local thread pool runs (``run_sweep_case``): it
writes its own ``case_<id>.h5`` on the worker (to a temporary name, renamed when
complete) and returns only the summary, so memory stays bounded by the window, not by
the number of cases. A complete result file holding the very scenario text of its case
(the varied values and the seed included) is skipped on a rerun: that is the resume.

The journal, ``<output_dir>/summary.running.jsonl``, is the incremental summary while
the sweep runs: one JSON line per finished case (case id, status, error, summary). If
the run stops early (Ctrl-C, an exception, the client killed) the journal stays and
lists what finished; on an exception or Ctrl-C summary.csv is written too, the cases
not finished marked ``not run (interrupted)``.
"""
from __future__ import annotations

import json
import os
import sys
import time
from typing import Any

JOURNAL = "summary.running.jsonl"


def _case_task(index: int, sweep, resume: bool) -> dict:
    """One Dask task: one case, by the C++ function the local thread pool runs."""
    from . import _core
    return _core().run_sweep_case(sweep, index, resume)


def _not_run(why: str) -> dict:
    return {"ok": False, "skipped": False, "wall_s": 0.0, "error": why, "summary": []}


def _journal_line(index: int, case_id: str, outcome: dict) -> str:
    return json.dumps({"case": case_id, "index": index, **outcome}) + "\n"


def _worker_threads(client: Any) -> int:
    try:
        return max(1, sum(client.nthreads().values()))
    except Exception:  # a client that cannot tell yet: the window still bounds memory
        return 1


def run_on_dask(core, sw, client: Any, *, resume: bool, progress: bool, max_in_flight: int | None):
    """Every case of `sw` on `client`'s cluster; (outcomes in sweep order, summary.csv path, wall s)."""
    from distributed import as_completed

    t0 = time.perf_counter()
    n = len(sw)
    window = max_in_flight or 2 * _worker_threads(client)
    os.makedirs(sw.output_dir, exist_ok=True)
    journal_path = os.path.join(sw.output_dir, JOURNAL)
    outcomes: list[dict | None] = [None] * n
    shared = client.scatter(sw, broadcast=True, hash=False)  # the sweep (with the base text) goes to each worker once
    tag = os.urandom(4).hex()
    cases = sw.cases

    def submit(i: int):
        return client.submit(_case_task, i, sweep=shared, resume=resume, pure=False,
                             key=f"packsim-{sw.name}-case_{cases[i][1]}-{tag}")

    pending: dict[str, tuple[int, Any]] = {}
    queue = as_completed()
    next_index = 0
    done = 0
    try:
        with open(journal_path, "w", encoding="utf-8") as journal:
            while next_index < n and len(pending) < window:
                f = submit(next_index)
                pending[f.key] = (next_index, f)
                queue.add(f)
                next_index += 1
            for f in queue:
                i, _ = pending.pop(f.key)
                try:
                    o = f.result()
                except Exception as e:  # the task itself died (e.g. its worker was killed)
                    o = _not_run(f"the case's task failed: {type(e).__name__}: {e}")
                f.release()
                outcomes[i] = o
                done += 1
                journal.write(_journal_line(i, cases[i][1], o))
                journal.flush()
                if progress:
                    what = "skipped (complete result)" if o["skipped"] else "ok" if o["ok"] else f"FAILED: {o['error']}"
                    print(f"[{done}/{n}] case_{cases[i][1]} {what}", file=sys.stdout, flush=True)
                if next_index < n:
                    g = submit(next_index)
                    pending[g.key] = (next_index, g)
                    queue.add(g)
                    next_index += 1
    except BaseException:
        for _, f in pending.values():
            f.cancel()
        core.write_summary_csv(sw, [o if o is not None else _not_run("not run (interrupted)") for o in outcomes])
        raise
    csv_path = core.write_summary_csv(sw, outcomes)
    os.remove(journal_path)
    return outcomes, csv_path, time.perf_counter() - t0
