"""python -m clhair.convert IN.usd OUT.{hair,ply,data}: USD BasisCurves to a strand file.

Exit status 0 on success; 1 with one line on standard error otherwise.
"""

from __future__ import annotations

import argparse
import sys
from typing import List, Optional

from . import Error
from .io import read_usd


def main(argv: Optional[List[str]] = None) -> int:
    p = argparse.ArgumentParser(prog="python -m clhair.convert",
                                description="USD BasisCurves to a clhair strand file")
    p.add_argument("input", help="a .usd, .usda or .usdc file")
    p.add_argument("output", help="a .hair (cyHair), .ply or .data (USC-HairSalon) file")
    p.add_argument("--samples-per-span", type=int, default=4,
                   help="points per span of cubic curves (default 4)")
    a = p.parse_args(argv)
    try:
        groom = read_usd(a.input, samples_per_span=a.samples_per_span)
        groom.write(a.output)
    except Error as e:
        print(f"clhair.convert: {e}", file=sys.stderr)
        return 1
    print(f"{a.output}: {groom.strand_count} strands, {groom.point_count} points")
    return 0


if __name__ == "__main__":
    sys.exit(main())
