"""No hand-written module of the package is over 600 lines (docs/design.md, "Layout":
small modules named after their algorithm); generated kernels are exempt."""

from pathlib import Path

import distkin

LIMIT = 600


def test_no_module_over_the_limit():
    root = Path(distkin.__file__).parent
    sizes = {p.relative_to(root).as_posix(): len(p.read_text(encoding="utf-8").splitlines())
             for p in root.rglob("*.py") if "_generated" not in p.parts}
    assert len(sizes) > 80
    over = {k: n for k, n in sizes.items() if n > LIMIT}
    assert over == {}, f"modules over {LIMIT} lines: {over}"
