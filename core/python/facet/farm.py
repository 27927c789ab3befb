"""facet-farm: distributed rendering of Facet scenes on Dask.

A still is cut into tiles (``--tile-size``) and sample chunks (``--sample-chunk``); each piece is
one Dask task that renders its region and sample range with a ``facet.RenderSession`` and
returns the ``facet.RenderPart`` (fixed-point film sums). The parts merge into exactly the image
``facet render`` gives for the same scene and seed (film.h: integer sums, fixed tile grid), so
neither the split, the number of workers nor the order in which tasks finish or are retried
changes a bit of the image. An animation (several scene files) is one task per frame, or per
tile of each frame when there are fewer frames than task slots. An adaptive render (the scene's
render.adaptive_threshold > 0) is split by tiles on the sessions' 16-pixel tile grid only: each
task renders its region's whole sample range and returns the region's image, which is exactly
the whole render's pixels there (render.h), so the pasted tiles are `facet render`'s image.

Conventions:
  - Geometry travels with the tasks: the client reads each scene file, strips its mesh arrays
    out of the JSON text (they travel as numpy arrays) and packs mesh files' bytes (of shapes
    and of prototypes), and submits that ScenePayload once per job as a task returning it; Dask
    copies it to each worker that needs it (once per worker, not per task; recomputed if lost)
    and the worker builds the Scene once and caches it (_worker_scene).
  - Textures, environment maps and glTF assets do not travel: the client makes their file
    names absolute (resolved against the scene file's directory, as `facet render` would), so
    each worker reads them itself from a file system shared at the same path (NFS, or the same
    files copied to the same place on every machine). Their texels never pass through the
    scheduler. (Mesh files that travel keep relative names, resolved against the worker's
    temporary directory, so every worker builds a description of the same fingerprint.)
  - Errors: everything the user can get wrong raises FarmError with one message (the scene
    file and JSON pointer for a bad scene, the address for an unreachable scheduler); the CLI
    prints it once, without a traceback, and exits 1. Ctrl-C cancels every task and shuts the
    local cluster down (exit 130).
  - Without a scheduler address a LocalCluster runs on this machine: by default one worker in
    this process (in-process transport; only the scheduler's HTTP endpoint listens, on
    127.0.0.1) with `cores` task threads, each task rendering on 1 thread; --workers N starts
    N worker processes listening on 127.0.0.1 only (measured on the 2-core development
    machine; see docs/farm.md and docs/performance.md).
"""

from __future__ import annotations

import argparse
import collections
import dataclasses
import hashlib
import json
import logging
import os
import pathlib
import re
import shutil
import signal
import sys
import tempfile
import threading
import time
import warnings
from typing import Callable, Sequence

import numpy as np

import facet

__all__ = ["FarmError", "ScenePayload", "Job", "load_payload", "plan_still", "run_jobs",
           "local_cluster", "connect", "render_files", "main"]

class FarmError(RuntimeError):
    """A user-facing error of the farm (bad scene, unreachable scheduler, failed task)."""


# ---------------------------------------------------------------------------------------------
# The scene as it travels


@dataclasses.dataclass
class ScenePayload:
    """One scene: JSON text without mesh arrays (texture, environment map and glTF file names
    made absolute: workers read those files themselves), the arrays, mesh files' bytes."""

    name: str                 # the scene file (error messages, part names)
    json: str                 # description JSON; meshes from arrays hold a 1-triangle stand-in
    meshes: list              # [(prototype | None, shape index, positions, indices, normals | None)]
    files: dict               # {file name in the payload: bytes} for mesh shapes with a file
    fingerprint: int          # of the original description: checked after rebuilding it
    width: int
    height: int
    spp: int
    seed: int
    base_dir: str = "."       # absolute: the scene file's directory (error messages)
    sent_fingerprint: int | None = None  # of the description as the workers rebuild it
    digest: str = ""          # of the JSON (absolute asset paths) and the mesh files' bytes
    adaptive: bool = False    # render.adaptive_threshold > 0: split by tiles only

    @property
    def key(self) -> str:
        """The workers' cache key: the description's fingerprint names files by their relative
        names only, so the same scene text in two directories (other textures) differs here."""
        return f"{self.fingerprint:016x}-{self.digest}"

    def nbytes(self) -> int:
        return (len(self.json.encode()) + sum(len(b) for b in self.files.values()) +
                sum(a.nbytes for m in self.meshes for a in m[2:] if a is not None))


_STANDIN = (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32),
            np.array([[0, 1, 2]], dtype=np.int32))


def _shape_lists(desc):
    """{None: the scene's shapes, prototype name: its shapes} (live lists: edits stick)."""
    lists = {None: desc.shapes}
    lists.update(desc.prototypes)
    return lists


def _description(payload: ScenePayload, base_dir: str):
    """The payload's description with its mesh arrays put back; relative names (the mesh files
    that travelled) resolve against base_dir, where the worker wrote them."""
    desc = facet.parse_scene_description(payload.json, payload.name, base_dir)
    lists = _shape_lists(desc)
    for proto, index, positions, indices, normals in payload.meshes:
        lists[proto][index].mesh = facet.MeshData(positions, indices, normals)
    return desc


