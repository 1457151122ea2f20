#!/usr/bin/python3
"""Per-instance accuracy records over seeds, and per-object comparisons of two tags.

The seeds of scripts/accuracy_seeds.sh are whole runs; their ADD(-S) < 4 cm shares (summary.tsv)
say how much two engine options differ, not where. This keeps one line per seed and instance in
out/seeds/instances.tsv (tag, seed, scene, image, object id and name, ADD(-S) in metres,
success: ADD(-S) < 4 cm, and ADD-S < 4 cm, a column that older lines may lack) and compares two
tags object by object.

Each (image, class) draws from its own random streams (Estimator::Estimate's stream_id), so an
instance's result depends on the seed and the options only, not on the other boxes of the run:
a run on a subset of the detections (accuracy_seeds.sh with DETECTIONS=subset.json) gives the
subset's instances the poses of the whole run (test Cli.EachClassAloneGivesTheWholeRunsRow; on
the main job, defaults seed 0: the 57 rows of the nine stride-3 classes and the cracker box's 5
run alone equal the whole run's), and instances may be run with different numbers of seeds.
Instances are independent samples, and the seeds of one instance too, so an object's
expected successes are the sum of its instances' success rates over their seeds, with the
binomial standard error of that sum.

Usage:
  accuracy_instances.py record TAG SEED EVAL_JSON DETECTIONS_JSON [instances.tsv]
      Appends the instances of EVAL_JSON (`mcpose eval --json`) whose (scene, image, class) has
      a box in DETECTIONS_JSON, replacing the tag's earlier lines for that seed; prints the
      subset's ADD(-S) < 4 cm and ADD-S < 4 cm in % of those instances, and their number.
  accuracy_instances.py compare [--adds] [--instances] TAG_A TAG_B [instances.tsv]
      Per object, over the instances both tags have: seeds, expected successes of A and B, the
      difference and its standard error (an instance with one seed counts the largest binomial
      variance, 0.25); then the total in instances and in points of the main job's 108, with a
      normal 90 % interval.
      A tag may pool several, joined by '+' (e.g. reference+sugar.ref: the same options run on
      the whole job and on one class's boxes): each instance's seeds are pooled, and a seed
      that two of them both ran counts once (it must have the same outcome in both, else
      the tags are not the same options and compare stops).
      --adds compares ADD-S < 4 cm instead (lines without that column are left out). ADD-S
      (the mean distance to the nearest model point) scores the fit of the shape, not which
      of its twins was chosen: the sugar box turned half a turn has ADD 10-12 cm and ADD-S
      a few mm.
      --instances also lists, under each object, every instance (scene/image): its seeds and
      success rate in A and in B, and the difference.
  accuracy_instances.py whole TAGS [instances.tsv]
      The seeds that the '+'-joined TAGS ran on every instance any of them has (e.g. one
      class's boxes per tag, all classes together): whole runs assembled from subset runs,
      with the poses of a whole run. Prints per such seed: seed, ADD(-S) < 4 cm and
      ADD-S < 4 cm in % of those instances (ADD-S: "-" where a line lacks it), and their number.
  accuracy_instances.py separation TAG_A TAG_B [instances.tsv]
      Why two tags differ on an object: per object, for each tag, how often a run that
      succeeded on an instance ended with a higher weight (the `score` column of
      out/seeds/TAG/seed_S.csv, beside instances.tsv) than a run that failed on the same
      instance, over all such pairs of runs (0.5: the weight does not tell the right pose from
      the wrong ones, 1: it always prefers the right one; ties count half), and the mean weight
      of the successes minus that of the failures. Then the correlation of success between A
      and B on the seeds both ran (each instance's seed s draws the same initial samples and
      noise in both, so a high correlation would make a paired comparison sharper).
"""
import csv
import json
import math
import os
import sys
from collections import defaultdict

DEFAULT_TSV = "out/seeds/instances.tsv"
THRESHOLD_M = 0.04


def fail(message):
    print(f"accuracy_instances: {message}", file=sys.stderr)
    sys.exit(1)


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        fail(f"{path}: {e}")


