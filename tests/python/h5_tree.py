"""Test helper: every dataset of an open HDF5 file or group by its link path (the
writer's own names, dimension scales and hard links included)."""
from __future__ import annotations

from collections.abc import Iterator

import h5py


def datasets(group: h5py.Group, prefix: str = "") -> Iterator[tuple[str, h5py.Dataset]]:
    """(path, dataset) for every dataset below `group`, depth first in link order;
    a path is relative to `group` ("truth/cell_v" for /truth/cell_v of the file)."""
    for k in group:
        o = group[k]
        if isinstance(o, h5py.Group):
            yield from datasets(o, prefix + k + "/")
        else:
            yield prefix + k, o
