"""What the machine offers this process (standard library only: the compile helper imports it)."""

import os

__all__ = ["usable_cores"]


def usable_cores():
    """Cores this process may run on (its CPU affinity where the OS tells), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return os.cpu_count() or 1
