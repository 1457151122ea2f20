"""Estimate a dataset on a Dask cluster: one task per image, merged into one BOP results CSV.

    python3 -m mcpose.distributed --dataset DIR --detections FILE --out results.csv \\
        [--scheduler ADDRESS | --workers N] [--resume] [--seed S] [mcpose estimate's options]

Without ``--scheduler`` a ``LocalCluster`` of ``--workers`` processes runs on this machine. With
``--scheduler tcp://HOST:8786`` the tasks go to an existing cluster (``dask-scheduler`` on one
machine, ``dask-worker tcp://HOST:8786 --nthreads 1`` on each); every worker needs this package
on its PYTHONPATH and the dataset at the same path. The CSV equals ``mcpose estimate``'s for the
same options and detections (the time column aside): each image's rows depend only on the seed
and the image. Finished images are journalled to OUT.partial as they arrive, as by ``mcpose
estimate``: ``--resume`` after a kill redoes only the unfinished ones, and a worker lost mid-run
costs only its images, which the scheduler gives to another worker.
"""

import argparse
import os
import sys
import time
import uuid

from . import Dataset, _mcpose

_WORKER_CACHE = {}


def _estimate_image(dataset, split, models, estimator_args, detections, source):
    """On a worker: the rows of one image (a dataset and estimator kept per worker process)."""
    key = (dataset, split, models, tuple(estimator_args))
    if key not in _WORKER_CACHE:
        _WORKER_CACHE.clear()
        _WORKER_CACHE[key] = (Dataset(dataset, split, models), _mcpose.Estimator(list(estimator_args)))
    ds, est = _WORKER_CACHE[key]
    return est.run(ds, detections, source)


class _Progress:
    """A one-line progress bar on stderr."""

    def __init__(self, total, kept, quiet):
        self.total, self.done, self.quiet, self.start = total, kept, quiet, time.monotonic()
        self.draw()

    def draw(self):
        if self.quiet:
            return
        width = 30
        filled = width * self.done // max(self.total, 1)
        sys.stderr.write(f"\r[{'#' * filled}{'-' * (width - filled)}] {self.done}/{self.total} images "
                         f"{time.monotonic() - self.start:.1f} s")
        sys.stderr.flush()

    def step(self):
        self.done += 1
        self.draw()

    def close(self):
        if not self.quiet:
            sys.stderr.write("\n")


def _parse(argv):
    p = argparse.ArgumentParser(
        prog="python3 -m mcpose.distributed",
        description="Estimate one pose per (image, class) on a Dask cluster, one task per image; any other "
                    "option is mcpose estimate's (--seed, --samples, ...).")
    p.add_argument("--dataset", required=True, help="Dataset root (YCB-Video or BOP layout)")
    p.add_argument("--split", default="test", help="BOP split folder")
    p.add_argument("--models", default="", help="Models folder to read meshes from instead of the dataset's")
    p.add_argument("--detections", required=True, help="BOP default-detections JSON")
    p.add_argument("--out", required=True, help="Results CSV (BOP format)")
    p.add_argument("--scheduler", help="Address of a running Dask scheduler, e.g. tcp://10.0.0.1:8786")
    p.add_argument("--workers", type=int, help="Worker processes of the local cluster (default: one per core)")
    p.add_argument("--resume", action="store_true",
                   help="Continue a killed run: keep the images its journal OUT.partial finished")
    p.add_argument("--retries", type=int, default=2, help="Extra tries of an image whose task fails")
    p.add_argument("-q", "--quiet", action="store_true", help="No progress bar")
    return p.parse_known_args(argv)


