"""Many scenes and views as independent tasks on Dask: each task renders one view and writes
its own files (the CLI's --raw set: depth.npy, ids.npy, objects.npy, materials.npy,
overdraw.npy, manifest.json with the camera; and color.png), so results never meet in memory
and a task that is run twice writes the same bytes.

    from hsr import batch
    jobs = batch.orbit_jobs("model.ply", 100, "out/views", width=640, height=480)
    batch.run(jobs)                                  # here, one after another
    batch.run(jobs, scheduler="tcp://host:8786")     # on a cluster (a shared file system)
    batch.run(jobs, client=distributed.Client(...))  # on a client you made

A worker loads each scene once (cached per process) and reuses it for every view it renders.

A script that starts its own local cluster (distributed.Client() or LocalCluster()) must do so
under `if __name__ == "__main__":`; Dask's worker processes import the script again, and
without the guard each starts a cluster of its own and the run waits forever. A script that
imports hsr.batch before it starts the cluster is told so instead, in one line, and stopped
(see _refuse_clusters_while_bootstrapping).
"""

import functools
import multiprocessing
import os
import signal
import sys
from dataclasses import dataclass

from . import _hsr

_UNGUARDED = ("hsr.batch: this script starts a Dask cluster outside `if __name__ == \"__main__\":`; "
              "Dask's worker processes import the script again and each would start a cluster of "
              "its own, and the run would wait forever: put the cluster and the run under that "
              "guard (stopping the run)\n")


def _bootstrapping():
    """True while this process is a new worker process importing the main script again
    (multiprocessing's spawn: the script runs as __mp_main__ before the worker starts)."""
    return bool(getattr(multiprocessing.current_process(), "_inheriting", False))


def _refuse_clusters_while_bootstrapping():
    """A cluster started while a worker process is still importing the script is the missing
    guard: Dask would restart that worker for ever. Its Client and LocalCluster then say so in
    one line, and stop the script that started the worker (its parent) and the worker itself.
    Any other time (the script itself, a task calling get_client()) they are Dask's own."""
    if not _bootstrapping():
        return
    try:
        import distributed
    except ImportError:
        return
    for cls in (distributed.Client, distributed.LocalCluster):
        original = cls.__init__

        def init(self, *args, __original=original, **kwargs):
            if _bootstrapping():
                sys.stderr.write(_UNGUARDED)
                sys.stderr.flush()
                os.kill(os.getppid(), signal.SIGTERM)
                os._exit(2)
            __original(self, *args, **kwargs)

        cls.__init__ = init


_refuse_clusters_while_bootstrapping()


@dataclass(frozen=True)
class Job:
    scene: str           # a model file or a built-in scene (as hsr render takes)
    camera: str          # the camera as JSON (hsr.Camera.to_json())
    out: str             # the directory this view's files go to
    algorithm: str = "zbuffer"
    depth: str = "window"
    normals: str = ""
    color: bool = True
    threads: int = 1     # per task: the tasks are the parallelism


@functools.lru_cache(maxsize=8)
def _scene(spec):
    return _hsr.Scene.load(spec)


def run_job(job):
    """Renders one job and writes its files; returns its output directory."""
    scene = _scene(job.scene)
    camera = _hsr.Camera.from_json(job.camera)
    os.makedirs(os.path.dirname(os.path.abspath(job.out)), exist_ok=True)
    _hsr.render_files(scene, camera, job.out, job.scene, algorithm=job.algorithm, depth=job.depth,
                      normals=job.normals, threads=job.threads, color=job.color)
    return job.out


def orbit_jobs(scene, views, out_root, width=640, height=480, **options):
    """`views` cameras on a ring around the scene (as hsr render --orbit), one job each, writing
    out_root/NNNN/."""
    framed = _hsr.Camera.frame(_scene(scene), width, height)
    return [Job(scene=scene, camera=framed.orbit(k, views).to_json(),
                out=os.path.join(out_root, "%04d" % k), **options) for k in range(views)]


def run(jobs, client=None, scheduler=None):
    """Runs the jobs: on `client` (a distributed.Client), on the cluster whose scheduler
    address is `scheduler`, or here one after another. Returns the output directories in
    job order."""
    jobs = list(jobs)
    if client is None and scheduler is None:
        return [run_job(j) for j in jobs]
    from distributed import Client
    own = client is None
    if own:
        client = Client(scheduler)
    try:
        futures = client.map(run_job, jobs, pure=False)
        return client.gather(futures)
    finally:
        if own:
            client.close()
