"""SIGTERM (``kill``, ``timeout``, a CI cancel) stops a command as Ctrl-C does: exit 130,
``distkin: error: interrupted``, and the pool's worker processes are stopped too (QA:
the default handler killed distkin alone; the workers of a chunked run, e.g.
``examples/certify_hexa.toml``, ran on as orphans holding the output pipes)."""

import multiprocessing
import os
import signal
import time

from distkin.app import cli


def _sleep(started):
    started.set()
    time.sleep(30)


def test_sigterm_is_an_interrupt_and_reaches_the_workers(monkeypatch, capsys):
    seen = {}

    def command(args):
        ctx = multiprocessing.get_context("spawn")
        started = ctx.Event()
        child = ctx.Process(target=_sleep, args=(started,), daemon=True)
        child.start()
        seen["child"] = child
        # the SIGTERM once the child runs, as a pool worker mid-chunk does (this test
        # failed once in a local -n 2 run beside other jobs, the child alive after the
        # join below; not reproduced since: the interpreter's start-up, when the SIGINT
        # may come, is no longer part of what it tests)
        seen["started"] = started.wait(60)
        os.kill(os.getpid(), signal.SIGTERM)       # as `kill PID` from outside
        time.sleep(5)                              # never reached: the handler raises
        seen["ran_on"] = True

    monkeypatch.setattr(cli, "_cmd_run", command)
    before = signal.getsignal(signal.SIGTERM)
    assert cli.main(["run", "x.toml"]) == 130
    assert capsys.readouterr().err.strip().splitlines() == ["distkin: error: interrupted"]
    assert "ran_on" not in seen
    assert seen["started"]
    child = seen["child"]
    child.join(10)                                  # SIGINT ends its sleep at once
    assert not child.is_alive() and child.exitcode != 0
    assert signal.getsignal(signal.SIGTERM) is before     # restored for the caller
