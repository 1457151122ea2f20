"""Pose accuracy on numpy poses: the YCB-Video protocol's metrics and BOP19's (the C++ library's
code, as ``mcpose eval`` runs it).

Poses are (B, 4, 4) or (4, 4) float64 model-to-camera matrices, metres; ``points`` the model's
(P, 3) points in metres (``Dataset.eval_points``). Errors come back in metres (MSPD in pixels).
"""

import numpy as np

from . import _mcpose

__all__ = ["add", "add_s", "add_or_add_s", "auc", "YCBV_SYMMETRIC_IDS", "bop19_symmetries", "mssd_mspd", "bop19"]

#: obj_ids scored with ADD-S in ADD(-S): 024_bowl, 036_wood_block, 051_large_clamp,
#: 052_extra_large_clamp, 061_foam_brick.
YCBV_SYMMETRIC_IDS = frozenset(_mcpose.ycbv_symmetric_ids())


def _batch(T_est, T_gt, points, symmetric):
    T_est = np.asarray(T_est, dtype=np.float64)
    T_gt = np.asarray(T_gt, dtype=np.float64)
    single = T_est.ndim == 2
    if single:
        T_est, T_gt = T_est[None], T_gt[None]
    err = _mcpose.add(np.asarray(points, dtype=np.float32), T_est, T_gt, symmetric)
    return float(err[0]) if single else err


def add(T_est, T_gt, points):
    """ADD: mean distance of corresponding model points under the two poses. (B,) float64 metres
    (a float for one pose)."""
    return _batch(T_est, T_gt, points, False)


def add_s(T_est, T_gt, points):
    """ADD-S: mean distance from each ground-truth-posed point to the closest estimate-posed
    point. (B,) float64 metres (a float for one pose)."""
    return _batch(T_est, T_gt, points, True)


def add_or_add_s(T_est, T_gt, points, obj_id):
    """ADD(-S): ADD-S for the YCB-Video symmetric objects, ADD for the others."""
    return _batch(T_est, T_gt, points, obj_id in YCBV_SYMMETRIC_IDS)


def auc(errors_m, max_m=0.10):
    """Area under the accuracy-threshold curve up to ``max_m`` metres over ``errors_m`` (1-D,
    metres; inf for a missing result), divided by ``max_m``: in [0, 1]."""
    return _mcpose.auc([float(e) for e in np.ravel(errors_m)], float(max_m))


def bop19_symmetries(models_info, obj_id):
    """An object's diameter (metres) and its symmetry transformations as BOP discretises them,
    (S, 4, 4) float64 metres, the identity first, from a BOP ``models_info.json``."""
    return _mcpose.bop19_symmetries(str(models_info), int(obj_id))


def mssd_mspd(T_est, T_gt, points, symmetries, K):
    """BOP19's MSSD (metres) and MSPD (pixels) of one pose: the largest distance of a model point
    posed by ``T_est`` from the same point posed by ``T_gt`` times a symmetry, least over the
    symmetries (``bop19_symmetries``); MSPD the same projected by ``K`` (3, 3)."""
    return _mcpose.bop19_pose_errors(np.asarray(points, dtype=np.float32), np.asarray(T_est, dtype=np.float64),
                                     np.asarray(T_gt, dtype=np.float64), np.asarray(symmetries, dtype=np.float64),
                                     np.asarray(K, dtype=np.float64))


def bop19(dataset, rows, models_info, targets=None):
    """BOP19 average recall of results ``rows`` (the tuples ``Estimator.run`` returns) on
    ``dataset``, as ``mcpose eval --metrics bop19`` computes it: ``{"overall": {...},
    "per_object": [...]}``, each with ``ar``, ``ar_vsd``, ``ar_mssd``, ``ar_mspd`` (0-1) and
    ``targets``. ``models_info``: a BOP models_info.json of the objects; ``targets``: a
    test_targets_bop19.json, or None for every instance at least 10 % visible."""
    return _mcpose.evaluate_bop19(dataset, list(rows), str(models_info), "" if targets is None else str(targets))
