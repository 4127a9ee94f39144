"""The Fig. 3 analogues of the certify section (``certify_*_certified_workspace.png``),
drawn by the package's own :func:`distkin.certify.plot.plot_certificate` from the
certificates the run stores in ``results.json`` (``certify.data.fig3_figures``: one
record per preset, :func:`certificate_record`), by the run and by ``python -m
benchmarks --replot certify``.

A record keeps what the figure draws and what ``summary()`` counts: the region, the
boxes (one string per box, exact: ``repr`` of the floats) with their status, σmin
bound, det sign, budget flag and undecided reason, and the tightened σmin bound's boxes.
Runs before this record was kept (``certify`` of 2026-11-26, run (33)) stored only the
summaries (``fig3``): their figures cannot be redrawn from the file.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np

from .plotting import FIGURES

__all__ = ["plot", "certificate_record", "certificate_from_record", "figure_name",
           "RECORDS"]

#: the key of ``certify.data`` holding the records, by preset label (as ``fig3``)
RECORDS = "fig3_figures"
_BOX_ROW = ("lo[columns] hi[columns] status sigma_lower det_sign budget reason "
            "('-': not recorded); status codes: distkin.certify.boxes.STATUS_NAMES")
_SIGMA_ROW = "lo[columns] hi[columns] sigma"


def _slug(label: str) -> str:
    return f"certify_{label.replace(', ', '_').replace(' ', '_')}"


def figure_name(label: str) -> str:
    """The file name of the figure of preset ``label`` (e.g. "hexa, radial reading")."""
    return f"{_slug(label)}_certified_workspace.png"


def _columns(cert, *boxes) -> list:
    """The coordinates stored per box: the varying ones when every box sits at the
    region's value along the fixed ones (it always should), else all six."""
    vary = list(cert.vary)
    fixed = [k for k in range(6) if k not in vary]
    exact = all(np.all(b[:, k] == cert.lower[k]) for b in boxes for k in fixed)
    return vary if exact else list(range(6))


def _f(v) -> str:
    return repr(float(v))


def certificate_record(cert) -> dict:
    """A JSON-ready record of a :class:`~distkin.certify.workspace.WorkspaceCertificate`
    from which :func:`certificate_from_record` rebuilds it exactly (the mechanism by its
    name and L only: all the figure and the summary use)."""
    tb = cert.sigma_bound
    cols = _columns(cert, cert.lo, cert.hi, *(() if tb is None else (tb.lo, tb.hi)))
    n = len(cert.status)
    budget = cert.budget_mask()
    reason, det = cert.reason, cert.det_sign
    rows = [" ".join([*(_f(cert.lo[i, k]) for k in cols), *(_f(cert.hi[i, k]) for k in cols),
                      str(int(cert.status[i])), _f(cert.sigma_lower[i]),
                      "-" if det is None else str(int(det[i])), str(int(budget[i])),
                      "-" if reason is None else str(int(reason[i]))])
            for i in range(n)]
    rec = {"mechanism": cert.mechanism.name, "L": int(cert.mechanism.L),
           "lower": [float(v) for v in cert.lower], "upper": [float(v) for v in cert.upper],
           "min_width": [float(v) for v in cert.min_width], "form": cert.form,
           "evaluated": int(cert.evaluated), "seconds": float(cert.seconds),
           "wall_seconds": float(cert.wall_seconds), "chunks": int(cert.chunks),
           "resumed": int(cert.resumed), "max_boxes": cert.max_boxes,
           "budget_recorded": cert.budget is not None, "columns": cols, "row": _BOX_ROW,
           "boxes": rows, "sigma_bound": None}
    if tb is not None:
        rec["sigma_bound"] = {
            "value": float(tb.value), "initial": float(tb.initial),
            "evaluated": int(tb.evaluated), "seconds": float(tb.seconds),
            "row": _SIGMA_ROW,
            "boxes": [" ".join([*(_f(tb.lo[i, k]) for k in cols),
                                *(_f(tb.hi[i, k]) for k in cols), _f(tb.sigma[i])])
                      for i in range(len(tb.sigma))]}
    return rec


