#!/usr/bin/python3
"""Tests of accuracy_instances.py compare on small hand-made instances.tsv files (ctest runs it)."""
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "accuracy_instances.py")


def rows(tag, seed, outcomes):
    """instances.tsv lines: one instance per (image, success) of object 3 in scene 1."""
    return [f"{tag}\t{seed}\t1\t{image}\t3\t004_sugar_box\t{0.01 if ok else 0.1:.6f}\t{ok}\t1"
            for image, ok in outcomes]


class CompareTest(unittest.TestCase):
    def compare(self, lines, a, b):
        with tempfile.TemporaryDirectory() as d:
            tsv = os.path.join(d, "instances.tsv")
            with open(tsv, "w") as f:
                f.write("\n".join(lines) + "\n")
            return subprocess.run([sys.executable, SCRIPT, "compare", a, b, tsv], capture_output=True, text=True)

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
        r = self.compare(rows("A", 0, [(1, 1)]), "A", "A+C")
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("has no tag C", r.stderr)


if __name__ == "__main__":
    unittest.main()
