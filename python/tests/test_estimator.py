"""The Python package against the command line on real frames: same poses for the same frame
and seed, numpy shapes, dtypes and units, and the command line's messages for bad input."""

import json

import numpy as np
import pytest

import mcpose
import mcpose.eval
from conftest import BOP, CLI, YCBV, cli_error, run_cli


def test_dataset_arrays_ycbv(ycbv):
    assert ycbv.format == "ycbv"
    assert (49, 1) in ycbv.frames and ycbv.object_ids == list(range(1, 22))
    f = ycbv.load_frame(49, 1)
    assert f.key == (49, 1)
    assert f.depth.shape == (480, 640) and f.depth.dtype == np.float32
    valid = f.depth[f.depth > 0]
    assert 0.3 < np.median(valid) < 2.0 and valid.max() < 3.0  # metres, not millimetres
    assert not f.depth.flags.writeable and not f.depth.flags.owndata  # a view of the C++ buffer
    assert f.K.shape == (3, 3) and f.K.dtype == np.float64
    assert f.K[0, 0] == pytest.approx(1066.778) and f.K[1, 2] == pytest.approx(241.3109) and f.K[2, 2] == 1
    assert list(f.gt_obj_ids) == [3, 6, 9, 13] and f.gt_obj_ids.dtype == np.int32
    T = f.gt_T_cam_obj
    assert T.shape == (4, 4, 4) and T.dtype == np.float64
    assert np.allclose(T[:, 3], [0, 0, 0, 1]) and np.all((T[:, 2, 3] > 0.5) & (T[:, 2, 3] < 1.2))
    assert np.allclose(T[:, :3, :3] @ T[:, :3, :3].transpose(0, 2, 1), np.eye(3), atol=1e-5)
    rgb = ycbv.load_colour(f)
    assert rgb.shape == (480, 640, 3) and rgb.dtype == np.uint8 and rgb.std() > 10
    m = ycbv.load_mesh(3)
    assert m.vertices.dtype == np.float32 and m.vertices.shape[1] == 3
    assert m.triangles.dtype == np.uint32 and m.triangles.shape == (15728, 3)
    assert 0.05 < np.ptp(m.vertices, axis=0).max() < 0.3  # metres
    assert ycbv.eval_points(3).shape == (2621, 3)
    assert ycbv.load_depths([(49, 1), (49, 2)]).shape == (2, 480, 640)
    assert ycbv.intrinsics([(49, 1), (0, 1)]).shape == (2, 3, 3)


def test_dataset_arrays_bop():
    ds = mcpose.Dataset(BOP, split="test")
    assert ds.format == "bop" and ds.frames
    f = ds.load_frame(*ds.frames[0])
    assert f.depth.dtype == np.float32 and f.depth.shape == (f.height, f.width)
    assert 0.3 < np.median(f.depth[f.depth > 0]) < 2.0
    assert f.gt_T_cam_obj.shape == (len(f.gt_obj_ids), 4, 4)


