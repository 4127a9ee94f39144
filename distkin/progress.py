"""The progress bar of chunked work (:func:`distkin.runstore.run_chunks`): rich, on
stderr, so that ``--json -`` keeps stdout clean; the chunks done of the total, the
elapsed time and the ETA, and a word on what runs before the first chunk (the one-off
loading of the compiled kernels).
"""

from __future__ import annotations

__all__ = ["ChunkProgress"]


class ChunkProgress:
    """The progress bar of chunked work on stderr (rich): ``total`` chunks, ``done``
    of them already finished (loaded from a store), the elapsed time and the ETA;
    nothing when not ``enabled``.  :meth:`advance` per finished chunk, :meth:`note` a
    word after the description ("" to clear), :meth:`close`."""

    def __init__(self, total, done, desc, enabled):
        self.bar, self.desc = None, desc
        if enabled and total:
            from rich.console import Console
            from rich.progress import (BarColumn, MofNCompleteColumn, Progress, TextColumn,
                                       TimeElapsedColumn, TimeRemainingColumn)
            self.bar = Progress(TextColumn("{task.description}"), BarColumn(),
                                MofNCompleteColumn(), TextColumn("chunks · elapsed"),
                                TimeElapsedColumn(), TextColumn("· ETA"),
                                TimeRemainingColumn(), transient=False,
                                console=Console(stderr=True))
            self.bar.start()
            self.task = self.bar.add_task(desc, total=total, completed=done)

    def advance(self):
        if self.bar is not None:
            self.bar.advance(self.task)

    def note(self, text):
        if self.bar is not None:
            self.bar.update(self.task, description=self.desc + text)

    def close(self):
        if self.bar is not None:
            self.bar.stop()
