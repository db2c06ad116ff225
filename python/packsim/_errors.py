"""Exceptions raised by packsim (the C++ core's errors arrive as these)."""
from __future__ import annotations

__all__ = ["ScenarioError", "FirmwareError"]


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


class FirmwareError(RuntimeError):
    """The run's firmware failed: it did not load, broke the contract (ABI, ``init``, a task
    over its budget), crashed or hung, and the scenario does not say
    ``expect: {firmware_fault: true}`` -- ``packsim run`` exits 1 for the same run.

    ``str(err)`` names the firmware, the time and the cause; ``result`` is the run as it
    went on with a dead MCU (the record of what the pack was left to).
    """

    def __init__(self, text: str, result=None) -> None:
        super().__init__(text)
        self.result = result

    def __reduce__(self):  # the message survives pickling (Dask); the result stays behind
        return (FirmwareError, (str(self),))
