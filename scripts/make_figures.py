"""Regenerate every figure into figures/ (same as ``vorobound figure``)."""

import sys

from vorobound.cli import main

if __name__ == "__main__":
    sys.exit(main(["figure", "--out", "figures", *sys.argv[1:]]))