def _absolute_asset_paths(text: str, base: pathlib.Path) -> str:
    """The description JSON with every file the workers read from the shared file system made
    absolute against `base`: image textures (any object's "texture" string: materials, normal
    maps, emission), environment maps (a light's "file") and glTF files (a gltf shape's "file",
    whose buffers and images then resolve next to it). Mesh shapes' files travel: untouched."""
    data = json.loads(text)

    def absolute(name):
        return name if os.path.isabs(name) else str(base / name)

    def textures(node):
        if isinstance(node, dict):
            for k, v in node.items():
                if k == "texture" and isinstance(v, str):
                    node[k] = absolute(v)
                else:
                    textures(v)
        elif isinstance(node, list):
            for v in node:
                textures(v)

    textures(data.get("materials", {}))
    textures(data.get("shapes", []))  # per-shape material overrides, if any
    textures(data.get("prototypes", {}))
    for light in data.get("lights", []):
        if isinstance(light.get("file"), str):
            light["file"] = absolute(light["file"])
    shape_lists = [data.get("shapes", [])] + list(data.get("prototypes", {}).values())
    for shapes in shape_lists:
        for shape in shapes:
            if shape.get("type") != "mesh" and isinstance(shape.get("file"), str):
                shape["file"] = absolute(shape["file"])
    return json.dumps(data, separators=(",", ":"))


def load_payload(path: str, spp: int | None = None, seed: int | None = None,
                 validate: bool = True, adaptive_threshold: float | None = None,
                 adaptive_min_samples: int | None = None) -> ScenePayload:
    """Reads a scene file into a payload; with `validate`, builds it once here so that a bad
    scene is one FarmError naming the file and JSON pointer before any task is sent. The
    adaptive options (None: the scene's) are written into the scene's render settings, which
    the workers' sessions read."""
    path = str(path)
    try:
        desc = facet.read_scene_description(path)
    except (ValueError, RuntimeError, OSError) as e:
        raise FarmError(str(e)) from None
    if adaptive_threshold is not None:
        if not (0.0 <= adaptive_threshold <= 1.0):  # also NaN
            raise FarmError(f"--adaptive-threshold: must be in [0, 1] (0 = off), got "
                            f"{adaptive_threshold}")
        desc.render.adaptive_threshold = float(adaptive_threshold)
    if adaptive_min_samples is not None:
        if adaptive_min_samples < 0:
            raise FarmError(f"--adaptive-min-samples: must be >= 0 (0 = automatic), got "
                            f"{adaptive_min_samples}")
        desc.render.adaptive_min_samples = int(adaptive_min_samples)
    if validate:
        try:
            scene = facet.build_scene(desc, name=path)
        except (ValueError, RuntimeError, OSError) as e:
            raise FarmError(str(e)) from None
    fp = desc.fingerprint()
    settings = desc.render
    base = pathlib.Path(desc.base_dir or ".").absolute()
    meshes, files, names = [], {}, {}
    for proto, shapes in _shape_lists(desc).items():
        where = "/shapes" if proto is None else f"/prototypes/{proto}"
        for i, shape in enumerate(shapes):
            if str(shape.kind).rsplit(".", 1)[-1] != "mesh":
                continue
            if shape.file:
                source = pathlib.Path(shape.file)
                if not source.is_absolute():
                    source = base / source
                try:
                    data = source.read_bytes()
                except OSError as e:
                    raise FarmError(f"{path}: {where}/{i}/file: cannot read {source}: "
                                    f"{e.strerror}")
                # One copy per distinct file: a prototype's mesh used by many shapes, or the
                # same file named twice, travels once.
                name = names.get(str(source))
                if name is None:
                    name = names[str(source)] = f"mesh{len(files)}{source.suffix}"
                    files[name] = data
                shape.file = name
                continue
            mesh = shape.mesh
            normals = mesh.normals
            meshes.append((proto, i, np.array(mesh.positions), np.array(mesh.indices),
                           None if normals is None else np.array(normals)))
            shape.mesh = facet.MeshData(*_STANDIN)
    payload = ScenePayload(name=path, json=_absolute_asset_paths(desc.to_json(), base),
                           meshes=meshes, files=files, fingerprint=fp,
                           width=desc.camera.width, height=desc.camera.height,
                           spp=int(spp if spp is not None else settings.spp),
                           seed=int(seed if seed is not None else settings.seed),
                           base_dir=str(base), adaptive=settings.adaptive_threshold > 0.0)
    h = hashlib.sha1(payload.json.encode())
    for name in sorted(files):
        h.update(name.encode())
        h.update(files[name])
    payload.digest = h.hexdigest()[:16]
    if not files:  # checked by the workers: the description arrived as it left
        payload.sent_fingerprint = _description(payload, ".").fingerprint()
    if validate:
        _cache_scene(payload.key, scene)  # in-process workers use it as it is
    return payload


# ---------------------------------------------------------------------------------------------
# Worker side: the scene cache and the task

