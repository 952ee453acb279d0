"""The per-model cache of the linearization Functions.

Every derived Function of :mod:`mbsym.linear` is built once per model and key and kept in
the model's one private cache dict; the model stays otherwise unchanged.
"""

from __future__ import annotations

from ..equations import EquationsOfMotion

__all__ = ["cached"]


def cached(eom: EquationsOfMotion, key, build):
    """``build()`` once per model and ``key``, kept in the model's one private cache dict."""
    cache = eom.__dict__.setdefault("_mbsym_cache", {})
    if key not in cache:
        cache[key] = build()
    return cache[key]
