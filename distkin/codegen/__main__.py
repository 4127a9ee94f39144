"""``python -m distkin.codegen [--check] [NAME ...]``: (re)write the generated kernels.

Without ``--check`` it writes ``distkin/_generated/NAME.py`` for every registered module
(:data:`distkin.codegen.registry.GENERATED`).  With ``--check`` it regenerates into a
temporary folder and exits 1, listing the stale files, if anything differs.
"""

from __future__ import annotations

import argparse
import difflib
import sys
import tempfile
import time
from pathlib import Path

from .registry import GENERATED, generate

__all__ = ["main"]

_DIR = Path(__file__).resolve().parent.parent / "_generated"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m distkin.codegen")
    ap.add_argument("--check", action="store_true", help="compare, do not write")
    ap.add_argument("names", nargs="*", help=f"modules (default: all of {sorted(GENERATED)})")
    args = ap.parse_args(argv)
    names = args.names or sorted(GENERATED)
    unknown = [n for n in names if n not in GENERATED]
    if unknown:
        print(f"distkin.codegen: error: unknown module(s) {unknown}; expected some of "
              f"{sorted(GENERATED)}", file=sys.stderr)
        return 2
    stale = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            t0 = time.perf_counter()
            src = generate(name)
            target = _DIR / f"{name}.py"
            if args.check:
                (Path(tmp) / f"{name}.py").write_text(src, encoding="utf-8")
                old = target.read_text(encoding="utf-8") if target.exists() else ""
                if old != src:
                    stale.append(name)
                    diff = difflib.unified_diff(old.splitlines(), src.splitlines(),
                                                f"committed/{name}.py", f"regenerated/{name}.py",
                                                lineterm="", n=1)
                    print("\n".join(list(diff)[:40]), file=sys.stderr)
                status = "stale" if name in stale else "ok"
            else:
                target.write_text(src, encoding="utf-8")
                status = "written"
            print(f"{name}: {status} ({time.perf_counter() - t0:.1f} s)")
    if stale:
        print(f"distkin.codegen: {len(stale)} generated module(s) differ from their source: "
              f"{stale}; run 'python -m distkin.codegen' and commit", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
