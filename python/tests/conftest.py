"""Shared set-up of the Python tests: the data, the command-line tool, and runs of it that
several tests compare against (made once per session)."""

import csv
import os
import pathlib
import subprocess

import pytest

import mcpose

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("MCPOSE_DATA_DIR", REPO.parent / "shared" / "data"))
YCBV = DATA / "ycbv"
BOP = DATA / "bop_ycbv_subset"
CLI = os.environ.get("MCPOSE_CLI", str(REPO / "build" / "mcpose"))

# Options that keep a run short (a first generation twice, not 8 times, the samples); the
# comparisons hold for any options.
FAST = ["--samples", "150", "--iterations", "12", "--twin-refine", "3", "--refine-iterations", "5",
        "--init-wide", "2"]
# The frames the multi-image tests run on: video 0049, frames 1-6 (4 objects each).
RUN_FRAMES = [(49, i) for i in range(1, 7)]


def run_cli(*args, timeout=300, check=True):
    r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, timeout=timeout)
    if check and r.returncode != 0:
        raise AssertionError(f"mcpose {' '.join(map(str, args))} failed:\n{r.stderr}")
    return r


def cli_error(*args):
    """The one-line message `mcpose` prints for a bad input, without its prefixes."""
    r = run_cli(*args, check=False)
    assert r.returncode != 0, r.stdout
    line = r.stderr.strip().splitlines()[0]
    for prefix in ("mcpose: error: ", "invalid argument: ", "not found: ", "unreadable data: ", "internal error: "):
        line = line.removeprefix(prefix)
    return line


def rows_without_time(path):
    """The rows of a results CSV with the time column dropped, in file order."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["scene_id", "im_id", "obj_id", "score", "R", "t", "time"], rows[0]
    return [tuple(r[:6]) for r in rows[1:]]


@pytest.fixture(scope="session")
def ycbv():
    return mcpose.Dataset(YCBV)


@pytest.fixture(scope="session")
def run_dir(tmp_path_factory):
    return tmp_path_factory.mktemp("runs")


@pytest.fixture(scope="session")
def run_detections(ycbv, run_dir):
    """Detector-like boxes (with distractors) of RUN_FRAMES, as a BOP JSON file."""
    dets = [d for d in ycbv.detections_from_gt(jitter=0.1, distractors=0.3, seed=0)
            if (d["scene_id"], d["image_id"]) in RUN_FRAMES]
    path = run_dir / "dets.json"
    mcpose.write_detections(str(path), dets)
    return path


@pytest.fixture(scope="session")
def cli_run(run_detections, run_dir):
    """`mcpose estimate` over RUN_FRAMES with FAST options, seed 3, uninterrupted."""
    out = run_dir / "cli.csv"
    run_cli("estimate", "--dataset", YCBV, "--detections", run_detections, "--out", out, "--seed", 3, "-q", *FAST)
    return out