_cache_lock = threading.Lock()
_scenes: "collections.OrderedDict[str, object]" = collections.OrderedDict()
_CACHED_SCENES = 2  # animations: the frame being rendered and the next one


def _cache_scene(key, scene):
    with _cache_lock:
        _scenes[key] = scene
        _scenes.move_to_end(key)
        while len(_scenes) > _CACHED_SCENES:
            _scenes.popitem(last=False)


# Scenes this process built from a payload (tests and bench/farm_scenes_bench.py read it on
# the workers: the client's own validated scene is not counted).
worker_scene_builds = 0

# Set by the client on Ctrl-C: in-process workers' renders stop within a pass.
_cancel = threading.Event()
# Set by main()'s SIGINT handler. Its KeyboardInterrupt can land inside a finalizer (Dask's
# Future.__del__ runs on the main thread), where Python prints "Exception ignored" and drops it;
# run_jobs checks this flag after every result so a dropped Ctrl-C still cancels the job.
_sigint = threading.Event()


def _worker_scene(payload: ScenePayload):
    """The built Scene of a payload, built once per worker process (LRU of _CACHED_SCENES)."""
    global worker_scene_builds
    with _cache_lock:
        scene = _scenes.get(payload.key)
        if scene is not None:
            _scenes.move_to_end(payload.key)
            return scene
        tmp = None
        try:
            if payload.files:
                tmp = tempfile.mkdtemp(prefix="facet-farm-")
                for name, data in payload.files.items():
                    pathlib.Path(tmp, name).write_bytes(data)
            desc = _description(payload, tmp or ".")
            worker_scene_builds += 1
            if payload.sent_fingerprint is not None and \
                    desc.fingerprint() != payload.sent_fingerprint:
                raise FarmError(f"{payload.name}: the scene changed on its way to the worker")
            try:
                scene = facet.build_scene(desc, name=payload.name)
            except (ValueError, RuntimeError, OSError) as e:
                # The client built this scene, so a failure here is most likely a file the
                # worker cannot see: say where it looked.
                import socket

                raise FarmError(f"{e} (on worker {socket.gethostname()}: textures, environment "
                                f"maps and glTF files are read by each worker at the client's "
                                f"absolute paths, under {payload.base_dir}: share them at the "
                                f"same path)") from None
        except (ValueError, RuntimeError, OSError) as e:
            raise FarmError(str(e)) from None
        finally:
            if tmp:
                shutil.rmtree(tmp, ignore_errors=True)
        _scenes[payload.key] = scene
        while len(_scenes) > _CACHED_SCENES:
            _scenes.popitem(last=False)
        return scene


def _scene_data(payload: ScenePayload) -> ScenePayload:
    return payload


@dataclasses.dataclass
class AdaptivePiece:
    """A tile of an adaptive render: its region's image (the whole render's pixels there) and
    the mean samples per pixel its tiles took."""

    region: tuple
    image: np.ndarray
    mean_spp: float


def render_piece(payload: ScenePayload, region, samples, threads: int):
    """The Dask task: renders `region` x `samples` of the payload's scene; a facet.RenderPart,
    or for an adaptive render (all its samples) an AdaptivePiece."""
    scene = _worker_scene(payload)
    session = facet.RenderSession(scene, spp=payload.spp, seed=payload.seed, region=region,
                                  samples=samples, threads=threads, time_budget=0)
    if not session.render(lambda info: not _cancel.is_set()):
        raise FarmError("cancelled")
    if payload.adaptive:
        return AdaptivePiece(tuple(region), np.asarray(session.image(), dtype=np.float32),
                             float(session.stats.mean_spp))
    part = session.part()
    part.name = f"{payload.name} region {tuple(region)} samples {tuple(samples)}"
    return part


FEATURES = ("albedo", "normal", "depth")


def feature_piece(payload: ScenePayload, region, threads: int):
    """The Dask task of a denoised render: the denoiser's features of `region` at the render's
    spp and seed, with their variances (facet.render_aovs(variances=True)): {name: array of
    the region's size}. Not split by sample range: a pixel's variance needs the sums of all
    its samples, and a region's values are the whole image's pixels there, bit for bit."""
    scene = _worker_scene(payload)
    return facet.render_aovs(scene, list(FEATURES), spp=payload.spp, seed=payload.seed,
                             threads=threads, variances=True, region=tuple(region))


# ---------------------------------------------------------------------------------------------
# Client side: plans, merging, the job loop


def tiles(width: int, height: int, size: int):
    """Regions (x0, y0, x1, y1) of a grid of size x size tiles covering the image, row-major."""
    return [(x, y, min(x + size, width), min(y + size, height))
            for y in range(0, height, size) for x in range(0, width, size)]


def chunks(spp: int, chunk: int):
    """Sample ranges [s0, s1) of at most `chunk` samples covering [0, spp)."""
    chunk = max(1, min(chunk, spp))
    return [(s, min(s + chunk, spp)) for s in range(0, spp, chunk)]