def run(args, estimator_args, client):
    """Runs the estimation of ``args`` on ``client``'s cluster; returns the number of rows."""
    detections = _mcpose.read_detections(args.detections)
    if not detections:
        raise ValueError(f"{args.detections}: holds no detections")
    estimator = _mcpose.Estimator(estimator_args)
    dataset = Dataset(args.dataset, args.split, args.models)
    _mcpose.check_detections(dataset, detections, args.detections)

    by_image = {}
    for d in detections:
        by_image.setdefault((d["scene_id"], d["image_id"]), []).append(d)
    fingerprint = estimator.fingerprint(detections, dataset)
    journal = _mcpose.ResultsJournal(args.out, fingerprint, args.resume)
    pending = [k for k in sorted(by_image) if not journal.has(*k)]
    if journal.kept_images and not args.quiet:
        print(f"resuming: {journal.kept_images} finished images kept from {args.out}.partial", file=sys.stderr)

    from distributed import as_completed
    # Task keys are unique to this run: two runs on one cluster never share (or cancel) a task.
    run_id = f"{fingerprint}-{uuid.uuid4().hex}"
    futures = {}
    for key in pending:
        fut = client.submit(_estimate_image, os.path.abspath(args.dataset), args.split,
                            os.path.abspath(args.models) if args.models else "", estimator_args,
                            by_image[key], args.detections, key=f"mcpose-image-{key[0]}-{key[1]}-{run_id}",
                            retries=args.retries, pure=False)
        futures[fut] = key
    progress = _Progress(len(by_image), len(by_image) - len(pending), args.quiet)
    for fut in as_completed(futures):
        key = futures[fut]
        journal.append(key[0], key[1], fut.result())
        progress.step()
    progress.close()
    journal.finish()
    return sum(len({d["category_id"] for d in dets}) for dets in by_image.values())  # a row per (image, class)


def _is_cluster_error(e):
    """Whether ``e`` is how a task or the cluster failed: an estimation error raised on a
    worker (RuntimeError), a task whose workers all died (KilledWorker), a cancelled task, a
    lost scheduler (CommClosedError, TimeoutError)."""
    import concurrent.futures
    from distributed import KilledWorker
    from distributed.comm.core import CommClosedError
    return isinstance(e, (RuntimeError, KilledWorker, CommClosedError, TimeoutError,
                          concurrent.futures.CancelledError))


def _cluster_message(e, out):
    from distributed import KilledWorker
    if isinstance(e, KilledWorker):
        text = f"task {e.task} was lost with {e.allowed_failures + 1} workers that died running it"
        worker = getattr(e.last_worker, "address", None)
        if worker:
            text += f" (the last {worker})"
    else:
        text = f"{type(e).__name__}: {e}" if str(e) else type(e).__name__
    if os.path.exists(out + ".partial"):
        text += f"; the images finished are kept in {out}.partial: rerun with --resume"
    return text


def main(argv=None):
    args, estimator_args = _parse(sys.argv[1:] if argv is None else argv)
    try:
        _mcpose.Estimator(estimator_args)  # the options' errors before any cluster starts
        if args.scheduler and args.workers:
            raise ValueError("--workers sizes the local cluster; with --scheduler the cluster has its own")
        from distributed import Client, LocalCluster
        if args.scheduler:
            with Client(args.scheduler) as client:
                rows = run(args, estimator_args, client)
        else:
            cores = os.cpu_count() or 1
            workers = args.workers or cores
            if workers < 1:
                raise ValueError(f"--workers must be at least 1, got {workers}")
            if not any(a == "--threads" or a.startswith("--threads=") for a in estimator_args):
                estimator_args = estimator_args + ["--threads", str(max(1, cores // workers))]
            with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster, Client(cluster) as client:
                rows = run(args, estimator_args, client)
    except (ValueError, OSError) as e:
        print(f"mcpose.distributed: error: {e}", file=sys.stderr)
        return 1
    except Exception as e:  # noqa: BLE001 - the cluster's failures, reported in one line
        if not _is_cluster_error(e):
            raise
        print(f"mcpose.distributed: error: {_cluster_message(e, args.out)}", file=sys.stderr)
        return 1
    if not args.quiet:
        print(f"{rows} result rows; results: {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
