#!/usr/bin/python3
"""Tests of accuracy_instances.py (record, compare, whole, separation) on small hand-made files; ctest runs it."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "accuracy_instances.py")


def rows(tag, seed, outcomes, adds=None):
    """instances.tsv lines: one instance per (image, ADD(-S) success) of object 3 in scene 1;
    the ADD-S success `adds` (the same for all), or no such column where None."""
    last = "" if adds is None else f"\t{adds}"
    return [f"{tag}\t{seed}\t1\t{image}\t3\t004_sugar_box\t{0.01 if ok else 0.1:.6f}\t{ok}{last}"
            for image, ok in outcomes]


class CompareTest(unittest.TestCase):
    def compare(self, lines, a, b, *flags):
        with tempfile.TemporaryDirectory() as d:
            tsv = os.path.join(d, "instances.tsv")
            with open(tsv, "w") as f:
                f.write("\n".join(lines) + "\n")
            return subprocess.run([sys.executable, SCRIPT, "compare", *flags, a, b, tsv], capture_output=True,
                                  text=True)

    def test_adds_compares_the_adds_column_and_leaves_out_lines_without_it(self):
        lines = (rows("A", 0, [(1, 0), (2, 0)], adds=1) + rows("A", 1, [(1, 0), (2, 0)], adds=0) +
                 rows("A", 2, [(1, 1), (2, 1)]) +  # no ADD-S column: left out
                 rows("B", 0, [(1, 0), (2, 1)], adds=1))
        r = self.compare(lines, "A", "B", "--adds")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("ADD-S < 4 cm", r.stdout)
        line = next(l for l in r.stdout.splitlines() if l.startswith("004_sugar_box"))
        # ADD-S: A half of seeds 0 and 1 for both images (1.00), B always (2.00).
        self.assertIn("2      2-2      1-1", line)
        self.assertIn("1.00         2.00 | -1.00", line)
        r = self.compare(lines, "A", "B")  # ADD(-S): A's three seeds, 1/3 each; B 1 of 2
        line = next(l for l in r.stdout.splitlines() if l.startswith("004_sugar_box"))
        self.assertIn("0.67         1.00 | -0.33", line)

    def test_instances_lists_each_instance_under_its_object(self):
        lines = (rows("A", 0, [(1, 1), (2, 0)], adds=1) + rows("A", 1, [(1, 1), (2, 1)], adds=1) +
                 rows("B", 0, [(1, 0), (2, 1)], adds=1))
        r = self.compare(lines, "A", "B", "--instances")
        self.assertEqual(r.returncode, 0, r.stderr)
        out = r.stdout.splitlines()
        first = out.index(next(l for l in out if l.startswith("004_sugar_box")))
        # Image 1: A both seeds, B none; image 2: A one of two, B its one seed.
        self.assertRegex(out[first + 1], r"^  1/1 +2 +1 \| +1\.00 +0\.00 \| \+1\.00 ")
        self.assertRegex(out[first + 2], r"^  1/2 +2 +1 \| +0\.50 +1\.00 \| -0\.50 ")
        self.assertTrue(out[first + 3].startswith("ALL"))
        plain = self.compare(lines, "A", "B").stdout.splitlines()
        self.assertEqual(plain, [l for l in out if not l.startswith("  ")])  # the same totals

    def test_adds_names_a_tag_without_the_column(self):
        r = self.compare(rows("A", 0, [(1, 1)], adds=1) + rows("B", 0, [(1, 1)]), "A", "B", "--adds")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("B has no line with the ADD-S column", r.stderr)

    def test_pooled_tags_count_a_shared_seed_once(self):
        lines = (rows("A", 0, [(1, 1), (2, 0)]) + rows("A", 1, [(1, 1), (2, 1)]) +
                 rows("B", 0, [(1, 0), (2, 0)]) +
                 # B2 repeats B's seed 0 (the same outcomes) and adds seeds 1 and 2.
                 rows("B2", 0, [(1, 0), (2, 0)]) + rows("B2", 1, [(1, 1), (2, 0)]) +
                 rows("B2", 2, [(1, 1), (2, 0)]))
        r = self.compare(lines, "A", "B+B2")
        self.assertEqual(r.returncode, 0, r.stderr)
        line = next(l for l in r.stdout.splitlines() if l.startswith("004_sugar_box"))
        # A: image 1 always (1.00), image 2 half (0.50): 1.50. B+B2: seeds 0, 1, 2 (not 0 twice):
        # image 1 two of three, image 2 none: 0.67.
        self.assertIn("2      2-2      3-3", line)
        self.assertIn("1.50         0.67 | +0.83", line)

    def test_pooled_tags_that_disagree_on_a_seed_are_refused(self):
        lines = rows("A", 0, [(1, 1)]) + rows("B", 0, [(1, 0)]) + rows("B2", 0, [(1, 1)])
        r = self.compare(lines, "A", "B+B2")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("differs between the tags", r.stderr)

    def test_an_unknown_tag_is_named(self):
        r = self.compare(rows("A", 0, [(1, 1)], adds=1), "A", "A+C")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("has no tag C", r.stderr)

    def test_whole_assembles_the_seeds_that_cover_every_instance(self):
        def other(tag, seed, ok, adds):  # one instance of another class
            return [f"{tag}\t{seed}\t1\t1\t5\t006_mustard_bottle\t0.01\t{ok}\t{adds}"]
        lines = (rows("S", 0, [(1, 1), (2, 0)], adds=1) + rows("S", 1, [(1, 1), (2, 1)], adds=1) +
                 other("M", 0, 0, 1) + other("M", 2, 1, 1))
        with tempfile.TemporaryDirectory() as d:
            tsv = os.path.join(d, "instances.tsv")
            with open(tsv, "w") as f:
                f.write("\n".join(lines) + "\n")
            r = subprocess.run([sys.executable, SCRIPT, "whole", "S+M", tsv], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        # Only seed 0 ran all three instances: 1 of 3 ADD(-S), 3 of 3 ADD-S.
        self.assertEqual(r.stdout, "0\t33.3\t100.0\t3\n")


class SeparationTest(unittest.TestCase):
    # (tag, seed, image, success, weight) of object 3 in scene 1
    RUNS = [("A", 0, 1, 1, 0.8), ("A", 1, 1, 0, 0.7),   # image 1: the success weighs more
            ("A", 0, 2, 0, 0.5), ("A", 1, 2, 1, 0.6),   # image 2: again
            ("B", 0, 1, 1, 0.5), ("B", 1, 1, 0, 0.5),   # image 1: a tie
            ("B", 0, 2, 1, 0.7), ("B", 1, 2, 1, 0.7)]   # image 2: no failure, no pair

    def separation(self, runs, drop_csv=None):
        with tempfile.TemporaryDirectory() as d:
            tsv = os.path.join(d, "instances.tsv")
            with open(tsv, "w") as f:
                for tag, seed, image, ok, _ in runs:
                    f.write(rows(tag, seed, [(image, ok)], adds=1)[0] + "\n")
            csvs = {}
            for tag, seed, image, _, weight in runs:
                csvs.setdefault((tag, seed), ["scene_id,im_id,obj_id,score,R,t,time"]).append(
                    f"1,{image},3,{weight},1 0 0 0 1 0 0 0 1,0 0 500,0.1")
            for (tag, seed), lines in csvs.items():
                if (tag, seed) == drop_csv:
                    continue
                os.makedirs(os.path.join(d, tag), exist_ok=True)
                with open(os.path.join(d, tag, f"seed_{seed}.csv"), "w") as f:
                    f.write("\n".join(lines) + "\n")
            return subprocess.run([sys.executable, SCRIPT, "separation", "A", "B", tsv], capture_output=True,
                                  text=True)

    def test_separation_counts_pairs_of_runs_within_each_instance(self):
        r = self.separation(self.RUNS)
        self.assertEqual(r.returncode, 0, r.stderr)
        line = next(l for l in r.stdout.splitlines() if l.startswith("004_sugar_box"))
        # A: both pairs won, dw +0.1 in each image. B: one pair, a tie, dw 0. The same-seed
        # successes (A, B): (1, 1), (0, 0), (0, 1), (1, 1): r = 0.125 / sqrt(0.25 * 0.1875).
        self.assertRegex(line, r"^004_sugar_box +1\.00 +\+0\.10000 +0\.50 +\+0\.00000 \| +4 +\+0\.58$")

    def test_separation_names_a_missing_results_file(self):
        r = self.separation(self.RUNS, drop_csv=("B", 1))
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("for seed 1", r.stderr)
        self.assertIn("seed_1.csv", r.stderr)


class RecordTest(unittest.TestCase):
    def test_record_keeps_the_boxed_instances_with_both_successes(self):
        evaluation = {"per_object": [{"obj_id": 3, "name": "004_sugar_box"}],
                      "instances": [
                          # turned half a turn: ADD 11 cm, ADD-S 3 mm
                          {"scene_id": 1, "im_id": 1, "obj_id": 3, "add_or_adds_m": 0.11, "adds_m": 0.003},
                          {"scene_id": 1, "im_id": 2, "obj_id": 3, "add_or_adds_m": 0.01, "adds_m": 0.005},
                          {"scene_id": 1, "im_id": 3, "obj_id": 3, "add_or_adds_m": None, "adds_m": None},
                          {"scene_id": 1, "im_id": 4, "obj_id": 3, "add_or_adds_m": 0.0, "adds_m": 0.0}]}
        detections = [{"scene_id": 1, "image_id": i, "category_id": 3} for i in (1, 2, 3)]  # not image 4
        with tempfile.TemporaryDirectory() as d:
            paths = [os.path.join(d, n) for n in ("eval.json", "dets.json", "instances.tsv")]
            for path, obj in zip(paths, (evaluation, detections)):
                with open(path, "w") as f:
                    json.dump(obj, f)
            r = subprocess.run([sys.executable, SCRIPT, "record", "T", "7", *paths], capture_output=True, text=True)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(r.stdout.split(), ["33.3", "66.7", "3"])  # ADD(-S), ADD-S < 4 cm, instances
            with open(paths[2]) as f:
                lines = [l.rstrip("\n").split("\t") for l in f]
        self.assertEqual(lines, [["T", "7", "1", "1", "3", "004_sugar_box", "0.110000", "0", "1"],
                                 ["T", "7", "1", "2", "3", "004_sugar_box", "0.010000", "1", "1"],
                                 ["T", "7", "1", "3", "3", "004_sugar_box", "", "0", "0"]])


if __name__ == "__main__":
    unittest.main()
