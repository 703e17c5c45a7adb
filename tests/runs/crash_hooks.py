"""A kill at a chosen instant of a long run, for the tests of resume and recovery."""


class Crash(BaseException):
    """Stands in for a kill at a chosen instant (not an Exception: nothing handles it)."""


def crash_after(n):
    """An ``on_commit`` hook that kills the run right after its ``n``-th commit."""

    def on_commit(n_chunks):
        if n_chunks == n:
            raise Crash

    return on_commit
