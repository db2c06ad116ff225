"""Python overrides -> the (dotted key, YAML value) pairs core/scenario/overrides.hpp takes."""
from __future__ import annotations

import json
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["flatten_overrides", "yaml_value"]


def _plain(value: Any, key: str) -> Any:
    """NumPy scalars/arrays and tuples -> JSON-able Python values; rejects the rest."""
    if isinstance(value, np.ndarray):
        if value.ndim == 0:  # a 0-d array is the number it holds (tolist() gives that number)
            return _plain(value.item(), key)
        return [_plain(v, key) for v in value.tolist()]
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, (list, tuple)):
        return [_plain(v, key) for v in value]
    if isinstance(value, Mapping):
        out = {}
        for k, v in value.items():
            if not isinstance(k, str):
                raise TypeError(f"override {key!r}: mapping keys must be str, got {type(k).__name__}")
            out[k] = _plain(v, f"{key}.{k}")
        return out
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else _NonFinite(value)
    raise TypeError(f"override {key!r}: cannot use a {type(value).__name__} as a scenario value "
                    "(use numbers, strings, bools, lists or dicts)")


class _NonFinite(float):
    """A NaN or infinity, written as YAML's .nan / .inf / -.inf: the scenario loader then
    says which field takes what range, as it does for the same value in a file (a Python
    check here could name the key but not its range)."""

    def yaml(self) -> str:
        return ".nan" if math.isnan(self) else ".inf" if self > 0 else "-.inf"


def _yaml_text(v: Any) -> str:
    """JSON (which is YAML) for a value holding a _NonFinite somewhere: flow sequences
    and mappings around the leaves."""
    if isinstance(v, _NonFinite):
        return v.yaml()
    if isinstance(v, list):
        return "[" + ", ".join(_yaml_text(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(json.dumps(k) + ": " + _yaml_text(x) for k, x in v.items()) + "}"
    return json.dumps(v)


def _has_non_finite(v: Any) -> bool:
    if isinstance(v, _NonFinite):
        return True
    if isinstance(v, list):
        return any(_has_non_finite(x) for x in v)
    if isinstance(v, dict):
        return any(_has_non_finite(x) for x in v.values())
    return False


def yaml_value(value: Any, key: str = "value") -> str:
    """One value as YAML text. JSON is YAML, and json.dumps writes floats with repr(), so
    every float arrives in C++ bit for bit; a NaN or infinity goes as YAML's own spelling,
    for the loader to refuse with the field's range."""
    plain = _plain(value, key)
    return _yaml_text(plain) if _has_non_finite(plain) else json.dumps(plain, allow_nan=False)


def flatten_overrides(*mappings: Mapping[str, Any] | None) -> list[tuple[str, str]]:
    """Nested dicts are merged key by key; keys may also be dotted paths
    (``"pack.cell.capacity_Ah"``, ``"pack.cell.rc_pairs.0.r_ohm"``). Lists and scalars
    replace what the scenario has. Later mappings win."""
    pairs: list[tuple[str, str]] = []

    def walk(prefix: str, m: Mapping[str, Any]) -> None:
        for k, v in m.items():
            if not isinstance(k, str):
                raise TypeError(f"override keys must be str, got {k!r} ({type(k).__name__})")
            if not k:
                raise ValueError("override keys must not be empty")
            path = f"{prefix}.{k}" if prefix else k
            if isinstance(v, Mapping) and len(v) > 0:
                walk(path, v)
            else:
                pairs.append((path, yaml_value(v, path)))

    for m in mappings:
        if m is None:
            continue
        if not isinstance(m, Mapping):
            raise TypeError(f"overrides must be a mapping (dict), got {type(m).__name__}")
        walk("", m)
    return pairs