def half_chunks(spp: int, chunk: int | None):
    """chunks() of each half-buffer, [0, spp/2) and [spp/2, spp): no sample range straddles
    the halves, so the tiles of each half sum on their own (denoising)."""
    h = spp // 2
    return ([(a, b) for a, b in chunks(h, chunk or h)] +
            [(h + a, h + b) for a, b in chunks(spp - h, chunk or spp - h)])


# The sessions' tile grid (render.h kDefaultTileSize): an adaptive render's tasks are regions on
# it, where a region's pixels are the whole render's.
ADAPTIVE_GRID = 16


def plan_still(width: int, height: int, spp: int, slots: int, tile_size: int | None = None,
               sample_chunk: int | None = None, adaptive: bool = False):
    """(regions, sample ranges) of a still, in the order the tasks are submitted (Dask runs
    independent tasks roughly in that order). Default: the largest tile of 512, 256, 128 or 64
    px giving at least 8 tiles per task slot, so a task is long against the scheduler's ~ms per
    task; and the last 2 tiles per slot cut in 4 x 4, so the wait for the last task (slots idle
    while it runs) is a sixteenth of a tile. Regions need not lie on one grid: any split merges
    to the same image. An adaptive render: regions on the 16-pixel grid (tile sizes multiples of
    16), the whole sample range each."""
    if tile_size is not None and tile_size < 1:
        raise FarmError(f"--tile-size: must be >= 1, got {tile_size}")
    if sample_chunk is not None and sample_chunk < 1:
        raise FarmError(f"--sample-chunk: must be >= 1, got {sample_chunk}")
    if adaptive and sample_chunk is not None and sample_chunk < spp:
        raise FarmError("--sample-chunk: an adaptive render (render.adaptive_threshold > 0) is "
                        "not split by sample range (its tiles stop at sample counts of their "
                        "own); it is split by tiles only")
    if adaptive and tile_size is not None and tile_size % ADAPTIVE_GRID:
        raise FarmError(f"--tile-size: an adaptive render (render.adaptive_threshold > 0) is "
                        f"split on its {ADAPTIVE_GRID}-pixel tile grid: give a multiple of "
                        f"{ADAPTIVE_GRID}, got {tile_size}")
    samples = chunks(spp, sample_chunk or spp)
    if tile_size is not None:
        return tiles(width, height, tile_size), samples
    size = 64  # all candidates and their quarters are multiples of ADAPTIVE_GRID
    for candidate in (512, 256, 128):
        if len(tiles(width, height, candidate)) >= 8 * slots:
            size = candidate
            break
    regions = tiles(width, height, size)
    tail = min(len(regions) // 4, 2 * slots)
    if size >= 64 and tail > 0:
        sub = size // 4
        last = regions[-tail:]
        regions = regions[:-tail]
        for x0, y0, x1, y1 in last:
            regions += [(x, y, min(x + sub, x1), min(y + sub, y1))
                        for y in range(y0, y1, sub) for x in range(x0, x1, sub)]
    return regions, samples


def _part_state(part):
    return part.__getstate__()


def _sum_parts(parts):
    """One part of the union of sample ranges of parts covering the same region: the 128-bit
    fixed-point sums added exactly (two uint64 words with carry), counts added."""
    if len(parts) == 1:
        return parts[0]
    states = sorted((_part_state(p) for p in parts), key=lambda s: s[5])
    first = list(states[0])
    sums = np.frombuffer(first[9], dtype=np.uint64).reshape(-1, 2).copy()
    counts = np.frombuffer(first[10], dtype=np.uint32).copy()
    end = first[6]
    for s in states[1:]:
        if s[5] != end or tuple(s[4]) != tuple(first[4]):
            raise FarmError(f"internal: parts of {first[8]} do not chain ({end} vs {s[5]})")
        end = s[6]
        other = np.frombuffer(s[9], dtype=np.uint64).reshape(-1, 2)
        lo = sums[:, 0] + other[:, 0]
        carry = (lo < sums[:, 0]).astype(np.uint64)
        sums[:, 1] += other[:, 1] + carry
        sums[:, 0] = lo
        counts += np.frombuffer(s[10], dtype=np.uint32)
        if first[11]:  # alpha (film transparency): its 128-bit sums, added the same way
            alpha = np.frombuffer(first[11], dtype=np.uint64).reshape(-1, 2).copy()
            oa = np.frombuffer(s[11], dtype=np.uint64).reshape(-1, 2)
            lo = alpha[:, 0] + oa[:, 0]
            alpha[:, 1] += oa[:, 1] + (lo < alpha[:, 0]).astype(np.uint64)
            alpha[:, 0] = lo
            first[11] = alpha.tobytes()
    first[6] = end
    first[9] = sums.tobytes()
    first[10] = counts.tobytes()
    merged = facet.RenderPart.__new__(facet.RenderPart)
    merged.__setstate__(tuple(first))
    return merged


def _place(job, part):
    """Pastes a complete tile (samples [0, spp)) into the job's image. A pixel's value depends
    only on its own sums (film.h), so the tile's resolved image is exactly that pixel of the
    merged image: no full-image merge at the end. Checks what merge_parts would."""
    p = job.payload
    if job.fingerprint is None:
        job.fingerprint = part.fingerprint
    if part.fingerprint != job.fingerprint or part.seed != p.seed or \
            (part.width, part.height) != (p.width, p.height) or part.samples != (0, p.spp):
        raise FarmError(f"{p.name}: internal: part {part.name} does not belong to this render "
                        f"(fingerprint, seed, size or samples {part.samples} differ)")
    img = part.image()  # (h, w, 3), or RGBA with film transparency
    if job.image is None:
        job.image = np.zeros((p.height, p.width, img.shape[2]), dtype=np.float32)
    x0, y0, x1, y1 = part.region
    job.image[y0:y1, x0:x1] = img


def _place_adaptive(job, piece):
    """Pastes an adaptive render's tile (AdaptivePiece) into the job's image."""
    p = job.payload
    if job.image is None:
        job.image = np.zeros((p.height, p.width, piece.image.shape[2]), dtype=np.float32)
    x0, y0, x1, y1 = piece.region
    job.image[y0:y1, x0:x1] = piece.image
    job.samples_taken += piece.mean_spp * (x1 - x0) * (y1 - y0)


def _place_halves(job, tile):
    """Pastes a complete tile's two half-buffers (the sums of its parts below and above
    spp/2) into job.halves."""
    p = job.payload
    h = p.spp // 2
    if job.halves is None:
        job.halves = [np.zeros((p.height, p.width, tile[0].image().shape[2]), dtype=np.float32)
                      for _ in range(2)]
    x0, y0, x1, y1 = tile[0].region
    for k, part in enumerate((_sum_parts([t for t in tile if t.samples[1] <= h]),
                              _sum_parts([t for t in tile if t.samples[0] >= h]))):
        job.halves[k][y0:y1, x0:x1] = part.image()


def _place_features(job, region, features):
    """Pastes a region's features and their variances (feature_piece) into job.features."""
    p = job.payload
    if job.features is None:
        job.features = {k: np.zeros((p.height, p.width, 3), dtype=np.float32) for k in features}
    x0, y0, x1, y1 = region
    for k, v in features.items():
        job.features[k][y0:y1, x0:x1] = v


def _denoised(job):
    """The merged half-buffers denoised on the client with the features and their variances
    the workers rendered per tile: `facet render --denoise`'s image, bit for bit. Denoising
    runs after the merge because a denoiser is not split-invariant (a pixel's result depends
    on its neighbours, which another tile may hold)."""
    f = job.features
    out = facet.denoise(job.halves[0][:, :, :3], job.halves[1][:, :, :3],
                        *(f[k] for k in FEATURES),
                        **{k + "_variance": f[k + "_variance"] for k in FEATURES})
    if job.image.shape[2] == 4:  # alpha is not denoised: the merged render's (as the CLI)
        out = np.dstack([out, job.image[:, :, 3]]).astype(np.float32)
    return out


@dataclasses.dataclass
class Job:
    """One image: a payload, its pieces and where the merged image goes."""

    payload: ScenePayload
    regions: list
    samples: list
    outputs: list                 # paths written when the image is complete
    label: str = ""
    image: np.ndarray | None = None
    fingerprint: int | None = None  # of the first part (scene + render settings)
    denoise: bool = False           # samples split at spp/2; halves kept; denoised at the end
    raw_outputs: list = dataclasses.field(default_factory=list)  # the image before denoising
    halves: list | None = None      # the two half-buffer images (denoise)
    features: dict | None = None    # features and their variances (denoise: feature_piece)
    samples_taken: float = 0.0      # adaptive: the samples its tiles took, summed

    @property
    def mean_spp(self) -> float:
        """The mean samples per pixel (an adaptive render's; else its spp)."""
        p = self.payload
        return self.samples_taken / (p.width * p.height) if p.adaptive else float(p.spp)

    @property
    def tasks(self) -> int:
        """Render pieces, and with denoise one feature piece per region."""
        return len(self.regions) * (len(self.samples) + int(self.denoise))


class Progress:
    """A one-line progress bar on a terminal (stderr), nothing otherwise."""

    def __init__(self, total: int, unit: str, enabled: bool | None = None):
        self.total, self.unit, self.done = total, unit, 0
        self.enabled = sys.stderr.isatty() if enabled is None else enabled
        self.start = time.monotonic()
        self.last = 0.0

    def step(self, n: int = 1):
        self.done += n
        now = time.monotonic()
        if not self.enabled or (now - self.last < 0.1 and self.done < self.total):
            return
        self.last = now
        elapsed = now - self.start
        eta = elapsed / self.done * (self.total - self.done) if self.done else 0.0
        width = 30
        filled = int(width * self.done / max(self.total, 1))
        sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {self.done}/{self.total} "
                         f"{self.unit}, {elapsed:.1f} s, ETA {eta:.1f} s ")
        sys.stderr.flush()

    def close(self):
        if self.enabled and self.done:
            sys.stderr.write("\n")
            sys.stderr.flush()


