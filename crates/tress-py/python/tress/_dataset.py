"""Datasets: many grooms rendered from the same cameras into files, on one machine or a cluster.

    import tress
    cams = tress.orbit(16, radius=60, elevation=10, target=(0, -5, 0), width=512, height=512)
    summary = tress.render_dataset(sorted(glob.glob("grooms/*.hair")), cams, "out",
                                   maps=("rgb", "alpha"), workers=2)
    summary["failed"]        # [(groom, the error's line), ...]

Layout: ``{out_dir}/{groom}/{view:03d}_{map}.npy`` for every map the renderer returns (each view's
(H, W, C) array as ``Renderer.render`` gives it), ``{view:03d}_rgb.png`` (sRGB, 8 bits) beside the
rgb array when Pillow is importable (``png=``), and ``{groom}/done.json`` written last, atomically.
A groom whose ``done.json`` describes the same cameras, maps, technique, head, settings and render
arguments, and whose listed files all exist, is skipped: an interrupted run picks up where it
stopped and a deleted output is drawn again. A changed input file is not noticed: delete its
``done.json`` (or the groom's folder).

Engines:

* ``"local"``: a process pool on this machine (``concurrent.futures.ProcessPoolExecutor``,
  started with ``spawn``: a forked child would inherit the parent's GPU driver threads).
  ``workers`` defaults to 1: each worker opens its own GPU device, which is heavy (lavapipe
  already uses every core for one frame), so more workers pay only on a machine with several
  GPUs or many cores. ``workers=0`` renders in this process, for debugging.
* ``"dask"``: Dask's ``distributed``. ``scheduler`` is an address (``"tcp://host:8786"``) or a
  ``distributed.Client``; without it a ``LocalCluster`` of ``workers`` (default 2) processes of one
  thread each is started and closed again. Workers write the files themselves, so ``out_dir`` and
  the inputs must be on a file system every worker sees.

Why Dask and not Ray: ``distributed`` is a pure-Python wheel of a few MB (Ray is a ~60 MB binary
wheel per platform and Python version, with its own object store and dashboard processes), its
``LocalCluster`` starts in a second or two inside a test, and the same code runs unchanged against a
scheduler on a cluster (SLURM/PBS/Kubernetes through ``dask-jobqueue``/``dask-kubernetes``). A groom
is a coarse task whose result is files on disk, so Ray's shared-memory object store buys nothing
here. Ray is not provided; ``pip install tress[dask]`` adds Dask.

Every worker process keeps ONE :class:`tress.Renderer` (opened on its first groom, or by the
local pool's initializer) and reuses it for every groom it is given. Failures (a corrupt file
raises :class:`tress.HairError`) are collected, never stop the other grooms, and are returned as
``(groom, line)``.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import threading
import time
import traceback
from typing import Any, Iterable, Optional, Sequence, Union

import numpy as np

from ._camera import Camera

_MARKER = "done.json"
_FORMAT = 1  # the marker's layout; a marker of another layout means "render again"

# One renderer per process, created on first use and kept (the local pool's initializer creates it
# up front; a Dask worker on its first groom). The lock serialises renders if a worker runs several
# threads.
_RENDERER = None
_LOCK = threading.Lock()


def _renderer():
    global _RENDERER
    if _RENDERER is None:
        from ._render import Renderer

        _RENDERER = Renderer()
    return _RENDERER


def _init_worker():
    _renderer()


# -- arguments -------------------------------------------------------------------------------


def _groom_name(source) -> str:
    if isinstance(source, (list, tuple)):
        if not source:
            raise ValueError("an input needs at least one path")
        source = source[0]
    name = os.path.basename(os.fspath(source))
    stem, _ = os.path.splitext(name)
    return stem or name


def _tasks_from(inputs) -> list:
    """``[(name, source)]`` where source is a list of paths (merged in order) or a tress.Hair."""
    from ._hair import Hair

    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    out = []
    for item in inputs:
        if isinstance(item, (str, os.PathLike)):
            name, source = _groom_name(item), item
        elif isinstance(item, (tuple, list)) and len(item) == 2 and isinstance(item[0], str):
            name, source = item
        else:
            raise TypeError(f"inputs must be paths or (name, path) pairs, got {item!r}")
        if isinstance(source, Hair):
            pass
        elif isinstance(source, (str, os.PathLike)):
            source = [os.fspath(source)]
        elif isinstance(source, (list, tuple)) and source and all(
                isinstance(p, (str, os.PathLike)) for p in source):
            source = [os.fspath(p) for p in source]
        else:
            raise TypeError(f"groom {name!r}: the source must be a path, a list of paths or a "
                            f"tress.Hair, got {type(source).__name__}")
        if name in ("", ".", "..") or "/" in name or os.sep in name or "\0" in name:
            raise ValueError(f"groom name {name!r} cannot be a folder name")
        out.append((name, source))
    names = [n for n, _ in out]
    dupes = sorted({n for n in names if names.count(n) > 1})
    if dupes:
        raise ValueError(f"groom names must be unique, these repeat: {dupes}; "
                         "pass (name, path) pairs to name them")
    return out


def _jsonable(v):
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (np.generic,)):
        return v.item()
    if isinstance(v, dict):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_jsonable(x) for x in v]
    if isinstance(v, (str, int, float, bool)) or v is None:
        return v
    return repr(v)


def _head_key(head):
    if head is None or isinstance(head, str):
        return head
    try:
        v, f = head
        digest = hashlib.sha256()
        for a in (np.ascontiguousarray(v, dtype=np.float32), np.ascontiguousarray(f, dtype=np.int64)):
            digest.update(str(a.shape).encode())
            digest.update(a.tobytes())
        return {"mesh_sha256": digest.hexdigest()}
    except Exception:
        return repr(head)  # render() says what is wrong with it


def _key(cameras, maps, technique, head, settings, render_kwargs) -> dict:
    """What the outputs depend on (besides the input), as the marker records it."""
    return {
        "format": _FORMAT,
        "cameras": [{"view": c.view.tolist(), "projection": c.projection.tolist(),
                     "width": c.width, "height": c.height} for c in cameras],
        "maps": list(maps),
        "technique": technique,
        "head": _head_key(head),
        "settings": _jsonable(settings or {}),
        "render": _jsonable(render_kwargs),
    }


def _digest(key: dict) -> str:
    return hashlib.sha256(json.dumps(key, sort_keys=True).encode()).hexdigest()


def _is_done(groom_dir: str, digest: str) -> bool:
    try:
        with open(os.path.join(groom_dir, _MARKER)) as f:
            marker = json.load(f)
    except (OSError, ValueError):
        return False
    if not isinstance(marker, dict) or marker.get("digest") != digest:
        return False
    files = marker.get("files")
    return isinstance(files, list) and all(
        isinstance(n, str) and os.path.isfile(os.path.join(groom_dir, n)) for n in files)


# -- one groom (runs in a worker) -----------------------------------------------------------------


def _error_line(e: BaseException) -> str:
    from . import _tress

    text = str(e).strip()
    line = text.splitlines()[0] if text else ""
    if isinstance(e, _tress.HairError):
        return line
    return f"{type(e).__name__}: {line}" if line else type(e).__name__


def _png_writer(png):
    if png is False:
        return None
    try:
        from PIL import Image
    except ImportError:
        if png:
            raise ImportError("png=True needs Pillow (pip install pillow)") from None
        return None
    return Image


def _render_groom(task: dict) -> tuple:
    """Renders one groom and writes its files; returns (name, None | error line, seconds).
    Never raises: a failure is returned as its line (and the traceback goes to stderr for
    anything that is not a HairError)."""
    from . import _tress
    from ._hair import Hair, load

    t0 = time.perf_counter()
    name, out = task["name"], task["dir"]
    try:
        source = task["source"]
        hair = source if isinstance(source, Hair) else load(source)
        os.makedirs(out, exist_ok=True)
        try:  # outputs of other arguments are about to be replaced: never leave their marker
            os.remove(os.path.join(out, _MARKER))
        except FileNotFoundError:
            pass
        r = _renderer()
        with _LOCK:
            result = r.render(hair, task["cameras"], technique=task["technique"], maps=task["maps"],
                              head=task["head"], settings=task["settings"], **task["render_kwargs"])
        image = _png_writer(task["png"])
        files = []
        for m, arr in result.items():
            arr = np.asarray(arr)
            for v in range(arr.shape[0]):
                fname = f"{v:03d}_{m}.npy"
                np.save(os.path.join(out, fname), arr[v])
                files.append(fname)
                if m == "rgb" and image is not None:
                    px = arr[v] if arr.dtype == np.uint8 else _srgb8(arr[v])
                    fname = f"{v:03d}_rgb.png"
                    image.fromarray(np.ascontiguousarray(px)).save(os.path.join(out, fname))
                    files.append(fname)
        seconds = time.perf_counter() - t0
        marker = {"digest": task["digest"], "groom": name,
                  "source": "tress.Hair" if isinstance(source, Hair) else source,
                  "views": len(task["cameras"]), "maps": sorted(result), "files": files,
                  "seconds": round(seconds, 3), "adapter": r.adapter, "key": task["key"]}
        tmp = os.path.join(out, f".{_MARKER}.{os.getpid()}.tmp")
        with open(tmp, "w") as f:
            json.dump(marker, f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, os.path.join(out, _MARKER))
        return name, None, seconds
    except Exception as e:  # noqa: BLE001 - every failure is reported, none stops the others
        if not isinstance(e, _tress.HairError):
            traceback.print_exc(file=sys.stderr)
        return name, _error_line(e), time.perf_counter() - t0


def _srgb8(linear: np.ndarray) -> np.ndarray:
    from ._render import _srgb8 as f

    return f(linear)


# -- progress ---------------------------------------------------------------------------------


class _Counter:
    """``render_dataset: 3/8 grooms (1 skipped, 0 failed) 12 s`` on stderr: one line rewritten on
    a terminal, else a line at most every 30 s and at the end (logs stay short)."""

    def __init__(self, total: int, enabled: bool):
        self.total, self.enabled, self.n, self.t0 = total, enabled, 0, time.perf_counter()
        self.skipped = self.failed = 0
        self.tty = enabled and hasattr(sys.stderr, "isatty") and sys.stderr.isatty()
        self.last = -1e9
        self._show()

    def update(self, failed: bool = False, skipped: bool = False):
        self.n += 1
        self.failed += failed
        self.skipped += skipped
        self._show()

    def _line(self) -> str:
        return (f"render_dataset: {self.n}/{self.total} grooms ({self.skipped} skipped, "
                f"{self.failed} failed) {time.perf_counter() - self.t0:.0f} s")

    def _show(self, final: bool = False):
        if not self.enabled:
            return
        if self.tty:
            sys.stderr.write("\r" + self._line() + ("\n" if final else ""))
        elif final or time.perf_counter() - self.last >= 30.0:
            self.last = time.perf_counter()
            sys.stderr.write(self._line() + "\n")
        sys.stderr.flush()

    def close(self):
        self._show(final=True)


class _Tqdm:
    def __init__(self, total: int, enabled: bool):
        from tqdm.auto import tqdm

        self.bar = tqdm(total=total, unit="groom", disable=not enabled, desc="render_dataset")
        self.skipped = self.failed = 0

    def update(self, failed: bool = False, skipped: bool = False):
        self.failed += failed
        self.skipped += skipped
        self.bar.set_postfix(skipped=self.skipped, failed=self.failed, refresh=False)
        self.bar.update(1)

    def close(self):
        self.bar.close()


def _progress(total: int, enabled: bool):
    if enabled:
        try:
            return _Tqdm(total, enabled)
        except ImportError:
            pass
    return _Counter(total, enabled)


# -- engines ----------------------------------------------------------------------------------


def _run_local(tasks: list, workers: int, report) -> None:
    if workers == 0:
        for t in tasks:
            report(*_render_groom(t))
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    ctx = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker) as pool:
        futures = {pool.submit(_render_groom, t): t["name"] for t in tasks}
        for fut in as_completed(futures):
            try:
                report(*fut.result())
            except Exception as e:  # the worker died (BrokenProcessPool) or its result was lost
                report(futures[fut], f"worker failed: {_error_line(e)}", 0.0)


def _run_dask(tasks: list, workers: Optional[int], scheduler, report) -> None:
    from distributed import Client, LocalCluster, as_completed

    cluster = None
    if scheduler is None:
        cluster = LocalCluster(n_workers=workers or 2, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    elif isinstance(scheduler, Client):
        client = scheduler
    else:
        client = Client(scheduler)
    try:
        futures = client.map(_render_groom, tasks, pure=False)
        names = {f.key: t["name"] for f, t in zip(futures, tasks)}
        for fut in as_completed(futures):
            try:
                report(*fut.result())
            except Exception as e:  # the worker died (KilledWorker) or the task was lost
                report(names[fut.key], f"worker failed: {_error_line(e)}", 0.0)
            fut.release()
    finally:
        if client is not scheduler:
            client.close()
        if cluster is not None:
            cluster.close()


def render_dataset(inputs: Iterable[Any], cameras: Union[Camera, Sequence[Camera]], out_dir,
                   maps: Iterable[str] = ("rgb", "alpha"), engine: str = "local",
                   technique: str = "strands", head=None, settings: Optional[dict] = None,
                   workers: Optional[int] = None, progress: bool = True, scheduler=None,
                   png: Optional[bool] = None, **render_kwargs) -> dict:
    """Render every groom in ``inputs`` from every camera and write the maps to ``out_dir``.

    ``inputs``: hair file paths (the groom is named by the file's stem) or ``(name, source)``
    pairs, the source a path, a list of paths merged in order, or a :class:`tress.Hair`.
    ``cameras``, ``maps``, ``technique``, ``head``, ``settings`` and ``render_kwargs``
    (``background``, ``rgb_format``, ``width``, ``height``) are :meth:`tress.Renderer.render`'s,
    the same for every groom. ``engine``: ``"local"`` or ``"dask"`` (see the module docs;
    ``workers`` and ``scheduler`` configure them). ``png``: also write rgb as PNG (None: when
    Pillow is importable). ``progress``: a tqdm bar if tqdm is importable, else a line on stderr.

    Returns ``{"done": rendered, "skipped": already done, "failed": [(groom, error line)],
    "seconds": wall time}``. The local engine uses ``spawn``: call it under
    ``if __name__ == "__main__":`` in a script.
    """
    from . import _render

    if engine not in ("local", "dask"):
        raise ValueError(f'engine must be "local" or "dask", got {engine!r}')
    if workers is not None and (int(workers) != workers or workers < (0 if engine == "local" else 1)):
        raise ValueError(f"workers must be an integer >= {0 if engine == 'local' else 1}, got {workers!r}")
    if scheduler is not None and engine != "dask":
        raise ValueError('scheduler is for engine="dask"')
    cams = [cameras] if isinstance(cameras, Camera) else list(cameras)
    if not cams or not all(isinstance(c, Camera) for c in cams):
        raise TypeError("cameras must be a tress.Camera or a non-empty sequence of them")
    maps = (maps,) if isinstance(maps, str) else tuple(maps)
    if not maps:
        raise ValueError("maps must name at least one map")
    known = getattr(_render, "MAPS", None)
    unknown = [m for m in maps if known is not None and m not in known]
    if unknown:
        raise ValueError(f"unknown map(s) {unknown}; valid maps: {', '.join(known)}")
    settings = dict(settings or {})
    pairs = _tasks_from(inputs)
    out_dir = os.path.abspath(os.fspath(out_dir))
    os.makedirs(out_dir, exist_ok=True)

    key = _key(cams, maps, technique, head, settings, render_kwargs)
    digest = _digest(key)
    t0 = time.perf_counter()
    bar = _progress(len(pairs), progress)
    summary = {"done": 0, "skipped": 0, "failed": [], "seconds": 0.0}

    def report(name, error, _seconds):
        if error is None:
            summary["done"] += 1
        else:
            summary["failed"].append((name, error))
        bar.update(failed=error is not None)

    tasks = []
    try:
        for name, source in pairs:
            d = os.path.join(out_dir, name)
            if _is_done(d, digest):
                summary["skipped"] += 1
                bar.update(skipped=True)
                continue
            tasks.append({"name": name, "source": source, "dir": d, "cameras": cams, "maps": maps,
                          "technique": technique, "head": head, "settings": settings,
                          "render_kwargs": render_kwargs, "png": png, "key": key, "digest": digest})
        if tasks:
            if engine == "local":
                _run_local(tasks, 1 if workers is None else int(workers), report)
            else:
                _run_dask(tasks, workers, scheduler, report)
    finally:
        bar.close()
    order = {n: i for i, (n, _) in enumerate(pairs)}
    summary["failed"].sort(key=lambda f: order.get(f[0], 0))
    summary["seconds"] = time.perf_counter() - t0
    return summary
