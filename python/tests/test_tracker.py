"""The Python tracker against `mcpose track` on real frames: the same poses for the same boxes
and seed at another thread count, a lost track on an empty frame, and the command line's
messages for bad options."""

import json

import numpy as np
import pytest

import mcpose
from conftest import FAST, YCBV, cli_error, run_cli

# Video 0049, frames 1-4: the first frame starts each track from its boxes, the others track.
FRAMES = [(49, i) for i in range(1, 5)]


def test_track_frame_equals_cli(ycbv, tmp_path):
    dets = [d for d in ycbv.detections_from_gt(jitter=0.1, distractors=0.3, seed=2)
            if (d["scene_id"], d["image_id"]) == FRAMES[0]]  # boxes on the first frame only
    path = tmp_path / "dets.json"
    mcpose.write_detections(str(path), dets)
    run_cli("track", "--dataset", YCBV, "--video", 49, "--frames", "1-4", "--detections", path,
            "--out", tmp_path / "t.csv", "--out-json", tmp_path / "t.json", "--seed", 7, "--threads", 2,
            "--track-samples", 200, "-q", *FAST)
    cli = json.loads((tmp_path / "t.json").read_text())
    assert cli["options"]["samples"] == 200 and cli["options"]["estimator"]["seed"] == 7

    tracker = mcpose.Tracker(seed=7, threads=1, track_samples=200, samples=150, iterations=12, twin_refine=3,
                             refine_iterations=5, init_wide=2)
    assert tracker.options == {**cli["options"], "estimator": {
        **cli["options"]["estimator"], "engine": {**cli["options"]["estimator"]["engine"], "threads": 1}}}
    got = []
    for key in FRAMES:
        steps = tracker.track_frame(ycbv.load_frame(*key), dets, ycbv)
        assert list(steps) == sorted(steps)
        got += [(key, s) for s in steps.values()]
    assert tracker.tracked_ids == [3, 6, 9, 13]
    assert len(got) == len(cli["steps"]) == 16
    for (key, s), c in zip(got, cli["steps"]):
        assert (key[0], key[1], s.obj_id) == (c["scene_id"], c["im_id"], c["obj_id"])
        assert s.T_cam_obj[:3, :3].ravel().tolist() == c["R"], (key, s.obj_id)  # exact
        assert (s.T_cam_obj[:3, 3] * 1000.0).tolist() == c["t_mm"], (key, s.obj_id)
        assert (s.weight, s.fit, s.visible, s.iterations) == (c["weight"], c["fit"], c["visible"], c["iterations"])
        assert (s.initialised, s.lost) == (c["initialised"], c["lost"])
        assert s.initialised == (key == FRAMES[0])
        assert list(s.box["bbox"]) == c["box"] and s.time_s > 0


def test_track_arrays_lost_and_restarted(ycbv):
    """The array entry point: a track started from a box, lost on an empty depth image (with no
    box to restart from: the class leaves the tracked set), started again from a box."""
    frame = ycbv.load_frame(49, 1)
    box = next(d for d in ycbv.detections_from_gt(jitter=0.0, distractors=0.0, seed=0)
               if (d["scene_id"], d["image_id"], d["category_id"]) == (49, 1, 6))
    mesh = ycbv.load_mesh(6)
    tracker = mcpose.Tracker(seed=1, samples=150, iterations=10)
    first = tracker.track(frame.depth, frame.K, mesh, 6, [box], stream_id=1)
    assert first.initialised and not first.lost and tracker.tracked_ids == [6]
    gt = frame.gt_T_cam_obj[list(frame.gt_obj_ids).index(6)]
    assert np.linalg.norm(first.T_cam_obj[:3, 3] - gt[:3, 3]) < 0.02

    second = tracker.track(frame.depth, frame.K, mesh, 6, stream_id=2)  # the same frame again: holds
    assert not second.initialised and not second.lost
    assert np.linalg.norm(second.T_cam_obj[:3, 3] - gt[:3, 3]) < 0.02

    empty = np.zeros_like(frame.depth)
    lost = tracker.track(empty, frame.K, mesh, 6, stream_id=3)
    assert lost.lost and not lost.initialised and tracker.tracked_ids == []
    with pytest.raises(ValueError, match="no track yet and no box"):
        tracker.track(frame.depth, frame.K, mesh, 6, stream_id=4)
    again = tracker.track(frame.depth, frame.K, mesh, 6, [box], stream_id=5)
    assert again.initialised and tracker.tracked_ids == [6]
    tracker.reset(6)
    assert tracker.tracked_ids == []


def test_tracker_bad_input_messages(ycbv):
    message = cli_error("track", "--dataset", YCBV, "--video", 49, "--out", "/tmp/never.csv", "--track-samples", 0)
    with pytest.raises(ValueError) as e:
        mcpose.Tracker(track_samples=0)
    assert str(e.value) == message
    with pytest.raises(ValueError, match="lost_fit"):
        mcpose.Tracker(lost_fit=2.0)
    frame = ycbv.load_frame(49, 1)
    box = {"category_id": 3, "score": 1.0, "bbox": (100, 100, 50, 50)}
    with pytest.raises(ValueError, match="not the tracked class 6"):
        mcpose.Tracker().track(frame.depth, frame.K, ycbv.load_mesh(6), 6, [box])
    with pytest.raises(ValueError, match="box 0"):
        mcpose.Tracker().track(frame.depth, frame.K, ycbv.load_mesh(3), 3, [{**box, "bbox": (700, 100, 50, 50)}])