def _write(image, outputs):
    for out in outputs:
        pathlib.Path(out).parent.mkdir(parents=True, exist_ok=True)
        facet.write_image(image, out)


def _finish(jobs, j, tiles_left):
    """Job j's last piece arrived: denoise if asked, write its outputs."""
    job = jobs[j]
    tiles_left[j] = -1
    if job.denoise:
        _write(job.image, job.raw_outputs)
        job.image, job.halves, job.features = _denoised(job), None, None
    _write(job.image, job.outputs)
    if len(jobs) > 1 and job.outputs:
        job.image = None  # animations: written, dropped


def run_jobs(client, jobs: Sequence[Job], threads_per_task: int = 1,
             progress: Progress | None = None, on_result: Callable | None = None) -> list:
    """Renders every job's pieces on the client's cluster and writes each image as soon as it is
    complete. Returns the images (None for jobs that wrote theirs and dropped it: animations).
    Raises FarmError for a failed task (after cancelling the rest); KeyboardInterrupt cancels
    every task and is re-raised."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    import dask

    futures = {}
    pending = {}
    _cancel.clear()
    # Each submit records its caller's source code for Dask's dashboard (inspect.getsource of
    # the first frame outside these modules): skipping facet's frames makes it the few lines
    # of the caller, not run_jobs tokenized again per task (measured: ~5 ms per task).
    ignored = dask.config.get("distributed.diagnostics.computations.ignore-modules", [])
    code_config = dask.config.set({"distributed.diagnostics.computations.ignore-modules":
                                   list(ignored) + ["facet", "runpy"]})
    try:
        for j, job in enumerate(jobs):
            # The scene travels once per job to the scheduler, as the spec of a task returning
            # it: Dask copies its result to each worker that runs one of the job's pieces (once
            # per worker, from peers), and recomputes it if every worker holding it is lost
            # (data scattered by the client would be gone with them).
            with warnings.catch_warnings():  # "Large object ... in task graph": on purpose
                warnings.filterwarnings("ignore", message="Large object", category=UserWarning)
                scattered = client.submit(_scene_data, job.payload, pure=False)
            pending[j] = {r: [] for r in job.regions}
            for s in job.samples:
                for r in job.regions:
                    f = client.submit(render_piece, scattered, r, s, threads_per_task,
                                      pure=False, retries=0)
                    futures[f] = (j, r, False)
            if job.denoise:
                for r in job.regions:
                    f = client.submit(feature_piece, scattered, r, threads_per_task,
                                      pure=False, retries=0)
                    futures[f] = (j, r, True)
        # Pieces still to come per job: the tiles, and with denoise their features.
        tiles_left = {j: len(job.regions) * (1 + int(job.denoise)) for j, job in enumerate(jobs)}
        for future in as_completed(list(futures), loop=client.loop):
            if _sigint.is_set():
                raise KeyboardInterrupt
            j, r, is_features = futures.pop(future)
            try:
                part = future.result()
            except KilledWorker as e:
                raise FarmError(f"{jobs[j].payload.name}: a task killed its worker "
                                f"{e.args[1] if len(e.args) > 1 else ''} repeatedly: {e}") from None
            except FarmError:
                raise
            except Exception as e:  # the task's own error, re-raised by Dask
                raise FarmError(f"{jobs[j].payload.name}: {type(e).__name__}: {e}") from None
            del future
            if is_features:
                _place_features(jobs[j], r, part)
                tiles_left[j] -= 1
            else:
                if on_result:
                    on_result(part)
                tile = pending[j][r]
                tile.append(part)
                if isinstance(part, AdaptivePiece):  # a whole tile of an adaptive render
                    _place_adaptive(jobs[j], part)
                    del pending[j][r]
                    tiles_left[j] -= 1
                elif len(tile) == len(jobs[j].samples):
                    _place(jobs[j], _sum_parts(tile))
                    if jobs[j].denoise:
                        _place_halves(jobs[j], tile)
                    del pending[j][r]
                    tiles_left[j] -= 1
            if progress:
                progress.step()
            if tiles_left[j] == 0:
                _finish(jobs, j, tiles_left)
    except KeyboardInterrupt:
        _cancel.set()
        raise
    finally:
        code_config.__exit__(None, None, None)
        if futures:
            client.cancel(list(futures))
        if progress:
            progress.close()
    return [job.image for job in jobs]


# ---------------------------------------------------------------------------------------------
# Clusters


def local_cluster(workers: int | None = None, threads: int | None = None,
                  processes: bool | None = None):
    """A LocalCluster on this machine, no dashboard. Default (workers None or 0): one worker in
    this process with a task thread per core (inproc transport: no socket but the scheduler's
    HTTP endpoint on 127.0.0.1); workers >= 1: that many worker processes listening on
    127.0.0.1 only."""
    from distributed import LocalCluster

    cores = os.cpu_count() or 1
    if processes is None:
        processes = bool(workers)
    # Quiet worker processes: they read Dask's logging levels from the environment at import.
    os.environ.setdefault("DASK_LOGGING__DISTRIBUTED", "error")
    # No statistical profiler in the workers: it samples every task thread's stack every 10 ms
    # with the GIL held (measured: ~8% more CPU than `facet render` with it on). Worker
    # processes get the client's Dask config from their nanny.
    import dask

    dask.config.set({"distributed.worker.profile.enabled": False,
                     # event-loop watchdog and resource sampling: 1 s, not 20 ms / 0.5 s
                     "distributed.admin.tick.interval": "1s",
                     "distributed.admin.system-monitor.interval": "2s"})
    return LocalCluster(n_workers=workers or 1, threads_per_worker=threads or cores,
                        processes=processes, host="127.0.0.1" if processes else None, dashboard_address=None,
                        preload=["facet.farm"] if processes else [],  # dask_setup: no SIGINT
                        scheduler_port=0, silence_logs=logging.ERROR, memory_limit=0,
                        # the scheduler's HTTP endpoint on loopback too, any free port
                        scheduler_kwargs={"dashboard": False, "dashboard_address": "127.0.0.1:0"})


def connect(address, timeout: float = 10.0):
    """A Client of the scheduler at `address` (or of a LocalCluster); FarmError when it cannot be
    reached within `timeout` seconds."""
    from distributed import Client

    try:
        return Client(address, timeout=timeout, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as e:
        raise FarmError(f"cannot reach the Dask scheduler at {address} within {timeout:g} s "
                        f"({type(e).__name__}: {e})") from None
    except TypeError as e:  # tls:// without Dask's TLS settings (distributed.comm.tls.*)
        raise FarmError(f"cannot connect to the Dask scheduler at {address}: {e}") from None


def quiet_logs():
    """Dask's and tornado's logs at ERROR (distributed sets its own levels when imported)."""
    import distributed  # noqa: F401  (sets its loggers' levels when first imported)

    for name in ("distributed", "tornado", "asyncio", "bokeh"):
        logging.getLogger(name).setLevel(logging.ERROR)


def dask_setup(worker):
    """Preload of the local cluster's worker processes: they ignore SIGINT, which a terminal's
    Ctrl-C sends to the whole process group; the client cancels the job and closes them."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)


def _slots(client) -> int:
    return max(1, sum(w.get("nthreads", 1)
                      for w in client.scheduler_info().get("workers", {}).values()))


# ---------------------------------------------------------------------------------------------
# The command


def frame_outputs(pattern: str, number: int) -> str:
    """out/frame_####.exr -> out/frame_0007.exr (a run of #: the frame number, zero-padded)."""
    return re.sub(r"#+", lambda m: f"{number:0{len(m.group(0))}d}", pattern, count=1)


def frame_number(path: str, position: int) -> int:
    """The number at the end of the scene file's stem (frames/f_0042.json -> 42), else position."""
    m = re.search(r"(\d+)$", pathlib.Path(path).stem)
    return int(m.group(1)) if m else position


def render_files(scenes: Sequence[str], outputs: Sequence[str], scheduler: str | None = None,
                 tile_size: int | None = None, sample_chunk: int | None = None,
                 spp: int | None = None, seed: int | None = None, workers: int | None = None,
                 threads: int | None = None, task_threads: int = 1, timeout: float = 10.0,
                 progress: bool | None = None, client=None, stats: dict | None = None,
                 denoise: bool = False, denoise_raw: Sequence[str] = (),
                 adaptive_threshold: float | None = None,
                 adaptive_min_samples: int | None = None):
    """Renders scene files (one still, or the frames of an animation) on Dask; see main()."""
    if not scenes:
        raise FarmError("no scene given")
    if not outputs:
        raise FarmError("-o: give at least one output (.exr or .png)")
    if denoise_raw and not denoise:
        raise FarmError("--denoise-raw: needs --denoise")
    animation = len(scenes) > 1
    if animation and not all("#" in o for o in list(outputs) + list(denoise_raw)):
        raise FarmError("-o: an animation needs a frame pattern in every output "
                        "(out/frame_####.exr)")
    t0 = time.monotonic()
    # Validate every scene here first: a bad one is one error, before any cluster starts.
    payloads = [load_payload(s, spp=spp, seed=seed, validate=True,
                             adaptive_threshold=adaptive_threshold,
                             adaptive_min_samples=adaptive_min_samples) for s in scenes]
    for payload in payloads:
        if denoise and payload.spp < 2:
            raise FarmError(f"{payload.name}: --denoise: needs at least 2 samples per pixel, "
                            f"got {payload.spp}")
        if denoise and payload.adaptive:
            raise FarmError(f"{payload.name}: --denoise: cannot be combined with adaptive "
                            f"sampling (render.adaptive_threshold > 0): the denoiser's "
                            f"half-buffers are sample ranges")
    t_load = time.monotonic()
    cluster = None
    own_client = client is None
    try:
        if own_client:
            if scheduler:
                client = connect(scheduler, timeout)
            else:
                cluster = local_cluster(workers, threads)
                client = connect(cluster, timeout)
        slots = _slots(client)
        # Render threads per task: 1 when each worker runs as many tasks at once as it has cores.
        per_task = max(1, task_threads)
        t_cluster = time.monotonic()
        jobs = []
        for k, payload in enumerate(payloads):
            if animation and len(payloads) >= slots and tile_size is None and sample_chunk is None:
                regions = [(0, 0, payload.width, payload.height)]
                samples = [(0, payload.spp)]
            else:
                regions, samples = plan_still(payload.width, payload.height, payload.spp, slots,
                                              tile_size, sample_chunk, payload.adaptive)
            if denoise:
                samples = half_chunks(payload.spp, sample_chunk)
            number = frame_number(payload.name, k + 1)
            name = (lambda o: frame_outputs(o, number)) if animation else (lambda o: o)
            jobs.append(Job(payload, regions, samples, [name(o) for o in outputs],
                            label=str(number), denoise=denoise,
                            raw_outputs=[name(o) for o in denoise_raw]))
        total = sum(j.tasks for j in jobs)
        unit = "frames" if animation and total == len(jobs) else "tiles"
        bar = Progress(total, unit, progress)
        images = run_jobs(client, jobs, per_task, bar)
        t_end = time.monotonic()
        if stats is not None:
            stats.update(load_s=t_load - t0, cluster_s=t_cluster - t_load,
                         render_s=t_end - t_cluster, tasks=total, slots=slots,
                         mean_spp=[job.mean_spp for job in jobs])
        return images
    finally:
        if own_client and client is not None:
            client.close()
        if cluster is not None:
            cluster.close()


