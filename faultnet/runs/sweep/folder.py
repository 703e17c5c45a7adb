"""A sweep's output folder: its manifest, one catalog file per point, and their states.

The folder holds ``sweep.json`` (the manifest: the sweep's settings and
seed) and one catalog per point, ``part-00007.parquet`` for point 7, each
with the checkpoint folder of an interrupted run next to it while it runs
(see :mod:`faultnet.runs.checkpoint`).  The per-point file names keep the
``part-NNNNN`` form of existing sweep folders, so every folder written so
far is recognised and resumed.

>>> point_file_name(7, n_points=12)
'part-00007.parquet'
>>> is_own_file("part-00007.parquet"), is_own_file("part-00007.parquet.lock")
(True, True)
>>> is_own_file("notes.txt")
False
"""

from __future__ import annotations

import json
import os
import re
import shutil

from faultnet._version import __version__
from faultnet.exceptions import CatalogError, OutputExistsError
from faultnet.io.atomic import atomic_write_json, is_tmp_name
from faultnet.io.lock import LOCK_SUFFIX
from faultnet.io.parquet import read_metadata, utc_now
from faultnet.runs.checkpoint import CHECKPOINT_SUFFIX, checkpoint_dir, checkpoint_status

__all__ = [
    "MANIFEST",
    "SWEEP_LOCK",
    "SWEEP_FORMAT",
    "is_own_file",
    "point_file_name",
    "point_state",
    "prepare_out",
]

MANIFEST = "sweep.json"
#: the lock file of a sweep folder (one sweep writes a folder at a time)
SWEEP_LOCK = "sweep.lock"
SWEEP_FORMAT = "faultnet-sweep"
#: the catalog file of one point (the on-disk form of every sweep folder)
_POINT_FILE_RE = re.compile(r"part-(\d+)\.parquet$")


def point_file_name(index, n_points):
    """File name of point ``index``'s catalog in a sweep of ``n_points`` points."""
    width = max(5, len(str(max(n_points - 1, 0))))
    return f"part-{index:0{width}d}.parquet"


def is_own_file(name):
    """True for the names a sweep writes: manifest, point catalogs, checkpoints, temporaries."""
    if name in (MANIFEST, SWEEP_LOCK) or is_tmp_name(name):
        return True
    for suffix in (CHECKPOINT_SUFFIX, LOCK_SUFFIX):
        if name.endswith(suffix):
            name = name[: -len(suffix)]
            break
    return bool(_POINT_FILE_RE.fullmatch(name))


def _listing(names):
    return f"{', '.join(names[:5])}{' ...' if len(names) > 5 else ''}"


def _check_folder(out, force):
    """Create ``out`` or check that it holds a sweep and nothing else; True if it has a manifest."""
    if os.path.exists(out) and not os.path.isdir(out):
        raise OutputExistsError(f"sweep output {out} exists and is not a folder")
    os.makedirs(out, exist_ok=True)
    names = [n for n in os.listdir(out) if n != SWEEP_LOCK]
    foreign = sorted(n for n in names if not is_own_file(n))
    has_manifest = os.path.isfile(os.path.join(out, MANIFEST))
    if names and not has_manifest and not force:
        raise OutputExistsError(
            f"output folder {out} is not empty and holds no sweep ({_listing(sorted(names))}); "
            "use another folder, or force=True / --force to write into it anyway"
        )
    if foreign and not force:
        raise OutputExistsError(
            f"output folder {out} holds files that are not part of a sweep: "
            f"{_listing(foreign)}; move them away, or pass force=True / --force"
        )
    return has_manifest


def _read_manifest(manifest, force):
    try:
        with open(manifest, encoding="utf-8") as fh:
            return json.load(fh)
    except (OSError, ValueError) as exc:
        if not force:
            raise OutputExistsError(
                f"{manifest} is unreadable ({exc}); pass --force to replace it"
            ) from None
    return None


def prepare_out(cfg, out, force):
    """Create or check the output folder and write its manifest; return the config to run.

    A config without a seed takes the manifest's seed (or fresh entropy).
    Settings that define the points must match the manifest unless ``force``.
    """
    out = os.fspath(out)
    manifest = os.path.join(out, MANIFEST)
    stored = _read_manifest(manifest, force) if _check_folder(out, force) else None
    if stored is not None and cfg.seed is None:
        cfg.seed = stored.get("config", {}).get("seed")
    cfg = cfg.with_seed()
    if stored is not None:
        old = stored.get("config", {})
        new = json.loads(json.dumps(cfg.defining()))
        diffs = [f"{k}: {old.get(k)!r} -> {new[k]!r}" for k in new if old.get(k) != new[k]]
        if diffs and not force:
            raise OutputExistsError(
                f"{out} holds a sweep with other settings ({'; '.join(diffs)}); use a new "
                "output folder, or force=True / --force to recompute the points that changed"
            )
    record = {
        "format": SWEEP_FORMAT,
        "format_version": 1,
        "config": cfg.to_dict(),
        "n_points": len(cfg.points()),
        "created": (stored or {}).get("created", utc_now()),
        "updated": utc_now(),
        "faultnet_version": __version__,
    }
    atomic_write_json(manifest, record)
    return cfg


def _same_point(stored, point):
    return json.loads(json.dumps(stored)) == json.loads(json.dumps(point))


def _remove_checkpoint(path):
    if os.path.isdir(checkpoint_dir(path)):
        shutil.rmtree(checkpoint_dir(path))


def _catalog_state(point, path, force):
    try:
        md = read_metadata(path)
    except CatalogError:
        os.remove(path)  # truncated or corrupt: recompute
        return "todo", "corrupt"
    if not _same_point(md.get("sweep_point"), point):
        if not force:
            raise OutputExistsError(
                f"{path} holds another run than point {point['index']} ({point}); "
                "pass force=True / --force to recompute it"
            )
        os.remove(path)
        _remove_checkpoint(path)
        return "todo", "stale"
    _remove_checkpoint(path)  # killed while cleaning up after merging
    return "done", None


def _checkpoint_state(point, path, force):
    wd = checkpoint_dir(path)
    try:
        run = (checkpoint_status(path) or {}).get("run", {})
    except (OSError, ValueError):
        run = {}
    stored = (run.get("extra") or {}).get("sweep_point")
    if stored is not None and not _same_point(stored, point):
        if not force:
            raise OutputExistsError(
                f"{wd} holds an interrupted run of another point; pass force=True / --force"
            )
        shutil.rmtree(wd)
        return "todo", "stale"
    return "todo", "resume"


def point_state(point, path, force):
    """``("done", None)`` or ``("todo", why)``; removes corrupt or (forced) stale files.

    ``why`` is ``missing``, ``resume`` (an interrupted run), ``corrupt`` or ``stale``.
    """
    if os.path.exists(path):
        return _catalog_state(point, path, force)
    if os.path.isdir(checkpoint_dir(path)):
        return _checkpoint_state(point, path, force)
    return "todo", "missing"
