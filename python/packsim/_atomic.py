"""Files written whole or not at all: under a temporary name, renamed when complete."""
from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def replaced_when_done(path: str, tmp: str | None = None) -> Iterator[str]:
    """Yields the temporary file name to write (`tmp`, by default `path` + ".tmp"); when
    the block completes it is renamed onto `path`, when the block raises it is removed."""
    tmp = path + ".tmp" if tmp is None else tmp
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise
