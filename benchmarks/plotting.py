"""Shared tools of the benchmark figures: the figures folder, a figure at the saved
resolution, and labels placed so that none covers a marker or another label.

The figures are drawn from a section's stored numbers (``results.json``'s ``data``) by
the section's ``plot(data, out)`` (``benchmarks/plot_NAME.py``), both at the end of a
run and by ``python -m benchmarks --replot``: what a figure shows is what the file says.
"""

from __future__ import annotations

import math
from pathlib import Path

__all__ = ["FIGURES", "DPI", "figure", "save", "place_labels", "overlaps", "text_box"]

#: where the figures go (BENCHMARKS.md links them from the repository root)
FIGURES = Path(__file__).resolve().parent / "figures"
#: the resolution figures are drawn and saved at (one, so that label boxes measured
#: while placing them are the ones saved)
DPI = 110


def figure(*args, **kw):
    """``plt.subplots`` on the Agg backend at :data:`DPI`; returns (fig, axes)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt.subplots(*args, dpi=DPI, **kw)


def save(fig, out, name) -> Path:
    """Save ``fig`` as ``out / name`` (folder made if needed), close it, return the path."""
    import matplotlib.pyplot as plt
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / name
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def overlaps(a, b, pad: float = 0.0) -> bool:
    """Do the display boxes ``a`` and ``b`` (matplotlib Bbox) overlap (``pad`` pixels
    of clearance required)?"""
    return not (a.x1 + pad <= b.x0 or b.x1 + pad <= a.x0 or
                a.y1 + pad <= b.y0 or b.y1 + pad <= a.y0)


def _marker_box(ax, x, y, size_pt):
    from matplotlib.transforms import Bbox
    px, py = ax.transData.transform((x, y))
    r = 0.5 * size_pt * ax.figure.dpi / 72.0
    return Bbox.from_extents(px - r, py - r, px + r, py + r)


def text_box(note, renderer):
    """The box of an annotation's text alone (its leader line apart)."""
    from matplotlib.text import Text
    note.get_window_extent(renderer)          # places the text at its offset first
    return Text.get_window_extent(note, renderer)


def _box_distance(box, px, py) -> float:
    """Pixels from the point (px, py) to the box (0 inside)."""
    dx = max(box.x0 - px, 0.0, px - box.x1)
    dy = max(box.y0 - py, 0.0, py - box.y1)
    return math.hypot(dx, dy)


def _crosses(p, q, boxes, start, pad=1.0) -> bool:
    """Does the segment p -> q (display) pass through one of ``boxes`` outside the box
    ``start`` (the marker it leaves from)?"""
    for t in [j / 24 for j in range(25)]:
        x, y = p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])
        if start.x0 - pad <= x <= start.x1 + pad and start.y0 - pad <= y <= start.y1 + pad:
            continue
        if any(b.x0 - pad <= x <= b.x1 + pad and b.y0 - pad <= y <= b.y1 + pad
               for b in boxes):
            return True
    return False


def _segments_cross(p, q, r, s) -> bool:
    """Do the segments p-q and r-s (display) cross?"""
    def side(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    return (side(p, q, r) * side(p, q, s) < 0) and (side(r, s, p) * side(r, s, q) < 0)


def _leader(box, own):
    """The leader line of a label in ``box`` for the point ``own``: matplotlib draws it
    from the text's centre (cut at the text's edge) to the point."""
    return own, (0.5 * (box.x0 + box.x1), 0.5 * (box.y0 + box.y1))


def _free(box, i, centres, frame, blocked, marks, lead, leaders):
    """May a label of point ``i`` stand in ``box``: inside the axes, over no marker,
    label or obstacle, and read as point i's: nearer to it than to any other point
    (without a leader line), or its leader line crossing no other marker, label or
    leader line."""
    if not (box.x0 >= frame.x0 and box.x1 <= frame.x1 and
            box.y0 >= frame.y0 and box.y1 <= frame.y1):
        return False
    if any(overlaps(box, b, pad=3.0) for b in blocked):
        return False
    own = centres[i]
    if not lead:
        d_own = _box_distance(box, *own)
        return all(_box_distance(box, *c) > d_own + 3.0
                   for j, c in enumerate(centres) if j != i)
    a, b = _leader(box, own)
    others = [m for j, m in enumerate(marks) if j != i] + blocked[len(marks):]
    return (not _crosses(a, b, others, marks[i], pad=0.5) and
            not any(_segments_cross(a, b, c, d) for c, d in leaders))


def _directions(i, centres, near_px=40.0):
    """The 16 directions (rad) to try for point i's label: nearest first to the
    direction away from its neighbours within ``near_px`` (right and a little up when
    it has none)."""
    own = centres[i]
    near = [c for j, c in enumerate(centres) if j != i and
            math.hypot(c[0] - own[0], c[1] - own[1]) < near_px]
    away = math.pi / 16
    if near:
        vx = sum(own[0] - c[0] for c in near)
        vy = sum(own[1] - c[1] for c in near)
        if math.hypot(vx, vy) > 0:
            away = math.atan2(vy, vx)
    angles = [math.pi / 8 * k + math.pi / 16 for k in range(16)]

    def gap(a):
        return abs((a - away + math.pi) % (2 * math.pi) - math.pi)
    return sorted(angles, key=lambda a: (round(gap(a), 9), a))


def place_labels(ax, points, labels, *, marker_pt: float = 7.0, obstacles=(),
                 fontsize: float = 7.0, colours=None):
    """Write ``labels[i]`` next to ``points[i]`` (data coordinates) where its text box
    overlaps no marker (a square of ``marker_pt`` points about each point), no label
    placed before it and no box of ``obstacles`` (data coordinates (x0, y0, x1, y1), e.g.
    error bars), inside the axes, and reads as that point's: the first of 16 directions
    at growing distances that is free; next to the point, the label must be nearer to
    it than to any other point, farther off a leader line joins them and may cross no
    other marker or label.  The layout must be final (``tight_layout`` before, not
    after).  Returns the annotations."""
    from matplotlib.transforms import Bbox
    fig = ax.figure
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    marks = [_marker_box(ax, x, y, marker_pt) for x, y in points]
    centres = [tuple(ax.transData.transform((x, y))) for x, y in points]
    blocked = list(marks)
    for x0, y0, x1, y1 in obstacles:
        (a, b), (c, d) = ax.transData.transform([(x0, y0), (x1, y1)])
        blocked.append(Bbox.from_extents(min(a, c) - 1, min(b, d) - 1,
                                         max(a, c) + 1, max(b, d) + 1))
    out, leaders = [], []
    for i, ((x, y), text) in enumerate(zip(points, labels)):
        colour = None if colours is None else colours[i]
        note = None
        for dist in (0.5 * marker_pt + 2, 12, 18, 26, 36, 48, 62, 78):
            lead = dist > 0.5 * marker_pt + 2
            for ang in _directions(i, centres):
                dx, dy = dist * math.cos(ang), dist * math.sin(ang)
                ha = "left" if dx > 1 else "right" if dx < -1 else "center"
                va = "bottom" if dy > 1 else "top" if dy < -1 else "center"
                cand = ax.annotate(
                    text, (x, y), xytext=(dx, dy), textcoords="offset points", ha=ha,
                    va=va, fontsize=fontsize, color=colour,
                    arrowprops=(None if not lead else
                                {"arrowstyle": "-", "lw": 0.5, "color": "0.45",
                                 "shrinkA": 0, "shrinkB": 3}))
                box = text_box(cand, renderer)
                if _free(box, i, centres, frame, blocked, marks, lead, leaders):
                    note = cand
                    if lead:
                        leaders.append(_leader(box, centres[i]))
                    break
                cand.remove()
            if note is not None:
                break
        if note is None:           # nowhere free: the first place, said in the log
            note = ax.annotate(text, (x, y), xytext=(5, 5), textcoords="offset points",
                               fontsize=fontsize, color=colour)
            print(f"benchmarks: no free place for the label {text!r}")
        blocked.append(text_box(note, renderer))
        out.append(note)
    return out
