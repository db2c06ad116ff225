"""Compare a result read from a file with the run held in memory.

Float channels are stored to a stated `resolution` (docs/results.md, "Storage and
resolution"): the file holds each value within half of it, or as exactly 0 when it lies
within one step of 0 (HDF5's scale-offset filter keeps its fill value, 0, for those).
Everything else (integer channels, tables, strings) is stored bit for bit."""
from __future__ import annotations

import numpy as np


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    if a.dtype != b.dtype or a.shape != b.shape:
        return False
    if a.dtype.names:
        return all(same_bits(np.asarray(a[n]), np.asarray(b[n])) for n in a.dtype.names)
    if a.dtype.kind == "O":
        return a.tolist() == b.tolist()
    return a.tobytes() == b.tobytes()


def assert_as_stored(stored, held, *, steps: float = 0.5, rtol: float = 0.0, only=None) -> None:
    """`stored` (read from a file) holds `held` (the run in memory), dataset by dataset
    (`only`: just these): float channels with a resolution within `steps` of it (0.5:
    rounding; 1: two builds whose last bits differ may round a value on a half step either
    way), other floats within `rtol` (0: bit for bit), everything else bit for bit."""
    assert stored.keys() == held.keys()
    for k in held.keys() if only is None else only:
        a, b = stored[k], held[k]
        res = held.attrs.get(k, {}).get("resolution")
        if a.dtype.kind != "f" or (res is None and rtol == 0.0):
            assert same_bits(a, b), k
            continue
        assert a.dtype == b.dtype and a.shape == b.shape, k
        if res is None:
            np.testing.assert_allclose(a, b, rtol=rtol, atol=1e-12, err_msg=k)
        else:
            near_zero = (a == 0.0) & (np.abs(b) < res)
            assert np.abs(np.where(near_zero, 0.0, a - b)).max(initial=0.0) <= steps * res * (1 + 1e-6), k
