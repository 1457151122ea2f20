"""mcpose: 6-DoF object pose estimation by Monte-Carlo sampling on RGB-D frames.

Units and conventions are those of the C++ library: depth and translations in metres, poses
``T_cam_obj`` as 4x4 float64 matrices mapping model to camera coordinates (``X_cam = R X + t``,
OpenCV axes), intrinsics ``K`` as 3x3 float64 in pixels with pixel centres at integer
coordinates. Detections are BOP dicts ``{"scene_id", "image_id", "category_id", "score",
"bbox": (x, y, w, h), "time"}`` (pixels). Errors are the command line's one-line messages:
``ValueError`` for bad input or options, ``FileNotFoundError`` for a missing file, ``OSError``
for a file that cannot be decoded.

    import mcpose
    ds = mcpose.Dataset("../shared/data/ycbv")
    dets = ds.detections_from_gt(jitter=0.1, distractors=0.3, seed=0)
    frame = ds.load_frame(49, 1)
    results = mcpose.Estimator(seed=0).estimate_frame(frame, dets, ds)
    for obj_id, r in results.items():
        print(obj_id, r.score, r.T_cam_obj[:3, 3])

    tracker = mcpose.Tracker(seed=0)          # a video, each frame from the last one's samples
    for image_id in range(1, 11):
        steps = tracker.track_frame(ds.load_frame(49, image_id), dets, ds)
"""

from dataclasses import dataclass, field

import numpy as np

from . import _mcpose
from ._mcpose import Frame, Mesh, __version__, read_detections, write_detections  # noqa: F401

__all__ = ["Dataset", "Estimator", "EstimatorOptions", "ObjectResult", "Tracker", "TrackStep", "Frame", "Mesh", "read_detections",
           "write_detections", "PER_ITERATION_DTYPE"]

#: Fields of ``ObjectResult.per_iteration``: each iteration's mean and best weight (unitless,
#: [0, 1]), the time spent rendering and counting inliers, and the whole iteration (milliseconds).
PER_ITERATION_DTYPE = np.dtype([("mean_weight", "f8"), ("best_weight", "f8"), ("score_ms", "f8"),
                                ("iteration_ms", "f8")])


class Dataset(_mcpose.Dataset):
    """A dataset in the YCB-Video native or the BOP layout (detected), ids as BOP's.

    ``Dataset(path, split="test", models="")``: ``split`` is the BOP split folder; ``models``
    a models folder to read meshes from instead of the dataset's own.

    Attributes and methods:
      - ``frames``: list of ``(scene_id, image_id)`` with ground truth, sorted.
      - ``object_ids``, ``object_name(obj_id)``, ``format`` ("ycbv" or "bop"), ``root``.
      - ``load_frame(scene_id, image_id)`` -> ``Frame`` with ``depth`` (H, W) float32 metres
        (0 = no measurement; a read-only view, no copy), ``K`` (3, 3) float64 pixels,
        ``width``, ``height``, ``gt_obj_ids`` (N,) int32 and ``gt_T_cam_obj`` (N, 4, 4)
        float64 metres.
      - ``load_colour(frame)`` -> (H, W, 3) uint8 RGB (a read-only view, no copy).
      - ``load_mesh(obj_id)`` -> ``Mesh`` with ``vertices`` (V, 3) float32 metres and
        ``triangles`` (T, 3) uint32.
      - ``eval_points(obj_id)`` -> (P, 3) float32 metres, the points ADD and ADD-S use.
      - ``detections_from_gt(jitter=0.1, distractors=0.3, seed=0)`` -> detector-like BOP
        detections from the ground truth, as ``mcpose detections-from-gt``.
    """

    def __init__(self, path, split="test", models=""):
        super().__init__(str(path), split, str(models))

    def load_depths(self, keys):
        """Depth of several frames: (B, H, W) float32 metres for ``keys`` [(scene_id, image_id)]."""
        return np.stack([self.load_frame(s, i).depth for s, i in keys])

    def intrinsics(self, keys):
        """Intrinsics of several frames: (B, 3, 3) float64 pixels."""
        return np.stack([self.load_frame(s, i).K for s, i in keys])


