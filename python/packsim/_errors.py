"""Exceptions raised by packsim (the C++ core's errors arrive as these)."""
from __future__ import annotations

__all__ = ["ScenarioError"]


class ScenarioError(ValueError):
    """A bad scenario (YAML, CSV table, override): nothing was simulated.

    ``str(err)`` is the C++ message ``file:line:column: field: message``; the parts are
    attributes. ``line`` and ``column`` are 1-based, 0 when unknown (for instance for a
    value set by an override rather than written in the file).
    """

    def __init__(self, text: str, *, file: str = "", line: int = 0, column: int = 0,
                 field: str = "", message: str = "") -> None:
        super().__init__(text)
        self.file = file
        self.line = line
        self.column = column
        self.field = field
        self.message = message or text

    def __reduce__(self):  # keep the attributes across pickling (multiprocessing, Dask)
        return (_rebuild, (str(self), self.file, self.line, self.column, self.field, self.message))


def _rebuild(text, file, line, column, field, message):
    return ScenarioError(text, file=file, line=line, column=column, field=field, message=message)