def record(tag, seed, eval_json, detections_json, tsv):
    evaluation, detections = load_json(eval_json), load_json(detections_json)
    boxed = {(d["scene_id"], d["image_id"], d["category_id"]) for d in detections}
    names = {o["obj_id"]: o["name"] for o in evaluation["per_object"]}
    rows = []
    for inst in evaluation["instances"]:
        key = (inst["scene_id"], inst["im_id"], inst["obj_id"])
        if key not in boxed:
            continue
        error = inst["add_or_adds_m"]  # None: no result for a boxed instance, a failure
        adds = inst["adds_m"]
        rows.append([tag, seed, *key, names.get(key[2], str(key[2])), "" if error is None else f"{error:.6f}",
                     int(error is not None and error < THRESHOLD_M),
                     int(adds is not None and adds < THRESHOLD_M)])
    if not rows:
        fail(f"no instance of {eval_json} has a box in {detections_json}")
    kept = []
    if os.path.exists(tsv):
        with open(tsv) as f:
            kept = [r for r in csv.reader(f, delimiter="\t") if not (r[0] == tag and r[1] == str(seed))]
    with open(tsv + ".tmp", "w", newline="") as f:
        w = csv.writer(f, delimiter="\t", lineterminator="\n")
        w.writerows(kept)
        w.writerows(rows)
    os.replace(tsv + ".tmp", tsv)
    n = len(rows)
    print(f"{100 * sum(r[7] for r in rows) / n:.1f} {100 * sum(r[8] for r in rows) / n:.1f} {n}")


def load(tsv, column=7):
    """{tag: {(scene, image, object): {seed: success}}}, {object: name}; success in `column`
    (7: ADD(-S) < 4 cm, 8: ADD-S < 4 cm; lines without it are left out)."""
    if not os.path.exists(tsv):
        fail(f"{tsv} is missing (scripts/accuracy_seeds.sh writes it)")
    out, names = defaultdict(lambda: defaultdict(dict)), {}
    with open(tsv) as f:
        for line, r in enumerate(csv.reader(f, delimiter="\t"), 1):
            if column == 8 and len(r) == 8:
                out.setdefault(r[0], defaultdict(dict))  # written before the ADD-S column
                continue
            try:
                seed, key, success = int(r[1]), (int(r[2]), int(r[3]), int(r[4])), int(r[column])
            except (IndexError, ValueError):
                fail(f"{tsv}:{line}: not a record (tag, seed, scene, image, object, name, ADD(-S), "
                     "ADD(-S) success[, ADD-S success])")
            out[r[0]][key][seed] = success
            names[key[2]] = r[5]
    return out, names


def pooled(data, tags, tsv):
    """{(scene, image, object): {seed: success}} of the '+'-joined tags, each seed once."""
    seeds = defaultdict(dict)
    for t in tags.split("+"):
        if t not in data:
            fail(f"{tsv} has no tag {t}")
        for key, outcomes in data[t].items():
            for seed, success in outcomes.items():
                if seeds[key].setdefault(seed, success) != success:
                    fail(f"{tags}: seed {seed} of instance {key} differs between the tags: "
                         "they are not the same options")
    return seeds


def rate(outcomes):
    """The success rate over seeds and the variance of that mean (sample variance / n)."""
    n = len(outcomes)
    p = sum(outcomes) / n
    var = sum((x - p) ** 2 for x in outcomes) / (n - 1) / n if n > 1 else 0.25
    return p, var


def shared_instances(data, tag_a, tag_b):
    """The instances both tags have, sorted, and {object: those of its instances}."""
    common = sorted(set(data[tag_a]) & set(data[tag_b]))
    if not common:
        fail(f"{tag_a} and {tag_b} share no instance")
    per_object = defaultdict(list)
    for key in common:
        per_object[key[2]].append(key)
    return common, per_object