@dataclass
class ObjectResult:
    """The pose of one object instance in one image.

    ``T_cam_obj``: (4, 4) float64, metres. ``score``: the best weight, [0, 1] (the BOP score).
    ``iterations``: filter iterations run. ``box``: the chosen detection (BOP dict plus its
    ``index`` among the boxes its filter sampled). ``per_iteration``: (iterations,) array of
    ``PER_ITERATION_DTYPE``. ``time_s``: wall time of this object, seconds. ``instance``: 0 for
    the class's first instance (the filter over all its boxes), k > 0 for a further one
    (``max_instances``). ``instances``: on a class's first instance, every instance of the class
    in the image, itself first; empty on the others.
    """
    obj_id: int
    name: str
    T_cam_obj: np.ndarray
    score: float
    iterations: int
    box: dict
    per_iteration: np.ndarray
    time_s: float
    instance: int = 0
    instances: list = field(default_factory=list)


def _result(d):
    per = np.ascontiguousarray(d["per_iteration"]).view(PER_ITERATION_DTYPE).reshape(-1)
    r = ObjectResult(obj_id=d["obj_id"], name=d["name"], T_cam_obj=d["T_cam_obj"], score=d["score"],
                     iterations=d["iterations"], box=d["box"], per_iteration=per, time_s=d["time_s"],
                     instance=d["instance"])
    if "instances" in d:
        r.instances = [r] + [_result(i) for i in d["instances"][1:]]
    return r


def _option_args(options):
    """Keyword options as the command line's flags: samples=300 -> --samples 300."""
    args = []
    for key, value in options.items():
        name = key.replace("_", "-")
        if isinstance(value, bool):
            if _mcpose.is_switch(name):
                args.append(f"--{name}" if value else f"--no-{name}")
            else:
                args += [f"--{name}", "on" if value else "off"]
        elif isinstance(value, (list, tuple, np.ndarray)):
            args.append(f"--{name}")
            args += [repr(float(v)) if isinstance(v, float) else str(v) for v in value]
        else:
            args += [f"--{name}", repr(value) if isinstance(value, float) else str(value)]
    return args


_FIELDS = {f["key"]: f for f in _mcpose.option_fields()}


class _OptionGroup:
    """The fields of one group of ``EstimatorOptions`` (``init``, ``weight``, ``refine``, ...)."""

    def __init__(self, root, prefix):
        object.__setattr__(self, "_root", root)
        object.__setattr__(self, "_prefix", prefix)

    def __getattr__(self, name):
        return self._root._get(self._prefix + name)

    def __setattr__(self, name, value):
        self._root._set(self._prefix + name, value)

    def __dir__(self):
        return [k[len(self._prefix):] for k in _FIELDS if k.startswith(self._prefix)]

    def __repr__(self):
        return "{" + ", ".join(f"{k}={getattr(self, k)!r}" for k in self.__dir__()) + "}"


