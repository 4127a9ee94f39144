"""Operating-system scheduling of the control loop and the simulated device.

Two requests a loop above 1 kHz makes of Linux, both best effort (elsewhere they do
nothing and say so):

* :func:`tight_timer_slack` -- a timed wait (``select`` with a timeout) ends on time
  instead of up to 50 µs late, the default timer slack of a normal thread: at 4 kHz
  that is a fifth of a period;
* :func:`realtime` -- the ``SCHED_FIFO`` policy (opt-in, ``[device] realtime = true``
  in the scene): the loop runs as soon as its frame arrives instead of waiting for
  other processes' time slices.  A loop that blocks between frames uses a fraction of
  a core; the kernel keeps 5 % of each second for normal processes
  (``sched_rt_runtime_us``) whatever happens.  What it cannot change: a pty moves
  bytes through a kernel worker thread of normal priority, so on a loaded machine the
  transfer itself can still wait (BENCHMARKS.md, control section).
"""

from __future__ import annotations

import os

__all__ = ["tight_timer_slack", "realtime", "restore"]

#: SCHED_FIFO priority asked for by :func:`realtime` (1..99; low: above every normal
#: process, below the kernel's own real-time threads)
PRIORITY = 10


def tight_timer_slack() -> bool:
    """``prctl(PR_SET_TIMERSLACK, 1 ns)`` for this thread; False where unavailable."""
    try:
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(29, 1, 0, 0, 0) == 0           # PR_SET_TIMERSLACK = 29
    except (OSError, AttributeError):
        return False


def realtime(priority: int = PRIORITY):
    """Switch this process to ``SCHED_FIFO`` at ``priority``.

    Returns ``(previous, message)``: ``previous`` the policy and priority to give to
    :func:`restore` (None if nothing changed), ``message`` "" on success, else why not
    (no permission, not Linux).
    """
    try:
        old = (os.sched_getscheduler(0), os.sched_getparam(0).sched_priority)
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(priority))
    except (AttributeError, OSError) as exc:
        return None, f"expected SCHED_FIFO priority {priority}, got {exc}"
    return old, ""


def restore(previous) -> None:
    """Undo :func:`realtime` (``previous`` as it returned; None: nothing)."""
    if previous is not None:
        try:
            os.sched_setscheduler(0, previous[0], os.sched_param(previous[1]))
        except OSError:
            pass