def compare(tag_a, tag_b, tsv, adds=False, instances=False, main_job_instances=108):
    loaded, names = load(tsv, 8 if adds else 7)
    data = {}
    for t in (tag_a, tag_b):
        data[t] = {key: list(outcomes.values()) for key, outcomes in pooled(loaded, t, tsv).items()}
        if not data[t]:  # only where every line of t predates the ADD-S column
            fail(f"{tsv}: {t} has no line with the ADD-S column")
    common, per_object = shared_instances(data, tag_a, tag_b)
    print(f"Expected successes, {'ADD-S' if adds else 'ADD(-S)'} < 4 cm")
    print(f"{'object':24} inst  seeds A  seeds B | {tag_a[:12]:>12} {tag_b[:12]:>12} | A - B (SE)")
    total_d, total_var = 0.0, 0.0
    for obj in sorted(per_object):
        keys = per_object[obj]
        sa = [rate(data[tag_a][k]) for k in keys]
        sb = [rate(data[tag_b][k]) for k in keys]
        ea, eb = sum(p for p, _ in sa), sum(p for p, _ in sb)
        var = sum(v for _, v in sa) + sum(v for _, v in sb)
        total_d += ea - eb
        total_var += var
        na = f"{min(len(data[tag_a][k]) for k in keys)}-{max(len(data[tag_a][k]) for k in keys)}"
        nb = f"{min(len(data[tag_b][k]) for k in keys)}-{max(len(data[tag_b][k]) for k in keys)}"
        print(f"{names[obj]:24} {len(keys):4} {na:>8} {nb:>8} | {ea:12.2f} {eb:12.2f} | "
              f"{ea - eb:+.2f} ({math.sqrt(var):.2f})")
        if instances:
            for k, (pa, va), (pb, vb) in zip(keys, sa, sb):
                print(f"  {f'{k[0]}/{k[1]}':27} {len(data[tag_a][k]):>8} {len(data[tag_b][k]):>8} | "
                      f"{pa:12.2f} {pb:12.2f} | {pa - pb:+.2f} ({math.sqrt(va + vb):.2f})")
    se = math.sqrt(total_var)
    print(f"{'ALL':24} {len(common):4} | A - B {total_d:+.2f} instances (SE {se:.2f}); "
          f"{100 * total_d / main_job_instances:+.2f} points of the main job's {main_job_instances} "
          f"(SE {100 * se / main_job_instances:.2f}; 90 % interval [{100 * (total_d - 1.6449 * se) / main_job_instances:+.2f}, "
          f"{100 * (total_d + 1.6449 * se) / main_job_instances:+.2f}])")


def whole(tags, tsv):
    def by_seed(column):  # {seed: {instance: success}}
        out = defaultdict(dict)
        for key, outcomes in pooled(load(tsv, column)[0], tags, tsv).items():
            for seed, success in outcomes.items():
                out[seed][key] = success
        return out

    add_s, adds = by_seed(7), by_seed(8)
    instances = set().union(*add_s.values())
    n = len(instances)
    for seed in sorted(add_s):
        if set(add_s[seed]) != instances:
            continue
        share = f"{100 * sum(adds[seed].values()) / n:.1f}" if set(adds[seed]) == instances else "-"
        print(f"{seed}\t{100 * sum(add_s[seed].values()) / n:.1f}\t{share}\t{n}")


def run_weights(tags, tsv, data):
    """{(scene, image, object): {seed: weight}} of the '+'-joined tags, from each tag's
    seed_S.csv beside `tsv`, for the instances and seeds `data` (pooled outcomes) holds."""
    weights = defaultdict(dict)
    for t in tags.split("+"):
        seeds = sorted({s for outcomes in data.values() for s in outcomes})
        for seed in seeds:
            path = os.path.join(os.path.dirname(tsv) or ".", t, f"seed_{seed}.csv")
            if not os.path.exists(path):
                continue  # this tag of the pool did not run that seed
            with open(path) as f:
                for line, r in enumerate(csv.DictReader(f), 2):
                    try:
                        key = (int(r["scene_id"]), int(r["im_id"]), int(r["obj_id"]))
                        weight = float(r["score"])
                    except (KeyError, TypeError, ValueError):
                        fail(f"{path}:{line}: not a results row (scene_id, im_id, obj_id, score, ...)")
                    if key in data and seed in data[key]:
                        weights[key][seed] = weight
    for key, outcomes in data.items():
        missing = [s for s in outcomes if s not in weights[key]]
        if missing:
            fail(f"{tags}: no results row of instance {key} for seed {missing[0]} in "
                 f"{os.path.join(os.path.dirname(tsv) or '.', '<tag>', f'seed_{missing[0]}.csv')}")
    return weights


