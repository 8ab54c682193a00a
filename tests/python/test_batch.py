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


SCRIPT = """import distributed
from hsr import batch
{guard}
{indent}jobs = batch.orbit_jobs("spheres:200", 4, {out!r}, width=32, height=24)
{indent}with distributed.Client(n_workers=1, threads_per_worker=1, dashboard_address=None) as c:
{indent}    print(len(batch.run(jobs, client=c)), "views")
"""


def run_script(tmp_path, guarded):
    import subprocess
    import sys
    path = tmp_path / ("guarded.py" if guarded else "unguarded.py")
    path.write_text(SCRIPT.format(guard='if __name__ == "__main__":' if guarded else "",
                                  indent="    " if guarded else "", out=str(tmp_path / "out")))
    return subprocess.run([sys.executable, str(path)], capture_output=True, text=True, timeout=120,
                          cwd=tmp_path, env=dict(os.environ))


def test_a_script_without_the_main_guard_is_told_so_and_stopped(tmp_path):
    pytest.importorskip("distributed")
    r = run_script(tmp_path, guarded=False)
    assert r.returncode != 0
    assert 'outside `if __name__ == "__main__":`' in r.stderr
    assert "views" not in r.stdout


def test_a_script_with_the_main_guard_runs(tmp_path):
    pytest.importorskip("distributed")
    r = run_script(tmp_path, guarded=True)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "4 views"
    assert "hsr.batch:" not in r.stderr
