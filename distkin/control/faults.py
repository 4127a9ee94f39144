"""Fault injection for the device simulator (``distkin sim --faults SPEC``).

A SPEC is a comma-separated list of ``KIND@T[:ARG]``, ``T`` in seconds of device time
(the simulator's physics clock, so that a fault hits the same moment of the motion on a
fast or a loaded machine):

``corrupt@T:N``     flip one random byte in each of the next N state frames (N = 1)
``garbage@T:N``     send a burst of N random bytes before the next frame (N = 64,
                    at most 10^7)
``truncate@T:N``    send only the first half of each of the next N frames (N = 1)
``drop@T:N``        do not send the next N frames (N = 1)
``stall@T:MS``      send nothing for MS milliseconds of wall time (MS = 50, at most
                    600000); the device keeps moving and keeps obeying the commands
                    it receives
``disconnect@T``    close the connection and stop serving

Example: ``--faults "corrupt@1.0:3,garbage@1.5:200,truncate@2.0,stall@3.0:50"``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["Fault", "parse_faults", "FaultInjector", "DISCONNECT", "FAULT_KINDS",
           "FAULT_MAX"]

FAULT_KINDS = {"corrupt": 1, "garbage": 64, "truncate": 1, "drop": 1, "stall": 50,
               "disconnect": 0}
#: the largest argument of a kind, where a larger one is no test but a hazard: a burst
#: of garbage is drawn in memory at once (review: ``garbage@1:100000000000`` asked for
#: 100 GB), and a stall holds the simulator (10 minutes, beyond any watchdog)
FAULT_MAX = {"garbage": 10_000_000, "stall": 600_000}

#: returned by :meth:`FaultInjector.outgoing` when the link must be closed
DISCONNECT = object()


@dataclass(frozen=True)
class Fault:
    """One scheduled fault: ``kind`` at device time ``t`` (s) with argument ``arg``."""

    kind: str
    t: float
    arg: int

    def __str__(self):
        return f"{self.kind}@{self.t:g}" + (f":{self.arg}" if self.kind != "disconnect" else "")


def parse_faults(spec: str | None, field: str = "--faults") -> tuple[Fault, ...]:
    """Parse a fault SPEC (see the module docstring); InputError on any malformed item."""
    if not spec:
        return ()
    out = []
    for i, item in enumerate(s.strip() for s in spec.split(",")):
        fld = f"{field}[{i}]"
        kind, at, rest = item.partition("@")
        if kind in FAULT_KINDS and not at:
            raise InputError(f"expected KIND@T[:ARG], got {item!r}: the kind {kind!r} has "
                             f"no '@T', the device time of the fault in s", field=fld,
                             hint=f"e.g. '{kind}@1.0'")
        if kind not in FAULT_KINDS or not at:
            raise InputError(f"expected KIND@T[:ARG] with KIND one of "
                             f"{', '.join(FAULT_KINDS)}, got {item!r}", field=fld)
        t_text, _, arg_text = rest.partition(":")
        try:
            t = float(t_text)
        except ValueError:
            raise InputError(f"expected a time in seconds after '@', got {t_text!r}",
                             field=fld) from None
        if not 0 <= t < float("inf"):
            raise InputError(f"expected a finite time >= 0 s, got {t_text!r}", field=fld)
        arg = FAULT_KINDS[kind]
        if arg_text:
            if kind == "disconnect":
                raise InputError(f"expected no argument for disconnect, got {arg_text!r}",
                                 field=fld)
            # ASCII digits only (str.isdigit also takes '²' and '３')
            if not (arg_text.isascii() and arg_text.isdigit()) or int(arg_text) < 1:
                raise InputError(f"expected a positive integer argument, got {arg_text!r}",
                                 field=fld)
            arg = int(arg_text)
            if arg > FAULT_MAX.get(kind, arg):
                unit = "bytes" if kind == "garbage" else "ms"
                raise InputError(f"expected at most {FAULT_MAX[kind]} {unit} for {kind}, "
                                 f"got {arg_text}", field=fld)
        out.append(Fault(kind, t, arg))
    return tuple(sorted(out, key=lambda f: f.t))


class FaultInjector:
    """Applies scheduled faults to the simulator's outgoing byte stream.

    Parameters
    ----------
    faults : sequence of Fault
    seed : int
        Seed of the random bytes.
    """

    def __init__(self, faults=(), seed: int = 1):
        self.pending = list(faults)
        self.rng = np.random.default_rng(seed)
        self.active = {"corrupt": 0, "truncate": 0, "drop": 0}
        self.garbage = 0
        self.stall_ms = 0
        self.log: list[dict] = []

    def due(self, t: float) -> list[Fault]:
        """Faults whose time has come at device time ``t`` (removed from the schedule)."""
        out = []
        while self.pending and self.pending[0].t <= t + 1e-12:
            f = self.pending.pop(0)
            out.append(f)
            if f.kind in self.active:
                self.active[f.kind] += f.arg
            elif f.kind == "garbage":
                self.garbage += f.arg
            elif f.kind == "stall":
                self.stall_ms = f.arg
            self.log.append({"t": t, "fault": f.kind, "arg": f.arg})
        return out

    def take_stall_ms(self) -> int:
        """Milliseconds to stall now (0 if none); consumes the request."""
        ms, self.stall_ms = self.stall_ms, 0
        return ms

    def outgoing(self, t: float, frame: bytes):
        """Bytes to send instead of ``frame`` at device time ``t``, or :data:`DISCONNECT`."""
        for f in self.due(t):
            if f.kind == "disconnect":
                return DISCONNECT
        out = b""
        if self.garbage:
            out += self.rng.integers(0, 256, self.garbage, dtype=np.uint8).tobytes()
            self.garbage = 0
        if self.active["drop"]:
            self.active["drop"] -= 1
            return out
        if self.active["truncate"]:
            self.active["truncate"] -= 1
            return out + frame[: len(frame) // 2]
        if self.active["corrupt"]:
            self.active["corrupt"] -= 1
            b = bytearray(frame)
            i = int(self.rng.integers(0, len(b) - 1))     # never the delimiter
            b[i] ^= int(self.rng.integers(1, 256))
            if b[i] == 0:                                 # keep the frame one frame long
                b[i] = 0x5A if frame[i] != 0x5A else 0xA5
            return out + bytes(b)
        return out + frame
