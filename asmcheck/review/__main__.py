"""``python -m asmcheck.review advise|testgen|coverage|itf ...``: the review tools on their own."""
from __future__ import annotations

import sys


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] not in ("advise", "testgen", "coverage", "itf"):
        sys.stderr.write("usage: python -m asmcheck.review advise|testgen|coverage|itf FILE [options]\n")
        return 2
    cmd, rest = argv[0], argv[1:]
    if cmd == "advise":
        from .advise import advise_main
        return advise_main(rest)
    if cmd == "testgen":
        from .testgen import testgen_main
        return testgen_main(rest)
    if cmd == "coverage":
        from .coverage import coverage_main
        return coverage_main(rest)
    from .itf import itf_main
    return itf_main(rest)


if __name__ == "__main__":
    sys.exit(main())
