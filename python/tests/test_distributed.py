"""The Dask runner on a LocalCluster of 2 worker processes over real frames: the CSV of
`mcpose estimate`, also when a worker is killed mid-run, and resumable."""

import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import FAST, YCBV, rows_without_time

pytest.importorskip("distributed")

RUNNER = [sys.executable, "-m", "mcpose.distributed"]


def runner_args(dets, out, *extra):
    return [*RUNNER, "--dataset", str(YCBV), "--detections", str(dets), "--out", str(out), "--seed", "3",
            *FAST, *map(str, extra)]


def test_local_cluster_equals_cli(cli_run, run_detections, tmp_path):
    out = tmp_path / "dask.csv"
    r = subprocess.run(runner_args(run_detections, out, "--workers", 2), capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    assert "6/6 images" in r.stderr  # the progress bar
    assert rows_without_time(out) == rows_without_time(cli_run)
    assert not (tmp_path / "dask.csv.partial").exists()


def test_worker_killed_mid_run(cli_run, run_detections, tmp_path):
    from distributed import Client, LocalCluster
    out = tmp_path / "killed.csv"
    journal = tmp_path / "killed.csv.partial"
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        pids = client.run(os.getpid)
        p = subprocess.Popen(runner_args(run_detections, out, "--scheduler", cluster.scheduler_address,
                                         "--threads", 1, "-q"),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        deadline = time.monotonic() + 120
        while p.poll() is None and time.monotonic() < deadline:
            if journal.exists() and "# done" in journal.read_text():
                break
            time.sleep(0.02)
        assert p.poll() is None, "the run ended before a worker could be killed"
        busy = [address for address, keys in client.processing().items() if keys]
        assert busy, "no worker holds an image"
        victim = pids[busy[0]]  # a worker with an image in hand
        os.kill(victim, signal.SIGKILL)
        try:
            stdout, stderr = p.communicate(timeout=300)
        finally:
            p.kill()
        assert p.returncode == 0, stderr
        assert victim not in client.run(os.getpid).values()
    assert rows_without_time(out) == rows_without_time(cli_run)


def test_resume_after_kill(cli_run, run_detections, tmp_path):
    """The runner killed with SIGKILL, rerun with --resume: the CLI's rows."""
    out = tmp_path / "r.csv"
    journal = tmp_path / "r.csv.partial"
    p = subprocess.Popen(runner_args(run_detections, out, "--workers", 2, "-q"), stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL, start_new_session=True)
    deadline = time.monotonic() + 120
    while p.poll() is None and time.monotonic() < deadline:
        if journal.exists() and journal.read_text().count("# done") >= 2:
            break
        time.sleep(0.02)
    assert p.poll() is None, "the run ended before it could be killed"
    os.killpg(p.pid, signal.SIGKILL)  # the runner and its local cluster
    p.wait(timeout=30)
    assert not out.exists()
    r = subprocess.run(runner_args(run_detections, out, "--workers", 2, "--resume"), capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "resuming:" in r.stderr
    assert rows_without_time(out) == rows_without_time(cli_run)


def test_bad_option_is_the_cli_message(run_detections, tmp_path):
    r = subprocess.run(runner_args(run_detections, tmp_path / "r.csv", "--engine", "gpu"), capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 1
    assert "--engine must be" in r.stderr and not (tmp_path / "r.csv").exists()


def test_cluster_failures_are_one_line(run_detections, tmp_path, monkeypatch, capsys):
    """A task's error on a worker, a task whose workers all died, a cancelled task: one line,
    exit 1, and --resume named once a journal holds finished images; anything else is a bug and
    is not hidden."""
    import concurrent.futures

    import distributed
    import mcpose.distributed as runner

    class NoCluster:
        def __init__(self, address):
            pass

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return False

    def failing(exc):
        def run(*args):
            raise exc
        return run

    monkeypatch.setattr(distributed, "Client", NoCluster)
    out = tmp_path / "r.csv"
    argv = ["--dataset", str(YCBV), "--detections", str(run_detections), "--out", str(out), "--scheduler",
            "tcp://127.0.0.1:1", "-q"]
    killed = distributed.KilledWorker("mcpose-image-49-2-abc", None, 2)
    for exc, line in [(RuntimeError("49/2: bad depth"), "RuntimeError: 49/2: bad depth"),
                      (concurrent.futures.CancelledError("mcpose-image-49-1-abc"),
                       "CancelledError: mcpose-image-49-1-abc"),
                      (killed, "task mcpose-image-49-2-abc was lost with 3 workers that died running it")]:
        monkeypatch.setattr(runner, "run", failing(exc))
        assert runner.main(argv) == 1
        assert capsys.readouterr().err == f"mcpose.distributed: error: {line}\n"
    (tmp_path / "r.csv.partial").write_text("# mcpose results journal 0\n")
    monkeypatch.setattr(runner, "run", failing(RuntimeError("lost")))
    assert runner.main(argv) == 1
    assert capsys.readouterr().err == (f"mcpose.distributed: error: RuntimeError: lost; the images finished are "
                                       f"kept in {out}.partial: rerun with --resume\n")
    monkeypatch.setattr(runner, "run", failing(KeyError("a bug")))
    with pytest.raises(KeyError):
        runner.main(argv)
