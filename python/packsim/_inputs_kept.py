"""No command writes over its own inputs: a result, a test's CSV, or another output of
the same command. `packsim run` refuses `-o` naming its scenario (docs/hardening.md);
`export`, `report` and `fit` wrote over the result or the test data they read (`packsim
fit cc.csv -o cc.csv` replaced the test with the preset, exit 0).
"""
from __future__ import annotations

import os
from collections.abc import Iterable, Mapping

__all__ = ["refuse_overwriting"]


def _key(path: str) -> str:
    return os.path.normcase(os.path.realpath(path))


def _same(a: str, b: str) -> bool:
    if os.path.exists(a) and os.path.exists(b):
        return os.path.samefile(a, b)  # hard links, other spellings
    return _key(a) == _key(b)


def refuse_overwriting(outputs: Mapping[str, str | os.PathLike | None], inputs: Iterable[str | os.PathLike],
                       error: type[Exception] = ValueError) -> None:
    """Raise `error` naming the option when an output (``{"-o": path, "--report": path}``;
    None: not written) is one of the input files, or two outputs are the same file."""
    given = [(flag, os.fspath(p)) for flag, p in outputs.items() if p is not None]
    files = [os.fspath(p) for p in inputs if isinstance(p, (str, os.PathLike))]
    for flag, out in given:
        for src in files:
            if _same(out, src):
                raise error(f"{flag} {out} is an input ({src}): writing it would destroy it; give another name")
    for i, (flag, out) in enumerate(given):
        for other_flag, other in given[i + 1:]:
            if _same(out, other):
                raise error(f"{flag} and {other_flag} name the same file ({out}): give each its own")
