"""Argument checks shared by every public function.

Each check names the argument and the allowed values in an
:class:`~faultnet.exceptions.InvalidParameterError`, so a user never meets a
bare numpy or Python error for a wrong input.

>>> check_int("n_events", 5)
5
>>> check_int("n_events", True)
Traceback (most recent call last):
...
faultnet.exceptions.InvalidParameterError: n_events must be an integer >= 1; got True
>>> seed_sequence(7).entropy
7
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from faultnet.exceptions import InvalidParameterError

__all__ = [
    "available_memory",
    "check_columns",
    "check_memory",
    "check_finite",
    "check_int",
    "check_positive",
    "generator_and_seed",
    "seed_sequence",
]

_RNG_RULE = "None, an int >= 0, a numpy SeedSequence or a numpy Generator"


def available_memory():
    """Bytes of memory a new allocation may take (Linux ``MemAvailable``; else physical)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        import os

        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, OSError, ValueError):
        return None


def check_memory(what, n_bytes, instead):
    """Refuse an allocation of ``n_bytes`` for ``what`` beyond the memory available, saying
    what to do ``instead``."""
    avail = available_memory()
    if avail is not None and n_bytes > avail:
        raise InvalidParameterError(
            f"{what} would take about {n_bytes / 2**30:,.3g} GiB of memory, more than the "
            f"{avail / 2**30:,.3g} GiB available; {instead}"
        )


def check_columns(name, table, columns, source):
    """``table`` if it is a DataFrame with ``columns``; else an error naming ``source``, the
    function whose table it must be."""
    import pandas as pd

    have = list(table.columns) if isinstance(table, pd.DataFrame) else None
    missing = [c for c in columns if have is None or c not in have]
    if missing:
        got = f"columns {have}" if have is not None else type(table).__name__
        raise InvalidParameterError(
            f"{name} must be the DataFrame of {source} (columns {list(columns)}); got {got}"
        )
    return table


def check_int(name, value, minimum=1) -> int:
    """``value`` as a Python int >= ``minimum`` (bools and non-integers refused)."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Integral):
        raise InvalidParameterError(f"{name} must be an integer >= {minimum}; got {value!r}")
    if value < minimum:
        raise InvalidParameterError(f"{name} must be an integer >= {minimum}; got {value!r}")
    return int(value)


def check_finite(name, value) -> float:
    """``value`` as a finite float (strings, bools, complex and NaN/inf refused)."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise InvalidParameterError(f"{name} must be a finite real number; got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise InvalidParameterError(f"{name} must be a finite real number; got {value!r}")
    return value


def check_positive(name, value) -> float:
    """``value`` as a finite float > 0."""
    value_f = check_finite(name, value)
    if value_f <= 0.0:
        raise InvalidParameterError(f"{name} must be finite and > 0; got {value!r}")
    return value_f


def _check_rng_type(rng, name):
    ok = (
        rng is None
        or isinstance(rng, np.random.SeedSequence | np.random.Generator)
        or (isinstance(rng, numbers.Integral) and not isinstance(rng, bool | np.bool_))
    )
    if not ok:
        raise InvalidParameterError(f"{name} must be {_RNG_RULE}; got {rng!r}")
    if isinstance(rng, numbers.Integral) and rng < 0:
        raise InvalidParameterError(f"{name} must be {_RNG_RULE}; got the negative int {rng}")


def seed_sequence(rng, name="rng") -> np.random.SeedSequence:
    """A recordable SeedSequence from a SPEC 7 ``rng`` argument.

    None draws fresh entropy; an int or SeedSequence is used as is; a
    Generator spawns a child (``SeedSequence.spawn``), so the run is
    reproducible from the recorded entropy and spawn key.
    """
    _check_rng_type(rng, name)
    if isinstance(rng, np.random.SeedSequence):
        return rng
    if isinstance(rng, np.random.Generator):
        seq = getattr(rng.bit_generator, "seed_seq", None)
        if isinstance(seq, np.random.SeedSequence):
            return seq.spawn(1)[0]
        return np.random.SeedSequence(rng.integers(0, 2**63, size=4).tolist())
    return np.random.SeedSequence(None if rng is None else int(rng))


def generator_and_seed(rng, name="rng"):
    """``(Generator, SeedSequence or None)`` from a SPEC 7 ``rng`` argument.

    A Generator is used as it is (its SeedSequence, when it has one, is
    returned for the record); anything else goes through
    ``np.random.default_rng`` on a SeedSequence.
    """
    _check_rng_type(rng, name)
    if isinstance(rng, np.random.Generator):
        seq = getattr(rng.bit_generator, "seed_seq", None)
        return rng, seq if isinstance(seq, np.random.SeedSequence) else None
    seq = rng if isinstance(rng, np.random.SeedSequence) else np.random.SeedSequence(rng)
    return np.random.default_rng(seq), seq
