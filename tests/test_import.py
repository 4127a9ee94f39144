"""``import distkin`` stays light: sympy is not imported until symbolic work is asked for.

(The import *time* is measured in benchmarks/bench_import.py, not here.)
"""

import subprocess
import sys

PROBE = """
import sys
import {mod}
print("sympy" in sys.modules)
"""

PROBE_LOADED = """
import sys
import {mod}
print(sorted(m for m in sys.modules if m == "sympy" or m.startswith("sympy.")
             or m == "distkin.codegen" or m.startswith("distkin.codegen.")))
"""


def _imports_sympy(mod: str) -> bool:
    r = subprocess.run([sys.executable, "-c", PROBE.format(mod=mod)], capture_output=True,
                       text=True, check=True)
    return r.stdout.strip() == "True"


def test_import_distkin_does_not_import_sympy():
    assert not _imports_sympy("distkin")


def test_geometry_and_scene_do_not_import_sympy():
    assert not _imports_sympy("distkin.geometry")
    assert not _imports_sympy("distkin.app.scene")
    assert not _imports_sympy("distkin.app.cli")


def test_analyses_and_control_import_neither_sympy_nor_the_code_generator():
    # the numeric analyses and the controller run on the committed kernels only
    # (docs/design.md, "Import direction")
    for mod in ("distkin.indices", "distkin.certify", "distkin.control"):
        r = subprocess.run([sys.executable, "-c", PROBE_LOADED.format(mod=mod)],
                           capture_output=True, text=True, check=True)
        assert r.stdout.strip() == "[]", f"import {mod} loaded {r.stdout.strip()}"


def test_star_import_gives_every_name_of_all():
    """QA: ``from distkin import *`` failed (``__all__`` still named ``numbers``, which
    became ``exact``, and ``scene``/``report``, which live in ``distkin.app``).  Every
    name of ``__all__`` now resolves, and the errors and warnings are distkin.errors'."""
    code = ("from distkin import *\nimport distkin, distkin.errors as e\n"
            "assert all(hasattr(distkin, n) for n in distkin.__all__)\n"
            "assert all(getattr(distkin, n) is getattr(e, n) for n in e.__all__ "
            "if n[0].isupper())\nprint(len(distkin.__all__))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    import distkin
    assert int(r.stdout) == len(distkin.__all__)
