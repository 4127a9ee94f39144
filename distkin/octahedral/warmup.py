"""The first compile of the fast octahedral tier on a machine, in two processes.

A fast solve (:func:`~.forward.forward_kinematics`, ``method="fast"`` or ``"auto"``)
runs two compiled chains (numba, :mod:`.batched`): the sign scan, polish and placement
(:func:`.batched.scan_single`), then the proof that vouches for the count of real roots
(:func:`.descartes.vouch_buffer`).  Numba compiles a function on its first call, in the
calling thread, and keeps the machine code in its on-disk cache; the two chains share
no function that takes long, so on a machine with two cores they can be compiled side
by side.  :func:`compile_fast_tier` starts a child process that compiles the proof
while this one compiles the scan, then waits for the child: the next calls load both
from the cache.  On the 2-core machine of BENCHMARKS.md the chains took 20.7 s and
16.8 s one after the other, so the first ``distkin demo`` waits for the longer one
only (``python -m benchmarks coldstart``).

The child computes nothing anyone reads: it calls the proof once on a placeholder
buffer of the right types, for its compile (numba compiles a function for the types of
its arguments, whatever their values), and its exit status is not looked at.  If it
fails or is killed, the first solve compiles what is missing itself, as before.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np

__all__ = ["compile_fast_tier", "pending_chains", "placeholder"]

#: the child's program: the proof's compile (:func:`_compile_proof`)
_CHILD = "from distkin.octahedral.warmup import _compile_proof; _compile_proof()"
#: seconds to wait for the child after this process's own compile, at most
TIMEOUT = 600.0


def _child_program(body: str) -> str:
    """``body`` run against this process's distkin: ``python -c`` puts the working
    folder first on the child's path, where a source checkout would shadow an installed
    distkin (then the child compiled that copy's cache, and this one compiled the
    proof again), so that entry is dropped; the folder holding this distkin is put
    first only when it is not on the path already (a checkout imported from the
    working folder), not ahead of the standard library for an installed distkin."""
    from pathlib import Path
    root = str(Path(__file__).resolve().parents[2])
    return (f"import sys; sys.path[:] = [p for p in sys.path if p != '']; "
            f"{root!r} in sys.path or sys.path.insert(0, {root!r}); {body}")


def pending_chains() -> tuple:
    """The compiled chains of the fast single solve without machine code in numba's
    cache yet: a subset of ``("scan", "proof")``."""
    from .descartes import vouch_buffer
    from .signscan import scan_one
    from .single import cached
    return tuple(name for name, f in (("scan", scan_one), ("proof", vouch_buffer))
                 if not cached(f))


def placeholder() -> tuple:
    """Arguments of :func:`.descartes.vouch_buffer` of the types a single solve passes
    (:func:`.forward.proved_single`): the buffer of :func:`.batched.scan_single`
    (float64, C order: squared sides, legs, kernel output, one root row), the number
    of root rows, eta, and the bounds lo, hi.  The values mean nothing."""
    return np.ones(54), 1, 1e-16, 0.5, 2.0


def _compile_proof() -> None:
    """The child's work: :func:`.descartes.vouch_buffer` once, on :func:`placeholder`,
    for numba to compile and cache it."""
    from .descartes import vouch_buffer
    try:
        vouch_buffer(*placeholder())
    except Exception:       # the values are placeholders; the compile is what counts
        pass


def _compile_scan() -> None:
    """This process's work: one single solve's compiled part
    (:func:`.batched.scan_single`) on the Griffis-Duffy example of Sec. VI."""
    from .batched import scan_single
    B = np.array([[0.0, 0.0, 0.0], [12.0, 0.0, 0.0], [6.0, 6.0 * 3 ** 0.5, 0.0]])
    Q = 0.5 * B
    scan_single(B, Q, np.array([20.0, 18.0, 18.0, 17.0, 15.0, 18.0]))


def compile_fast_tier(*, timeout: float = TIMEOUT, notice=None) -> tuple:
    """Compile what the fast single solve has not compiled yet on this machine, the
    proof in a child process beside the scan in this one (module docstring).
    ``notice``: called first with :func:`.single.compile_notice`'s line when something
    is to be compiled (the CLI's queries pass theirs).

    Returns the chains compiled (``pending_chains()`` before the call): ``()`` when
    both are cached, and then nothing runs.  A child still compiling ``timeout``
    seconds after this process's own compile, or when this process is interrupted, is
    killed (the solve then compiles what is missing itself)."""
    todo = pending_chains()
    if todo and notice is not None:
        from .single import compile_notice
        notice(compile_notice())
    child = None
    if "proof" in todo:
        child = subprocess.Popen([sys.executable, "-c", _child_program(_CHILD)],
                                 stdin=subprocess.DEVNULL,
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        if "scan" in todo:
            _compile_scan()
        if child is not None:
            child.wait(timeout)
    except BaseException:   # interrupted (or the child too slow): leave no child behind
        if child is not None and child.poll() is None:
            child.kill()
            child.wait()
        if not isinstance(sys.exc_info()[1], subprocess.TimeoutExpired):
            raise
    return todo
