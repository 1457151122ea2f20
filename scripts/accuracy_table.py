#!/usr/bin/python3
"""Accuracy of several runs side by side, each the mean over its seeds.

Usage: accuracy_table.py [--per-video] [--transposed [--objects A,B] [--baseline RUN]]
                         RUN:EVAL_JSON [RUN:EVAL_JSON ...]
Each EVAL_JSON is `mcpose eval --json` output; the files of one RUN (one per seed) are averaged.
Default: one row per object and overall, the runs side by side under ADD(-S) < 4 cm, ADD-S < 4 cm
and ADD-S AUC (YCB-Video protocol), in %, and where the files hold it (`mcpose eval --metrics
ycbv,bop19`) the BOP19 average recall with its range over the seeds. --per-video adds the same
per video (scene). Videos
0000-0003 are the training videos the defaults were chosen on, 0049 the test video.
--transposed: one row per run instead (overall, and ADD(-S) < 4 cm of each object named by
--objects), with each run's difference to --baseline.
"""
import argparse
import json
import sys

METRICS = [("add_s_lt_4cm", "ADD(-S)<4"), ("adds_lt_4cm", "ADD-S<4"), ("adds_auc", "ADD-S AUC")]


def auc(errors, max_m=0.1):
    """The accuracy-threshold AUC up to max_m, as mcpose eval computes it (src/eval/metrics.cc)."""
    if not errors:
        return 0.0
    below = [max(e, 0.0) for e in errors if e is not None and e < max_m]
    return (len(below) - sum(below) / max_m) / len(errors)


def video_metrics(doc, scene):
    """The three metrics over one video's instances, from the per-instance errors."""
    inst = [i for i in doc["instances"] if i["scene_id"] == scene]

    def err(i, key):
        return i[key] if i.get("has_result", True) and i[key] is not None else float("inf")

    n = len(inst)
    return {
        "instances": n,
        "add_s_lt_4cm": sum(err(i, "add_or_adds_m") < 0.04 for i in inst) / n,
        "adds_lt_4cm": sum(err(i, "adds_m") < 0.04 for i in inst) / n,
        "adds_auc": auc([err(i, "adds_m") for i in inst]),
    }


def row_of(doc, obj=None, scene=None):
    if scene is not None:
        return video_metrics(doc, scene)
    if obj is None:
        return doc["overall"]
    return next(o for o in doc["per_object"] if o["obj_id"] == obj or o["name"] == obj)


def mean(docs, key, obj=None, scene=None):
    return 100 * sum(row_of(d, obj, scene)[key] for d in docs) / len(docs)


def side_by_side(runs, names, per_video):
    seeds = {len(v) for v in runs.values()}
    print(f"Mean over {'/'.join(str(s) for s in sorted(seeds))} seed(s), % of instances; runs: {', '.join(names)}")
    header = f"{'object':24} {'inst':>4} | " + " | ".join(
        label + ": " + " ".join(f"{n:>8}" for n in names) for _, label in METRICS)
    print(header)
    first = runs[names[0]][0]

    def line(title, inst, obj=None, scene=None):
        cells = " | ".join(" " * (len(label) + 2) + " ".join(f"{mean(runs[n], key, obj, scene):8.1f}" for n in names)
                           for key, label in METRICS)
        print(f"{title:24} {inst:4d} | {cells}")

    for o in first["per_object"]:
        line(o["name"], o["instances"], obj=o["obj_id"])
    line("ALL", first["overall"]["instances"])
    if per_video:
        print("per video (0000-0003 training, 0049 test):")
        for scene in sorted({i["scene_id"] for i in first["instances"]}):
            line(f"video {scene:04d}", video_metrics(first, scene)["instances"], scene=scene)
    if all("bop19" in d for n in names for d in runs[n]):
        print("BOP19 average recall, %: AR (AR_VSD / AR_MSSD / AR_MSPD)"
              + (", then AR per video" if per_video else ""))
        for n in names:
            docs = runs[n]
            m = {k: 100 * sum(d["bop19"]["overall"][k] for d in docs) / len(docs)
                 for k in ("ar", "ar_vsd", "ar_mssd", "ar_mspd")}
            ars = [100 * d["bop19"]["overall"]["ar"] for d in docs]
            cells = f"{m['ar']:5.1f} ({min(ars):.1f}-{max(ars):.1f}) ({m['ar_vsd']:.1f} / {m['ar_mssd']:.1f} / {m['ar_mspd']:.1f})"
            if per_video:
                scenes = sorted(r["scene_id"] for r in docs[0]["bop19"]["per_scene"])
                for scene in scenes:
                    ar = sum(100 * r["ar"] for d in docs for r in d["bop19"]["per_scene"] if r["scene_id"] == scene)
                    cells += f" | {scene:04d} {ar / len(docs):5.1f}"
            print(f"{n:24} {cells}")


def transposed(runs, names, objects, baseline):
    base = runs.get(baseline) if baseline else None
    first = runs[names[0]][0]
    objs = []
    for name in objects:
        try:
            objs.append(row_of(first, name)["name"])
        except StopIteration:
            sys.exit(f"accuracy_table: no object {name} in the evaluation")
    cols = [label for _, label in METRICS] + [f"{o} (-S)<4" for o in objs]
    print(f"{'run':28} " + " ".join(f"{c:>14}" for c in cols))
    for n in names:
        cells = []
        for key, _ in METRICS:
            v = mean(runs[n], key)
            d = "" if base is None or n == baseline else f" ({v - mean(base, key):+.1f})"
            cells.append(f"{v:.1f}{d}")
        for o in objs:
            cells.append(f"{mean(runs[n], 'add_s_lt_4cm', o):.1f}")
        print(f"{n:28} " + " ".join(f"{c:>14}" for c in cells))
    if base is not None:
        print(f"(in brackets: points against {baseline})")


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument("--per-video", action="store_true")
    parser.add_argument("--transposed", action="store_true")
    parser.add_argument("--objects", default="")
    parser.add_argument("--baseline", default="")
    parser.add_argument("runs", nargs="+", metavar="RUN:EVAL_JSON")
    args = parser.parse_args(argv)
    if any(":" not in a for a in args.runs):
        sys.exit(__doc__.strip())
    runs = {}
    for a in args.runs:
        run, path = a.rsplit(":", 1)
        runs.setdefault(run, []).append(json.load(open(path)))
    names = list(runs)
    if args.baseline and args.baseline not in runs:
        sys.exit(f"accuracy_table: no run named {args.baseline}")
    if args.transposed:
        transposed(runs, names, [o for o in args.objects.split(",") if o], args.baseline)
    else:
        side_by_side(runs, names, args.per_video)


if __name__ == "__main__":
    main(sys.argv[1:])
