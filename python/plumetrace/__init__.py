"""plumetrace: Python side of the odor-plume-tracking simulator.

Submodules:
    plumetrace.report  builds report.html and report.md from a `plumetrace reproduce` output
                       folder (`python3 -m plumetrace.report OUT_DIR`).

Nothing heavy is imported here, so `import plumetrace` stays cheap.
"""

__all__ = []