def separation(tag_a, tag_b, tsv):
    loaded, names = load(tsv)
    data = {t: pooled(loaded, t, tsv) for t in (tag_a, tag_b)}
    weights = {t: run_weights(t, tsv, data[t]) for t in (tag_a, tag_b)}
    _, per_object = shared_instances(data, tag_a, tag_b)

    def separate(t, keys):  # P(success's weight > failure's), mean difference; None: no pair
        wins, pairs, diffs = 0.0, 0, []
        for k in keys:
            ok = [weights[t][k][s] for s, x in data[t][k].items() if x]
            bad = [weights[t][k][s] for s, x in data[t][k].items() if not x]
            for a in ok:
                for b in bad:
                    wins += 1.0 if a > b else 0.5 if a == b else 0.0
            pairs += len(ok) * len(bad)
            if ok and bad:
                diffs.append(sum(ok) / len(ok) - sum(bad) / len(bad))
        if not pairs:
            return None
        return wins / pairs, sum(diffs) / len(diffs)

    def paired(keys):  # correlation of A's and B's success on the seeds both ran; None: no spread
        xs = [(data[tag_a][k][s], data[tag_b][k][s]) for k in keys for s in data[tag_a][k] if s in data[tag_b][k]]
        n = len(xs)
        if n < 2:
            return None, n
        ma, mb = sum(a for a, _ in xs) / n, sum(b for _, b in xs) / n
        cov = sum((a - ma) * (b - mb) for a, b in xs) / n
        va, vb = ma * (1 - ma), mb * (1 - mb)
        return (cov / math.sqrt(va * vb) if va > 0 and vb > 0 else None), n

    print(f"Does the weight tell the right pose from the wrong ones? (ADD(-S) < 4 cm; A = {tag_a}, B = {tag_b})")
    print("P: how often a success's weight beats a failure's of the same instance; dw: the mean weight of the")
    print("successes minus the failures'; r: the correlation of A's and B's successes on the same seeds")
    print(f"{'object':24} {'P A':>6} {'dw A':>9} {'P B':>6} {'dw B':>9} | {'pairs':>6} {'r':>6}")
    for obj in sorted(per_object):
        keys = per_object[obj]
        cells = []
        for t in (tag_a, tag_b):
            s = separate(t, keys)
            cells += ["-", "-"] if s is None else [f"{s[0]:.2f}", f"{s[1]:+.5f}"]
        r, n = paired(keys)
        print(f"{names[obj]:24} {cells[0]:>6} {cells[1]:>9} {cells[2]:>6} {cells[3]:>9} | "
              f"{n:6} {'-' if r is None else f'{r:+.2f}':>6}")


def main(argv):
    if len(argv) >= 6 and argv[1] == "record":
        record(argv[2], int(argv[3]), argv[4], argv[5], argv[6] if len(argv) > 6 else DEFAULT_TSV)
    elif len(argv) >= 4 and argv[1] == "compare":
        flags = {"--adds", "--instances"}
        args = [a for a in argv[2:] if a not in flags]
        if len(args) < 2:
            print(__doc__, file=sys.stderr)
            sys.exit(2)
        compare(args[0], args[1], args[2] if len(args) > 2 else DEFAULT_TSV,
                "--adds" in argv[2:], "--instances" in argv[2:])
    elif len(argv) >= 4 and argv[1] == "separation":
        separation(argv[2], argv[3], argv[4] if len(argv) > 4 else DEFAULT_TSV)
    elif len(argv) >= 3 and argv[1] == "whole":
        whole(argv[2], argv[3] if len(argv) > 3 else DEFAULT_TSV)
    else:
        print(__doc__, file=sys.stderr)
        sys.exit(2)


if __name__ == "__main__":
    main(sys.argv)