class EstimatorOptions:
    """Every option of the estimator as an attribute, grouped as ``mcpose::EstimatorOptions``
    (``include/mcpose/options.h``; the table of every field, its default and values:
    ``docs/options.md``)::

        opts = mcpose.EstimatorOptions(samples=300, refine={"tukey_m": 0.008})
        opts.refine.tukey_m = 0.006
        opts.engine.backend = "scalar"
        est = mcpose.Estimator(opts, threads=2)   # keywords: flags applied on top

    Setting a field that does not exist raises ``AttributeError``, a value of the wrong type
    ``TypeError``; bounds are checked when an ``Estimator`` is made (``ValueError`` with the
    command line's message). ``to_json()`` gives the options' JSON, as ``--out-json`` writes it.
    """

    def __init__(self, **fields):
        object.__setattr__(self, "_values", {k: f["default"] for k, f in _FIELDS.items()})
        for name, value in fields.items():
            if isinstance(value, dict):
                for k, v in value.items():
                    self._set(f"{name}.{k}", v)
            else:
                self._set(name, value)

    def _get(self, key):
        if key in self._values:
            return self._values[key]
        if any(k.startswith(key + ".") for k in self._values):
            return _OptionGroup(self, key + ".")
        raise AttributeError(f"EstimatorOptions has no field '{key}' (docs/options.md lists them)")

    def _set(self, key, value):
        f = _FIELDS.get(key)
        if f is None:
            raise AttributeError(f"EstimatorOptions has no field '{key}' (docs/options.md lists them)")
        kind = f["type"]
        if kind == "bool":
            if not isinstance(value, (bool, np.bool_)):
                raise TypeError(f"{key} takes True or False, got {value!r}")
            value = bool(value)
        elif kind in ("int", "seed"):
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
                raise TypeError(f"{key} takes a whole number, got {value!r}")
            value = int(value)
        elif kind == "float":
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
                raise TypeError(f"{key} takes a number, got {value!r}")
            value = float(value)
        elif kind == "enum" and value not in f["choices"]:
            raise TypeError(f"{key} takes one of {', '.join(f['choices'])}, got {value!r}")
        self._values[key] = value

    def __getattr__(self, name):
        return self._get(name)

    def __setattr__(self, name, value):
        self._set(name, value)

    def __dir__(self):
        return sorted({k.split(".")[0] for k in _FIELDS})

    def to_dict(self):
        """The options as nested dicts, the groups as dicts."""
        out = {}
        for key, value in self._values.items():
            *groups, name = key.split(".")
            d = out
            for g in groups:
                d = d.setdefault(g, {})
            d[name] = value
        return out

    def to_json(self):
        """The options' JSON, as ``mcpose estimate --out-json`` writes them."""
        import json
        return json.dumps(self.to_dict())

    def __repr__(self):
        return f"EstimatorOptions({self.to_dict()!r})"


class Estimator:
    """The Monte-Carlo pose estimator with the options of ``mcpose estimate``.

    ``Estimator(options=None, **flags)``: ``options`` an ``EstimatorOptions`` (default: the
    defaults); each keyword is then a flag of ``mcpose estimate`` with ``-`` written ``_``
    (``samples=620``, ``max_grid_pixels=0``, ``engine="scalar"``, ``weights=(a, b, c)``,
    ``appearance=False`` or ``"off"``, ``resolve_twins=False``, ``refine_tukey=0.008``), with the
    same defaults, and parsed and checked by the same code: a bad option raises ``ValueError``
    with the message the command line prints. The GIL is released while the engine runs; one
    estimator serves one call at a time (calls from other threads wait their turn), so threads
    that estimate at once each need their own.
    """

    def __init__(self, options=None, **flags):
        if options is not None and not isinstance(options, EstimatorOptions):
            raise TypeError(f"options must be an EstimatorOptions, got {type(options).__name__}")
        self._impl = _mcpose.Estimator(_option_args(flags), options.to_json() if options is not None else "")

    @property
    def options(self):
        """The options in effect (every field, defaults included), as ``--out-json`` writes them."""
        import json
        return json.loads(self._impl.options_json)

    def estimate(self, depth, K, detections, meshes, rgb=None, seed=None):
        """Poses of the object classes of one image from their boxes.

        depth: (H, W) float32, metres, 0 = no measurement. K: (3, 3) float64, pixels.
        detections: BOP dicts of one image (``scene_id`` and ``image_id``, when given, select
        the random streams, as in ``mcpose estimate``). meshes: ``{obj_id: Mesh}``, a mesh for
        every class of the detections. rgb: optional (H, W, 3) uint8 colour registered to the
        depth. seed: overrides the estimator's seed.
        Returns ``{obj_id: ObjectResult}``: each class's first instance, its ``instances``
        listing every instance the boxes show (``max_instances``).
        """
        out = self._impl.estimate(depth, K, list(detections), dict(meshes), rgb, seed)
        return {k: _result(v) for k, v in out.items()}

    def estimate_frame(self, frame, detections, dataset, seed=None):
        """``estimate`` on a dataset's frame: its detections among ``detections``, the
        dataset's meshes and (when a mesh has colour) the frame's colour image. Returns
        ``{obj_id: ObjectResult}``; the poses equal ``mcpose estimate``'s for the same seed."""
        out = self._impl.estimate_frame(frame, list(detections), dataset, seed)
        return {k: _result(v) for k, v in out.items()}

    def run(self, dataset, detections, source="detections"):
        """Checks and estimates every image of ``detections`` as ``mcpose estimate`` does; the
        BOP results rows as tuples ``(scene_id, im_id, obj_id, score, R (9, row-major), t (3,
        metres), time_s)``."""
        return self._impl.run(dataset, list(detections), source)

    def fingerprint(self, detections, dataset):
        """What decides the rows of a run on ``dataset``: the options but the thread count, the
        detections, the dataset's folder, split and models folder, and mcpose's version. A
        results journal is resumed only under the same fingerprint."""
        return self._impl.fingerprint(list(detections), dataset)


