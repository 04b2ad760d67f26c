"""Compares PipelinePieces.py's totals across rank counts (plain python3):
the contour's owned triangles equal the one-process run's exactly (ghost
cells are copies, never counted twice), the decimated triangles are within
2 per piece of it (each piece rounds its own target, and a collapse removes
two triangles), and the runs on several ranks did meet ghost cells and
piece borders (so the distributed path was exercised).
  python3 ComparePieces.py ranks-1.json ranks-2.json [ranks-4.json ...]
"""

import json
import sys

runs = [json.load(open(path)) for path in sys.argv[1:]]
one = runs[0]
failures = 0
print("| ranks | contour owned | contour ghost | border vertices | decimated |")
print("|---|---|---|---|---|")
for run in runs:
    print("| %d | %d | %d | %d | %d |" % (run["ranks"], run["owned"], run["ghost"],
                                         run["border"], run["decimated"]))
for run in runs[1:]:
    n = run["ranks"]
    checks = [
        (run["owned"] == one["owned"], "owned triangles equal one process's"),
        (abs(run["decimated"] - one["decimated"]) <= 2 * n,
         "decimated triangles within 2 per piece of one process's"),
        (run["ghost"] > 0 and run["border"] > 0, "ghost cells and borders met"),
    ]
    for ok, what in checks:
        if not ok:
            failures += 1
            print("FAIL %d ranks: %s" % (n, what))
sys.exit(1 if failures or one["ranks"] != 1 else 0)
