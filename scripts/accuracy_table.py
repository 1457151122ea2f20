#!/usr/bin/python3
"""Per-object accuracy of several runs side by side, each the mean over its seeds.

Usage: accuracy_table.py RUN:EVAL_JSON [RUN:EVAL_JSON ...]
Each EVAL_JSON is `mcpose eval --json` output; the files of one RUN (one per seed) are averaged.
Columns: ADD(-S) < 4 cm, ADD-S < 4 cm and ADD-S AUC (YCB-Video protocol) per run, in %.
"""
import json
import sys


def main(args):
    if not args or any(":" not in a for a in args):
        sys.exit(__doc__.strip())
    runs = {}
    for a in args:
        run, path = a.split(":", 1)
        runs.setdefault(run, []).append(json.load(open(path)))
    names = list(runs)
    seeds = {len(v) for v in runs.values()}

    def mean(docs, key, obj=None):
        rows = [d["overall"] if obj is None else next(o for o in d["per_object"] if o["obj_id"] == obj) for d in docs]
        return 100 * sum(r[key] for r in rows) / len(rows)

    print(f"Mean over {'/'.join(str(s) for s in sorted(seeds))} seed(s), % of instances; runs: {', '.join(names)}")
    metrics = [("add_s_lt_4cm", "ADD(-S)<4"), ("adds_lt_4cm", "ADD-S<4"), ("adds_auc", "ADD-S AUC")]
    print(f"{'object':24} {'inst':>4} | " + " | ".join(label + ": " + " ".join(f"{n:>8}" for n in names)
                                                      for _, label in metrics))
    first = runs[names[0]][0]
    for o in first["per_object"] + [None]:
        k = None if o is None else o["obj_id"]
        name, inst = ("ALL", first["overall"]["instances"]) if o is None else (o["name"], o["instances"])
        cells = " | ".join(" " * (len(label) + 2) + " ".join(f"{mean(runs[n], key, k):8.1f}" for n in names)
                           for key, label in metrics)
        print(f"{name:24} {inst:4d} | {cells}")


if __name__ == "__main__":
    main(sys.argv[1:])