@dataclass
class TrackStep:
    """One object in one frame of a track.

    ``T_cam_obj``: (4, 4) float64, metres. ``weight``: the frame's best weight, [0, 1].
    ``fit``: the share of the answer's visible silhouette that the depth confirms; ``visible``:
    the share of its silhouette not hidden behind nearer surfaces (the track is lost below
    ``lost_fit`` / ``lost_visible``). ``initialised``: estimated from this frame's boxes (first
    frame or restart). ``lost``: the track was lost in this frame (then restarted if the frame
    had boxes). ``iterations``: filter iterations run. ``box``: the box the answer was found in
    (BOP dict; ``None`` where a lost track had none). ``time_s``: wall time, seconds.
    """
    obj_id: int
    T_cam_obj: np.ndarray
    weight: float
    fit: float
    visible: float
    initialised: bool
    lost: bool
    iterations: int
    box: dict
    time_s: float


class Tracker:
    """The tracker of ``mcpose track``: each frame starts from the last one's samples.

    ``Tracker(**options)``: each keyword is a flag of ``mcpose track`` with ``-`` written ``_``:
    the tracker's own (``track_samples=300``, ``track_iterations=3``, ``stop_weight``,
    ``motion_sigma_t`` (metres), ``motion_sigma_r`` (radians), ``box_margin``,
    ``track_refine_iterations``, ``lost_fit``, ``lost_visible``) and the estimator's, which
    first frames and restarts use (``seed``, ``samples``, ``threads``, ...), with the same
    defaults and checks: a bad option raises ``ValueError`` with the command line's message.
    Same seed, same poses, at any thread count; ``track_frame`` gives ``mcpose track``'s poses.
    """

    def __init__(self, **options):
        self._impl = _mcpose.Tracker(_option_args(options))

    @property
    def options(self):
        """The options in effect (defaults included), as ``mcpose track --out-json`` writes them."""
        import json
        return json.loads(self._impl.options_json)

    @property
    def tracked_ids(self):
        """The classes with a live track (their next frame needs no box), increasing."""
        return self._impl.tracked_ids

    def reset(self, obj_id):
        """Forgets the track of ``obj_id``: its next frame is estimated from its boxes."""
        self._impl.reset(obj_id)

    def track(self, depth, K, mesh, obj_id, boxes=(), rgb=None, stream_id=0):
        """The pose of class ``obj_id`` in the next frame of its track.

        depth: (H, W) float32, metres, 0 = no measurement. K: (3, 3) float64, pixels. mesh: the
        class's ``Mesh``. boxes: this frame's detections of the class (BOP dicts); they start
        the track and restart a lost one, and may be empty while it holds. rgb: optional
        (H, W, 3) uint8 colour. stream_id: selects the frame's random streams (vary it by frame).
        Returns a ``TrackStep``.
        """
        return TrackStep(**self._impl.track(depth, K, mesh, obj_id, list(boxes), rgb, stream_id))

    def track_frame(self, frame, detections, dataset):
        """The next frame of a video as ``mcpose track`` runs it: every class with a live track
        or with boxes among ``detections`` (those of other frames are ignored), with the
        dataset's meshes and, where a mesh has colour, the frame's colour. Returns
        ``{obj_id: TrackStep}``."""
        out = self._impl.track_frame(frame, list(detections), dataset)
        return {k: TrackStep(**v) for k, v in out.items()}