def test_estimate_equals_cli(ycbv, tmp_path):
    """Default options, frame 0049/000001 with distractor boxes: the same poses to the bit."""
    dets = [d for d in ycbv.detections_from_gt(seed=1) if (d["scene_id"], d["image_id"]) == (49, 1)]
    path = tmp_path / "dets.json"
    mcpose.write_detections(str(path), dets)
    run_cli("estimate", "--dataset", YCBV, "--detections", path, "--out", tmp_path / "r.csv",
            "--out-json", tmp_path / "r.json", "--seed", 5, "--threads", 2, "-q")
    objects = json.loads((tmp_path / "r.json").read_text())["objects"]
    cli = {o["obj_id"]: o for o in objects if o["instance"] == 0}

    est = mcpose.Estimator(seed=5, threads=2)
    frame = ycbv.load_frame(49, 1)
    got = est.estimate_frame(frame, dets, ycbv)
    assert sorted(got) == sorted(cli) == [3, 6, 9, 13]
    for obj_id, r in got.items():  # every instance, as the CLI writes them
        assert [i.instance for i in r.instances] == [o["instance"] for o in objects if o["obj_id"] == obj_id]
        assert [i.T_cam_obj[:3, :3].ravel().tolist() for i in r.instances] == \
            [o["R"] for o in objects if o["obj_id"] == obj_id]
    assert sum(len(r.instances) for r in got.values()) == len(objects)
    for obj_id, r in got.items():
        o = cli[obj_id]
        assert r.T_cam_obj.shape == (4, 4) and r.T_cam_obj.dtype == np.float64
        assert r.T_cam_obj[:3, :3].ravel().tolist() == o["R"], obj_id  # exact, not approximate
        assert (r.T_cam_obj[:3, 3] * 1000.0).tolist() == o["t_mm"], obj_id
        assert r.score == o["best_weight"] and r.iterations == o["iterations"]
        assert r.box["bbox"] == tuple(o["chosen_box"]["bbox"]) and r.box["index"] == o["chosen_box"]["index"]
        assert r.per_iteration.shape == (r.iterations,)
        assert r.per_iteration["mean_weight"].tolist() == [it["mean_weight"] for it in o["per_iteration"]]
        assert r.name == ycbv.object_name(obj_id)

    # The array entry point, from plain numpy arrays, gives the same poses; the seed argument
    # overrides the estimator's.
    meshes = {i: ycbv.load_mesh(i) for i in got}
    again = mcpose.Estimator(seed=0, threads=1).estimate(
        np.array(frame.depth), frame.K, dets, meshes, rgb=np.array(ycbv.load_colour(frame)), seed=5)
    for obj_id, r in got.items():
        assert np.array_equal(again[obj_id].T_cam_obj, r.T_cam_obj), obj_id