def _corners(rec, parts, width):
    """(lo, hi) (n, 6) from the first 2 * len(columns) fields of each row."""
    cols = rec["columns"]
    m = len(cols)
    n = len(parts)
    bad = [i for i, p in enumerate(parts) if len(p) != 2 * m + width]
    if bad:
        raise ValueError(f"expected {2 * m + width} fields per box row ({m} columns), "
                         f"got {len(parts[bad[0]])} in row {bad[0]}")
    lo = np.tile(np.asarray(rec["lower"], float), (n, 1))
    hi = lo.copy()
    if n:
        vals = np.array([[float(v) for v in p[:2 * m]] for p in parts]).reshape(n, 2 * m)
        lo[:, cols], hi[:, cols] = vals[:, :m], vals[:, m:]
    return lo, hi


def certificate_from_record(rec):
    """The certificate of a :func:`certificate_record` record."""
    from distkin.certify.tighten import SigmaBound
    from distkin.certify.workspace import WorkspaceCertificate
    m = len(rec["columns"])
    parts = [r.split() for r in rec["boxes"]]
    lo, hi = _corners(rec, parts, 5)
    tail = [p[2 * m:] for p in parts]
    status = np.array([int(t[0]) for t in tail], dtype=np.int8)
    sigma = np.array([float(t[1]) for t in tail], dtype=float)
    det = (None if tail and tail[0][2] == "-" else
           np.array([int(t[2]) for t in tail], dtype=np.int8))
    budget = (np.array([t[3] == "1" for t in tail], dtype=bool)
              if rec["budget_recorded"] else None)
    reason = (None if tail and tail[0][4] == "-" else
              np.array([int(t[4]) for t in tail], dtype=np.int8))
    tb = None
    if rec["sigma_bound"] is not None:
        s = rec["sigma_bound"]
        sp = [r.split() for r in s["boxes"]]
        tlo, thi = _corners(rec, sp, 1)
        tb = SigmaBound(value=s["value"], initial=s["initial"], evaluated=s["evaluated"],
                        seconds=s["seconds"], lo=tlo, hi=thi,
                        sigma=np.array([float(p[-1]) for p in sp], dtype=float))
    return WorkspaceCertificate(
        mechanism=SimpleNamespace(name=rec["mechanism"], L=rec["L"]),
        lower=np.asarray(rec["lower"], float), upper=np.asarray(rec["upper"], float),
        min_width=np.asarray(rec["min_width"], float), form=rec["form"], lo=lo, hi=hi,
        status=status, sigma_lower=sigma,
        det_sign=np.zeros(len(status), np.int8) if det is None else det,
        evaluated=rec["evaluated"], seconds=rec["seconds"],
        wall_seconds=rec["wall_seconds"], chunks=rec["chunks"], sigma_bound=tb,
        resumed=rec["resumed"], budget=budget, max_boxes=rec["max_boxes"], reason=reason)


def plot(data, out=FIGURES) -> dict:
    """Draw the Fig. 3 analogue of every preset of ``data["fig3"]`` whose certificate
    is stored (``data["fig3_figures"]``) into ``out``; returns {file name: path written,
    or why it was not redrawn}."""
    from distkin.certify.plot import plot_certificate
    records = data.get(RECORDS, {})
    written = {}
    for label in data.get("fig3", {}):
        name = figure_name(label)
        if label not in records:
            written[name] = (f"its boxes are not in results.json (certify.data.{RECORDS} "
                             f"has no {label!r}): rerun `python -m benchmarks certify`")
            continue
        cert = certificate_from_record(records[label])
        written[name] = plot_certificate(cert, Path(out) / _slug(label), length_unit="mm")
    return written
