"""python3 -m plumetrace.report OUT_DIR: exit status 0, 2 with the malformed file named, or 3
when a file cannot be read or written (a full disk)."""

import argparse
import sys
import time
from typing import Optional, Sequence

from .._files import BadPath, exit_status
from . import ReportError, build_report


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python3 -m plumetrace.report",
        description="Build report.html, report.md and figures/*.png from OUT_DIR/summary.json "
                    "(and OUT_DIR/sensitivity.json when present).")
    parser.add_argument("out_dir", metavar="OUT_DIR", help="output folder of plumetrace reproduce")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    try:
        written = build_report(args.out_dir)
    except (ReportError, BadPath, OSError) as err:
        print(f"plumetrace.report: error: {err}", file=sys.stderr)
        return exit_status(err)
    elapsed = time.perf_counter() - start
    print(f"wrote {written[0]} and {written[1]} with {len(written) - 2} figures "
          f"in {elapsed:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