def test_one_estimator_shared_by_threads(ycbv):
    """Threads calling one estimator take turns: each gets the poses of a call made alone."""
    import threading
    dets = [d for d in ycbv.detections_from_gt(seed=2) if d["scene_id"] == 49 and d["image_id"] in (1, 2, 3)]
    est = mcpose.Estimator(seed=7, threads=1, samples=150, iterations=8, init_wide=2)
    frames = [ycbv.load_frame(49, i) for i in (1, 2, 3)]
    alone = [est.estimate_frame(f, dets, ycbv, seed=s) for f, s in zip(frames, (7, 8, 9))]
    got = [None] * 3

    def work(k):
        got[k] = est.estimate_frame(frames[k], dets, ycbv, seed=7 + k)  # each its own seed

    threads = [threading.Thread(target=work, args=(k,)) for k in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k in range(3):
        assert sorted(got[k]) == sorted(alone[k])
        for obj_id, r in alone[k].items():
            assert np.array_equal(got[k][obj_id].T_cam_obj, r.T_cam_obj), (k, obj_id)


def test_simd_target_is_per_estimator(ycbv):
    """Two estimators of one process, one capped at the least SIMD target: each keeps its own
    (the cap changes nothing else), and both give the same poses."""
    engine = mcpose.EstimatorOptions().engine
    choices = [f for f in mcpose._mcpose.option_fields() if f["key"] == "engine.simd_target"][0]["choices"]
    assert choices[0] == "best" and engine.simd_target == "best"  # then the targets, best first
    fast = {"seed": 3, "threads": 2, "samples": 150, "iterations": 6, "init_wide": 2}
    capped = mcpose.Estimator(simd_target=choices[-1], **fast)
    best = mcpose.Estimator(**fast)
    assert capped.options["engine"]["simd_target"] == choices[-1]
    assert best.options["engine"]["simd_target"] == "best"
    dets = [d for d in ycbv.detections_from_gt(seed=1) if d["scene_id"] == 49 and d["image_id"] == 1]
    frame = ycbv.load_frame(49, 1)
    a, b = capped.estimate_frame(frame, dets, ycbv), best.estimate_frame(frame, dets, ycbv)
    assert sorted(a) == sorted(b)
    for obj_id, r in a.items():
        assert np.array_equal(b[obj_id].T_cam_obj, r.T_cam_obj), obj_id
    with pytest.raises(ValueError, match="simd-target must be best"):
        mcpose.Estimator(simd_target="AVX9")


def test_options_match_cli_defaults():
    o = mcpose.Estimator().options
    assert o["samples"] == 620 and o["max_iterations"] == 50 and o["seed"] == 0
    assert mcpose.Estimator(appearance=False).options != o
    assert mcpose.Estimator(samples=300, weights=(0.5, 0.2, 0.3), resolve_twins=False).options["samples"] == 300


def test_every_option_field_is_an_attribute():
    defaults = mcpose.Estimator().options
    opts = mcpose.EstimatorOptions()
    assert opts.to_dict() == defaults
    fields = mcpose._mcpose.option_fields()
    assert len(fields) == len({f["key"] for f in fields}) > 50
    for f in fields:
        *groups, name = f["key"].split(".")
        holder = opts
        for g in groups:
            holder = getattr(holder, g)
        assert getattr(holder, name) == f["default"], f["key"]
        setattr(holder, name, f["default"])  # each is settable with a value of its type
    assert mcpose.Estimator(opts).options == defaults


def test_estimator_options_as_attributes_and_keywords():
    opts = mcpose.EstimatorOptions(samples=300, refine={"tukey_m": 0.008})
    opts.engine.backend = "fixed"
    opts.init.rest_share = 0
    o = mcpose.Estimator(opts, threads=1).options  # flags on top of the options
    assert o["samples"] == 300 and o["refine"]["tukey_m"] == 0.008 and o["engine"]["backend"] == "fixed"
    assert o["init"]["rest_share"] == 0 and o["engine"]["threads"] == 1
    assert mcpose.Estimator(refine_tukey=0.008, refine_max_distance=0.03).options["refine"]["max_distance_m"] == 0.03
    with pytest.raises(AttributeError, match="no field 'refine.tukey'"):
        opts.refine.tukey = 0.01
    with pytest.raises(TypeError, match="samples takes a whole number"):
        opts.samples = 1.5
    with pytest.raises(TypeError, match="scalar, fixed, simd, float-simd"):
        opts.engine.backend = "gpu"
    with pytest.raises(TypeError, match="takes True or False"):
        opts.appearance.enabled = "off"
    opts.samples = 0  # bounds: checked by the C++ library, with the command line's words
    with pytest.raises(ValueError, match=r"samples must lie in \[1, 1000000\], got 0"):
        mcpose.Estimator(opts)


@pytest.mark.parametrize("options,flags", [
    ({"samples": 0}, ["--samples", "0"]),
    ({"engine": "gpu"}, ["--engine", "gpu"]),
    ({"weights": (0.5, 0.5)}, ["--weights", "0.5", "0.5"]),
    ({"tau": "high"}, ["--tau", "high"]),
    ({"colour_weight": 1.5}, ["--colour-weight", "1.5"]),
    ({"engine": "scalar", "cluster_culling": True}, ["--engine", "scalar", "--cluster-culling"]),
    ({"no_such_option": 1}, ["--no-such-option", "1"]),
])
def test_bad_options_raise_cli_message(options, flags, tmp_path):
    message = cli_error("estimate", "--dataset", YCBV, "--detections", tmp_path / "d.json",
                        "--out", tmp_path / "r.csv", *flags)
    with pytest.raises(ValueError) as e:
        mcpose.Estimator(**options)
    assert str(e.value) == message


def test_bad_input_raises_cli_message(ycbv, tmp_path):
    # A missing dataset.
    with pytest.raises(FileNotFoundError) as e:
        mcpose.Dataset(tmp_path / "nowhere")
    assert str(e.value) == cli_error("estimate", "--dataset", tmp_path / "nowhere", "--detections",
                                     tmp_path / "d.json", "--out", tmp_path / "r.csv")
    # A detection of a class the dataset lacks, and one whose box lies outside the image.
    good = [d for d in ycbv.detections_from_gt() if (d["scene_id"], d["image_id"]) == (49, 1)]
    for bad in ({**good[0], "category_id": 99}, {**good[0], "bbox": (700.0, 10.0, 20.0, 20.0)}):
        path = tmp_path / "bad.json"
        mcpose.write_detections(str(path), good[1:] + [bad])
        message = cli_error("estimate", "--dataset", YCBV, "--detections", path, "--out", tmp_path / "r.csv")
        assert str(path) in message
        with pytest.raises(ValueError) as e:
            mcpose.Estimator().run(ycbv, good[1:] + [bad], str(path))
        assert str(e.value) == message
        assert not (tmp_path / "r.csv").exists() and not (tmp_path / "r.csv.tmp").exists()
    # Arrays of the wrong shape name the argument.
    frame = ycbv.load_frame(49, 1)
    meshes = {d["category_id"]: ycbv.load_mesh(d["category_id"]) for d in good}
    with pytest.raises(ValueError, match="depth: expected a float32 array of shape"):
        mcpose.Estimator().estimate(frame.depth[0], frame.K, good, meshes)
    with pytest.raises(ValueError, match="K: expected a 3x3 array"):
        mcpose.Estimator().estimate(frame.depth, frame.K[:2], good, meshes)
    with pytest.raises(ValueError, match="no mesh for category_id"):
        mcpose.Estimator().estimate(frame.depth, frame.K, good, {})
    # A box is checked by the one rule the files' boxes meet: a score above 1 is refused here too.
    with pytest.raises(ValueError, match=r"score must be a finite number in \[0, 1\], got 3"):
        mcpose.Estimator().estimate(frame.depth, frame.K, [{**good[0], "score": 3.0}] + good[1:], meshes)
    with pytest.raises(ValueError, match="rgb: expected a uint8 array"):
        mcpose.Estimator().estimate(frame.depth, frame.K, good, meshes, rgb=np.zeros((10, 10, 3), np.uint8))
    # The arrays are checked as the readers check the files: the same limits, the same words.
    depth = np.array(frame.depth)
    bad_arrays = []
    raw = (depth * 1e4).astype(np.uint16)
    bad_arrays.append(((raw, frame.K), "depth: expected float32 or float64 metres, got dtype uint16; a depth image "
                                       "in sensor units must be scaled to metres first"))
    for value in (np.nan, np.inf, -0.5, 1e30):
        d = depth.copy()
        d[240, 320] = value
        bad_arrays.append(((d, frame.K), "depth: pixel \\(320, 240\\) = "))
    bad_arrays.append(((depth.astype(object), frame.K), "depth: expected float32 or float64 metres, got dtype object"))
    for (i, j), value, message in (((0, 1), 5.0, "not a pinhole matrix"), ((0, 0), 1e12, "fx = 1e\\+12 px is outside"),
                                   ((1, 1), 1e-6, "fy = 1e-06 px is outside"), ((0, 2), 1e9, "principal point"),
                                   ((0, 0), np.nan, "is not finite")):
        K = np.array(frame.K)
        K[i, j] = value
        bad_arrays.append(((depth, K), "K: .*" + message))
    for (d, K), message in bad_arrays:
        with pytest.raises(ValueError, match=message):
            mcpose.Estimator().estimate(d, K, good, meshes)
    for bad, message in (({**good[0], "score": 3.0}, "score must be a finite number in \\[0, 1\\], got 3"),
                         ({**good[0], "bbox": (10.0, 10.0, 1e300, 20.0)}, "has a value outside")):
        with pytest.raises(ValueError, match=message):
            mcpose.Estimator().estimate(frame.depth, frame.K, good[1:] + [bad], meshes)
    with pytest.raises(ValueError, match="more than 10000 boxes in one image"):
        mcpose.Estimator().estimate(frame.depth, frame.K, good * (10001 // len(good) + 1), meshes)
    with pytest.raises(ValueError, match="rgb: expected a uint8 array .* got dtype float64"):
        mcpose.Estimator().estimate(frame.depth, frame.K, good, meshes,
                                    rgb=np.full(frame.depth.shape + (3,), np.nan))
    tracker = mcpose.Tracker()
    with pytest.raises(ValueError, match="score must be a finite number"):
        tracker.track_frame(frame, [{**good[0], "score": 3.0}], ycbv)


def test_eval_metrics(ycbv):
    pts = ycbv.eval_points(13)
    T = ycbv.load_frame(49, 1).gt_T_cam_obj
    assert np.all(mcpose.eval.add(T, T, pts) == 0)
    moved = T.copy()
    moved[:, 0, 3] += 0.01
    assert np.allclose(mcpose.eval.add(moved, T, pts), 0.01)
    assert np.all(mcpose.eval.add_s(moved, T, pts) <= mcpose.eval.add(moved, T, pts) + 1e-12)
    assert isinstance(mcpose.eval.add(T[0], T[0], pts), float)
    assert mcpose.eval.auc([0.0, 0.0]) == pytest.approx(1.0)
    assert mcpose.eval.auc([0.05, np.inf]) == pytest.approx(0.25, abs=0.01)
    assert 13 in mcpose.eval.YCBV_SYMMETRIC_IDS
    with pytest.raises(ValueError, match="points: expected an"):
        mcpose.eval.add(T, T, pts[:, :2])


def test_cli_path_exists():
    import os
    assert os.access(CLI, os.X_OK), CLI


def test_bop19_metrics_equal_the_cli(ycbv, cli_run, run_dir):
    """mcpose.eval.bop19 on the CLI's rows gives the AR `mcpose eval --metrics bop19` prints; the
    MSSD of a pose shifted 1 cm is 1 cm, and a continuous symmetry's turn costs nothing."""
    import json
    info = BOP / "models" / "models_info.json"
    out = run_dir / "bop19.json"
    run_cli("eval", "--dataset", YCBV, "--results", cli_run, "--metrics", "bop19", "--models-info", info,
            "--json", out)
    cli = json.loads(out.read_text())["bop19"]
    rows = []
    import csv
    with open(cli_run, newline="") as f:
        for r in list(csv.reader(f))[1:]:
            rows.append((int(r[0]), int(r[1]), int(r[2]), float(r[3]), [float(v) for v in r[4].split()],
                         [float(v) / 1000 for v in r[5].split()], float(r[6])))
    got = mcpose.eval.bop19(ycbv, rows, info)
    assert got["overall"]["ar"] == pytest.approx(cli["overall"]["ar"], abs=1e-9)
    assert got["overall"]["targets"] == cli["overall"]["targets"]
    assert [o["obj_id"] for o in got["per_object"]] == [o["obj_id"] for o in cli["per_object"]]
    for a, b in zip(got["per_object"], cli["per_object"]):
        assert a["ar_mssd"] == pytest.approx(b["ar_mssd"], abs=1e-9)

    diameter, sym = mcpose.eval.bop19_symmetries(info, 13)  # the bowl: a continuous symmetry
    assert 0.1 < diameter < 0.3 and sym.shape[0] > 300 and np.allclose(sym[0], np.eye(4))
    pts = ycbv.eval_points(13)
    T = np.eye(4)
    T[:3, 3] = (0, 0, 1)
    moved = T.copy()
    moved[2, 3] += 0.01
    K = np.array([[1066.8, 0, 313.0], [0, 1067.5, 241.3], [0, 0, 1]])
    mssd, mspd = mcpose.eval.mssd_mspd(moved, T, pts, sym, K)
    assert mssd == pytest.approx(0.01, abs=1e-6) and mspd > 0
    turned = T @ sym[100]
    assert mcpose.eval.mssd_mspd(turned, T, pts, sym, K)[0] < 1e-6
