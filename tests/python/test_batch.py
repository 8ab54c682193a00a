"""hsr.batch on Dask: 100 views as independent tasks on a local cluster of 2 worker processes
write the same bytes as a sequential run."""
import filecmp
import os

import pytest

from hsr import batch


def tree(root):
    files = []
    for d, _, names in os.walk(root):
        files += [os.path.relpath(os.path.join(d, n), root) for n in names]
    return sorted(files)


def test_dask_local_cluster_matches_a_sequential_run(tmp_path):
    distributed = pytest.importorskip("distributed")
    seq = batch.orbit_jobs("spheres:2000", 100, str(tmp_path / "seq"), width=96, height=72, depth="linear")
    par = batch.orbit_jobs("spheres:2000", 100, str(tmp_path / "par"), width=96, height=72, depth="linear")
    assert batch.run(seq) == [j.out for j in seq]
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        done = batch.run(par, client=client)
        workers = client.run(os.getpid)
    assert done == [j.out for j in par]
    assert len(set(workers.values())) == 2  # two processes did the work
    files = tree(tmp_path / "seq")
    assert len(files) == 100 * 7  # depth, ids, objects, materials, overdraw, manifest, color.png
    assert files == tree(tmp_path / "par")
    match, mismatch, errors = filecmp.cmpfiles(tmp_path / "seq", tmp_path / "par", files, shallow=False)
    assert mismatch == [] and errors == []
