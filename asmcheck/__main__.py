"""``python -m asmcheck``: the command line (see asmcheck.cli)."""
import sys

try:
    from .cli import main
except KeyboardInterrupt:          # Ctrl-C while the program is still loading: nothing to report
    sys.exit(3)

sys.exit(main())
