"""The ``rockcem`` command line.

Exit codes: 0 success, 2 bad input (one line on stderr, no traceback).
"""

from __future__ import annotations

import argparse
import sys

__all__ = ["main"]


def _materials(args) -> int:
    from .materials import fluids, minerals

    print(f"{'mineral':<22}{'K GPa':>8}{'G GPa':>8}{'rho g/cm3':>11}{'vp km/s':>9}{'vs km/s':>9}  source")
    for name, m in minerals().items():
        print(f"{name:<22}{m.K:8.2f}{m.G:8.2f}{m.rho:11.3f}{m.vp:9.3f}{m.vs:9.3f}  {m.source}")
    print()
    print(f"{'fluid':<22}{'K GPa':>8}{'rho g/cm3':>11}  source")
    for name, f in fluids().items():
        print(f"{name:<22}{f.K:8.2f}{f.rho:11.3f}  {f.source}")
    return 0


def _parser() -> argparse.ArgumentParser:
    from . import __version__

    parser = argparse.ArgumentParser(prog="rockcem", description="Rock physics of burial history.")
    parser.add_argument("--version", action="version", version=f"rockcem {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("materials", help="list the mineral and fluid catalogue")
    p.set_defaults(func=_materials)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``rockcem`` console script."""
    parser = _parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, FileNotFoundError) as exc:
        print(f"rockcem: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
