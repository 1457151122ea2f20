"""Resumable runs of `mcpose estimate`: a run killed with SIGKILL part-way and rerun with
--resume gives the rows of an uninterrupted run, none missing, none twice."""

import signal
import subprocess
import time

import pytest

import mcpose
from conftest import CLI, FAST, YCBV, cli_error, rows_without_time, run_cli


def done_images(journal):
    try:
        return sum(1 for line in journal.read_text().splitlines() if line.startswith("# done "))
    except FileNotFoundError:
        return 0


def test_sigkill_then_resume(cli_run, run_detections, tmp_path):
    out = tmp_path / "killed.csv"
    journal = tmp_path / "killed.csv.partial"
    args = [CLI, "estimate", "--dataset", str(YCBV), "--detections", str(run_detections), "--out", str(out),
            "--seed", "3", "-q", *FAST]
    p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    while done_images(journal) < 2 and p.poll() is None and time.monotonic() < deadline:
        time.sleep(0.02)
    assert p.poll() is None, "the run ended before it could be killed"
    p.send_signal(signal.SIGKILL)
    p.wait(timeout=30)
    kept = done_images(journal)
    assert 2 <= kept < 6
    assert not out.exists(), "a killed run must leave no results file"

    resume = [a for a in args if a != "-q"] + ["--resume"]
    r = subprocess.run(resume, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert f"resuming: {kept} finished images kept" in r.stdout + r.stderr
    assert not journal.exists()
    rows, expected = rows_without_time(out), rows_without_time(cli_run)
    assert len(rows) == len({tuple(row) for row in rows}), "a row twice"
    assert rows == expected


def test_resume_of_a_cut_line_and_of_nothing(cli_run, run_detections, tmp_path):
    """--resume without a journal is a fresh run; a journal cut inside an image, or torn by a
    power loss, loses only that image."""
    out = tmp_path / "cut.csv"
    args = ["estimate", "--dataset", YCBV, "--detections", run_detections, "--out", out, "--seed", 3, "-q", *FAST]
    run_cli(*args, "--resume")
    assert rows_without_time(out) == rows_without_time(cli_run)

    lines = cli_run.read_text().splitlines()[1:]
    first = [line for line in lines if line.startswith("49,1,")]
    second = [line for line in lines if line.startswith("49,2,")]
    options = {flag.lstrip("-").replace("-", "_"): value for flag, value in zip(FAST[::2], FAST[1::2])}
    fingerprint = mcpose.Estimator(seed=3, **options).fingerprint(mcpose.read_detections(str(run_detections)),
                                                                  mcpose.Dataset(YCBV))
    # A row cut short, then what a torn write can leave behind: zeros and a stale row's tail.
    journal = [f"# mcpose results journal {fingerprint}", *first, f"# done 49 1 {len(first)}", second[0],
               "\0" * 40, second[1][10:], second[2][:25]]
    out.unlink()
    (tmp_path / "cut.csv.partial").write_text("\n".join(journal))
    r = run_cli(*args[:-len(FAST) - 1], *FAST, "--resume")
    assert "resuming: 1 finished images kept" in r.stdout + r.stderr
    assert rows_without_time(out) == rows_without_time(cli_run)
    # The kept image's rows are the journal's, time column included.
    assert [line for line in out.read_text().splitlines() if line.startswith("49,1,")] == first


def test_resume_refuses_other_options(run_detections, tmp_path):
    out = tmp_path / "r.csv"
    (tmp_path / "r.csv.partial").write_text("# mcpose results journal 0123456789abcdef\n")
    message = cli_error("estimate", "--dataset", YCBV, "--detections", run_detections, "--out", out, "--resume")
    assert message == f"{out}.partial: was written by a run with other options, detections, dataset or mcpose " \
                      "version; rerun without --resume to start afresh"
    assert not out.exists()


def test_fingerprint_names_the_dataset_split_and_models(run_detections, tmp_path):
    """A journal is resumed only by a run on the same dataset folder (however it is named), split
    and models folder."""
    dets = mcpose.read_detections(str(run_detections))
    est = mcpose.Estimator(seed=3)
    base = est.fingerprint(dets, mcpose.Dataset(YCBV))
    assert est.fingerprint(dets, mcpose.Dataset(str(YCBV) + "/./")) == base
    models = tmp_path / "models"
    models.symlink_to(YCBV / "models")
    assert est.fingerprint(dets, mcpose.Dataset(YCBV, models=models)) == base  # the same folder, another name
    assert est.fingerprint(dets, mcpose.Dataset(YCBV, split="train")) != base
    copy = tmp_path / "ycbv"
    copy.mkdir()
    for entry in YCBV.iterdir():
        (copy / entry.name).symlink_to(entry)
    assert est.fingerprint(dets, mcpose.Dataset(copy)) != base  # another dataset folder
    assert mcpose.Estimator(seed=3, threads=1).fingerprint(dets, mcpose.Dataset(YCBV)) == base
    assert mcpose.Estimator(seed=4).fingerprint(dets, mcpose.Dataset(YCBV)) != base


def test_a_second_run_on_the_same_output_is_refused(tmp_path):
    """One run at a time holds a journal: a second one on the same OUT stops at once."""
    out = str(tmp_path / "r.csv")
    first = mcpose._mcpose.ResultsJournal(out, "abc", False)
    with pytest.raises(ValueError, match=r"r\.csv\.partial: in use by another run writing .*r\.csv"):
        mcpose._mcpose.ResultsJournal(out, "abc", True)
    del first
    assert mcpose._mcpose.ResultsJournal(out, "abc", True).kept_images == 0