def _parser():
    p = argparse.ArgumentParser(
        prog="facet-farm",
        description="Distributed rendering of Facet scenes on Dask: bit-identical to "
                    "`facet render`, whatever the split, the workers and lost workers.")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("render", help="render a still or the frames of an animation")
    r.add_argument("scenes", nargs="+", help="scene.json, or frames/*.json for an animation")
    r.add_argument("-o", "--output", action="append", default=[], required=True,
                   help=".exr/.png; repeatable; with #### (frame number) for animations")
    r.add_argument("--scheduler", help="tcp://host:8786 or tls://host:8786 (default: a local "
                   "cluster on 127.0.0.1)")
    r.add_argument("--tile-size", type=int, help="tile edge in pixels (default: by image size "
                   "and task slots)")
    r.add_argument("--sample-chunk", type=int, help="samples per task (default: all)")
    r.add_argument("--spp", type=int, help="samples per pixel (default: the scene's)")
    r.add_argument("--seed", type=int, help="sampler seed (default: the scene's)")
    r.add_argument("--adaptive-threshold", type=float,
                   help="adaptive sampling's noise threshold in [0, 1], 0 = off (default: the "
                   "scene's render.adaptive_threshold); split by tiles only")
    r.add_argument("--adaptive-min-samples", type=int,
                   help="adaptive sampling's minimum samples, 0 = automatic (default: the "
                   "scene's)")
    r.add_argument("--workers", type=int, default=0,
                   help="local cluster: worker processes (default 0: one worker thread per core "
                   "in this process)")
    r.add_argument("--threads", type=int, help="local cluster: task threads per worker "
                   "(default: the cores)")
    r.add_argument("--task-threads", type=int, default=1,
                   help="render threads of each task (default 1: one task per core)")
    r.add_argument("--timeout", type=float, default=10.0,
                   help="seconds to wait for the scheduler (default 10)")
    r.add_argument("--denoise", action="store_true",
                   help="denoise each image after its tiles are merged (docs/denoise.md): the "
                   "image of `facet render --denoise`")
    r.add_argument("--denoise-raw", action="append", default=[],
                   help="with --denoise: also write the image before denoising; repeatable")
    r.add_argument("--progress", dest="progress", action="store_true", default=None,
                   help="progress bar even when stderr is not a terminal")
    r.add_argument("--no-progress", dest="progress", action="store_false")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    quiet_logs()
    _sigint.clear()
    previous = None
    if threading.current_thread() is threading.main_thread():
        def on_sigint(signum, frame):
            _sigint.set()
            raise KeyboardInterrupt
        previous = signal.signal(signal.SIGINT, on_sigint)
    try:
        return _main(args)
    finally:
        if previous is not None:  # main() called in-process: leave SIGINT as it was
            signal.signal(signal.SIGINT, previous)
        _sigint.clear()


def _main(args) -> int:
    try:
        render_files(args.scenes, args.output, scheduler=args.scheduler,
                     tile_size=args.tile_size, sample_chunk=args.sample_chunk, spp=args.spp,
                     seed=args.seed, workers=args.workers, threads=args.threads,
                     task_threads=args.task_threads,
                     timeout=args.timeout, progress=args.progress, denoise=args.denoise,
                     denoise_raw=args.denoise_raw, adaptive_threshold=args.adaptive_threshold,
                     adaptive_min_samples=args.adaptive_min_samples)
    except FarmError as e:
        print(f"facet-farm: error: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("facet-farm: cancelled", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    # `python3 -m facet.farm`: run the imported module's main, so that tasks pickle by reference
    # to facet.farm (as on the workers), not by value from __main__.
    from facet.farm import main as _main

    sys.exit(_main())
