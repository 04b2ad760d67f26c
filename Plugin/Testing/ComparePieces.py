"""Compares PipelinePieces.py's totals across rank counts (plain python3):
the contour's owned triangles equal the one-process run's exactly (ghost
cells are copies, never counted twice), the decimated triangles are within
2 per piece of it (each piece rounds its own target, and a collapse removes
two triangles), every vertex coloured by Volume on Surface on several ranks
has the colour the one-process run gives the vertex at the same position
(the whole volume is on every rank; vertices are compared where both runs
kept them), a camera change casts no ray again on any rank count (the
volume used before, gathered or whole, is kept), and the runs
on several ranks did meet ghost cells and piece borders (so the distributed
path was exercised).
  python3 ComparePieces.py ranks-1.json ranks-2.json [ranks-4.json ...]
"""

import glob
import json
import sys


def colours(path):
    """Vertex position (to 1e-6) -> RGBA, over the run's rank files."""
    result = {}
    for rank_file in glob.glob(path + ".rank*.json"):
        for x, y, z, r, g, b, a in json.load(open(rank_file)):
            result[(round(x, 6), round(y, 6), round(z, 6))] = (r, g, b, a)
    return result


runs = [json.load(open(path)) for path in sys.argv[1:]]
maps = [colours(path) for path in sys.argv[1:]]
one = runs[0]
failures = 0
print("| ranks | contour owned | contour ghost | border vertices | decimated |")
print("|---|---|---|---|---|")
for run in runs:
    print("| %d | %d | %d | %d | %d |" % (run["ranks"], run["owned"], run["ghost"],
                                         run["border"], run["decimated"]))
for run, coloured in zip(runs[1:], maps[1:]):
    n = run["ranks"]
    shared = [p for p in coloured if p in maps[0]]
    same = sum(1 for p in shared if coloured[p] == maps[0][p])
    print("%d ranks: %d coloured vertices, %d at positions the one-process run kept, "
          "%d of them the same colour" % (n, len(coloured), len(shared), same))
    checks = [
        (len(shared) > len(coloured) // 2 and same == len(shared),
         "Volume on Surface colours equal one process's"),
        (run["owned"] == one["owned"], "owned triangles equal one process's"),
        (abs(run["decimated"] - one["decimated"]) <= 2 * n,
         "decimated triangles within 2 per piece of one process's"),
        (run["ghost"] > 0 and run["border"] > 0, "ghost cells and borders met"),
        (run["cast"] > 0 and run["recast"] == 0, "no ray cast again after a camera change "
         "(%d rays, then %d)" % (run["cast"], run["recast"])),
    ]
    for ok, what in checks:
        if not ok:
            failures += 1
            print("FAIL %d ranks: %s" % (n, what))
if not (one["cast"] > 0 and one["recast"] == 0):
    failures += 1
    print("FAIL 1 rank: rays cast again after a camera change (%d, then %d)" % (
        one["cast"], one["recast"]))
sys.exit(1 if failures or one["ranks"] != 1 else 0)
