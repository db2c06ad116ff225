"""packsim.run(..., progress=True): a tqdm bar over simulated time. tqdm.auto picks the
notebook widget in Jupyter (nothing is printed to the kernel's stdout) and a text bar
on stderr elsewhere."""
from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator


@contextlib.contextmanager
def tqdm_progress() -> Iterator[Callable[[float, float], None]]:
    try:
        from tqdm.auto import tqdm
    except ImportError as e:
        raise ImportError("progress=True needs tqdm (pip install tqdm), or pass a callable(t_s, end_s)") from e
    bar = None
    done = [0.0]

    def report(t_s: float, end_s: float) -> None:
        nonlocal bar
        if bar is None:
            bar = tqdm(total=round(end_s, 3), unit="s", unit_scale=True, desc="simulated", leave=False)
        bar.update(round(t_s - done[0], 3))
        done[0] = t_s

    try:
        yield report
    finally:
        if bar is not None:
            bar.close()
