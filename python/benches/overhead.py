"""The module's overhead: `truth` and `compress` through Python against the
library's own time for the same work, measured in the same run on a 40k-rod
system (gamma 23, L = 10, density 40). Writes results/bench-python.json.

    python python/benches/overhead.py [--repeat 5] [--out results/bench-python.json]
"""

import argparse
import json
import statistics
import time
from pathlib import Path

import rgc
from rgc import _rgc


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    rods = rgc.generate(rgc.Box(10.0), density=40, gamma=23, seed=1)
    rows = []
    for what, call in [("truth", lambda: rgc.truth(rods)), ("compress", lambda: rgc.compress(rods))]:
        through, library = [], []
        for _ in range(a.repeat):
            # Alternate, so that drift on a shared machine hits both alike.
            library.append(_rgc.library_seconds(rods, what))
            start = time.perf_counter()
            r = call()
            labels = r.cluster_idx if what == "truth" else r.body_idx
            assert labels.shape == (len(rods),)
            through.append(time.perf_counter() - start)
        row = {
            "what": what,
            "rods": len(rods),
            "python_s": statistics.median(through),
            "library_s": statistics.median(library),
        }
        row["ratio"] = row["python_s"] / row["library_s"]
        rows.append(row)
        print(f"{what:>8}: {len(rods)} rods, through Python {row['python_s']:.3f} s, library {row['library_s']:.3f} s, ratio {row['ratio']:.3f} (median of {a.repeat})")
    if a.out:
        doc = {"command": "python python/benches/overhead.py " + " ".join(f"--{k} {v}" for k, v in vars(a).items() if v is not None), "rows": rows}
        tmp = Path(a.out + ".tmp")
        tmp.write_text(json.dumps(doc, indent=2) + "\n")
        tmp.replace(a.out)


if __name__ == "__main__":
    main()
