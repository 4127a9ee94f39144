"""QA X1 D6: Ctrl-C while ``distkin control`` starts.  The parser's construction
imported ``distkin.control`` (numpy, the numba cache) outside :func:`distkin.app.cli.main`'s
handling of the interrupt: a KeyboardInterrupt traceback and exit -2 instead of
``distkin: error: interrupted`` and 130 (README: 130 interrupted).  The interrupt is
raised by an import hook at the import of ``distkin.control.config``, the moment QA
hit, so the test does not depend on timing."""

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

HOOK = '''
import sys
class Interrupt:
    def find_spec(self, name, path=None, target=None):
        if name == "distkin.control.config":
            raise KeyboardInterrupt
        return None
sys.meta_path.insert(0, Interrupt())
from distkin.app.cli import main
sys.exit(main(sys.argv[1:]))
'''


def _run(code, *args):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-c", code, *args], capture_output=True,
                          text=True, env=env, timeout=300)


def test_an_interrupt_while_the_controller_loads_is_one_line_and_130(tmp_path):
    for cmd in (["control", "--sim", "--seconds", "1"], ["sim"]):
        proc = _run(HOOK, *cmd)
        assert proc.returncode == 130, proc.stderr
        assert proc.stderr.strip().splitlines() == ["distkin: error: interrupted"]


def test_building_the_parser_imports_neither_numpy_nor_the_control_package():
    proc = _run("import sys\nfrom distkin.app.cli import build_parser\nbuild_parser()\n"
                "print(sorted(m for m in ('numpy', 'distkin.control') if m in sys.modules))")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"
