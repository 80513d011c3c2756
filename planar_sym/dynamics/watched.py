"""A long call into the compiled integrator, watched: its clock reported while it runs.

ctypes releases the GIL for the call, so the call runs in a worker thread while this one
reads the time the C loop has reached (it writes it after every accepted step into the same
``double`` that holds the failure time at the end) and passes it to the progress callback.
Without a callback the call is made directly: the numbers are the same either way, as the
integration itself never looks at the clock.
"""

from __future__ import annotations

import ctypes
import threading
from collections.abc import Callable

#: how often the clock is read (s)
POLL_S = 0.1


def call_watched(call: Callable[[], int], reached: ctypes.c_double, t_end_s: float,
                 progress: Callable[[float, float], None] | None) -> int:
    """``call()`` (a ctypes call returning an int); with ``progress``, run in a worker thread
    and ``progress(reached.value, t_end_s)`` called every POLL_S until it has returned (at
    least once, at its end)."""
    if progress is None:
        return call()
    box: dict = {}

    def work():
        try:
            box["rc"] = call()
        except BaseException as exc:  # noqa: BLE001 - raised again in the caller's thread
            box["exc"] = exc

    # a daemon: Ctrl-C ends the program at once instead of waiting for the C loop to finish
    worker = threading.Thread(target=work, name="planar-sym integrator", daemon=True)
    worker.start()
    while True:  # read at least once, after the first wait: a quick run still reports its end
        worker.join(POLL_S)
        progress(reached.value, t_end_s)
        if not worker.is_alive():
            break
    if "exc" in box:
        raise box["exc"]
    return box["rc"]
