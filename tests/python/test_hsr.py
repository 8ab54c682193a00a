"""hsr from Python: scenes from NumPy arrays and files, cameras (intrinsics, poses, JSON), render()
returning NumPy arrays equal to the CLI's raw files, every algorithm by name, the GL facade, ray
queries, and the GIL released while rendering."""
import json
import os
import subprocess
import threading
import time

import numpy as np
import pytest

import hsr


def square(z=0.0, size=1.0):
    v = np.array([[-size, -size, z], [size, -size, z], [size, size, z], [-size, size, z]], np.float32)
    return v, np.array([[0, 1, 2, 3]])


def test_render_a_scene_built_from_arrays():
    v, f = square()
    scene = hsr.scene_from_arrays(v, f, name="square", color=(1.0, 0.0, 0.0))
    assert scene.polygon_count == 1 and scene.objects[0]["name"] == "square"
    cam = hsr.Camera()
    cam.eye, cam.target, cam.width, cam.height, cam.near, cam.far = (0, 0, 5), (0, 0, 0), 64, 48, 1, 20
    out = hsr.render(scene, cam, depth="linear", normals="world")
    assert out.color.shape == (48, 64, 3) and out.color.dtype == np.uint8
    assert out.depth.shape == (48, 64) and out.depth.dtype == np.float32
    assert out.ids.dtype == np.uint32 and out.normals.shape == (48, 64, 3)
    drawn = out.ids != hsr.NO_ID
    assert 200 < drawn.sum() < 48 * 64
    # depth along the view axis in scene units: the square is 5 away
    np.testing.assert_allclose(out.depth[drawn], 5.0, atol=1e-3)
    assert np.isinf(out.depth[~drawn]).all()
    np.testing.assert_allclose(out.normals[drawn], [[0, 0, 1]] * int(drawn.sum()), atol=1e-6)
    assert (out.objects[drawn] == 0).all() and (out.objects[~drawn] == hsr.NO_ID).all()
    assert out.color[24, 32, 0] > 200 and out.color[24, 32, 2] < 60  # red, shaded
    assert out.stats["polygons_in"] == 1 and out.stats["camera"]["near"] == 1.0
    assert out.stats["materials"][0]["color"] == [1.0, 0.0, 0.0]


def test_arrays_are_owned_not_copied_and_writable():
    scene = hsr.Scene.load("spheres:200")
    out = hsr.render(scene, hsr.Camera.frame(scene, 80, 60))
    # color is a view of rgba: one buffer, the frame's
    assert np.shares_memory(out.color, out.rgba)
    # The arrays' memory is the C++ buffers', kept alive by the arrays (a capsule as base)
    assert not out.ids.flags.owndata and type(out.ids.base).__name__ == "PyCapsule"
    ids = out.ids
    del out
    assert ids.sum() > 0  # still readable after the Frame is gone
    ids[0, 0] = 7  # and writable


def test_bad_arrays_are_refused_with_a_clear_error():
    v, f = square()
    with pytest.raises(hsr.Error, match="uses vertex 9"):
        hsr.scene_from_arrays(v, np.array([[0, 1, 9]]))
    with pytest.raises(hsr.Error, match="N x 3"):
        hsr.scene_from_arrays(v[:, :2], f)
    # Indices must be integers: 1.7 would have been read as vertex 1
    for bad_dtype in (np.float64, np.float32, bool):
        with pytest.raises(hsr.Error, match="integer array of vertex indices"):
            hsr.scene_from_arrays(v, f.astype(bad_dtype))
    with pytest.raises(hsr.Error, match="integer"):
        hsr.scene_from_arrays(v, [[0.0, 1.5, 2.0]])
    assert hsr.scene_from_arrays(v, f.astype(np.uint16)).polygon_count == len(f)
    with pytest.raises(hsr.Error, match="not finite"):
        bad = v.copy()
        bad[1, 0] = np.nan
        hsr.scene_from_arrays(bad, f)
    with pytest.raises(hsr.Error):
        hsr.render(hsr.scene_from_arrays(v, f), hsr.Camera(), algorithm="no-such")
    assert issubclass(hsr.Error, ValueError)


def test_render_matches_the_cli_raw_files_byte_for_byte(cli, tmp_path):
    raw = tmp_path / "raw"
    subprocess.run([cli, "render", "solids", "--size", "120x90", "--output", "none", "--raw", str(raw),
                    "--depth", "distance", "--normals", "eye", "--algorithm", "scanline"], check=True)
    manifest = json.loads((raw / "manifest.json").read_text())
    scene = hsr.Scene.load("solids")
    camera = hsr.Camera.from_json(json.dumps(manifest["camera"]))
    out = hsr.render(scene, camera, algorithm="scanline", depth="distance", normals="eye")
    for name, array in [("depth", out.depth), ("ids", out.ids), ("objects", out.objects),
                        ("materials", out.materials), ("normals", out.normals), ("overdraw", out.overdraw)]:
        on_disk = np.load(raw / (name + ".npy"))
        assert on_disk.dtype == array.dtype and on_disk.shape == array.shape, name
        assert on_disk.tobytes() == array.tobytes(), name
    assert out.stats["camera"]["projection"] == manifest["camera"]["projection"]
    assert [o["name"] for o in out.stats["objects"]] == [o["name"] for o in manifest["objects"]]


OBJ_OBJECTS_AND_MATERIALS_DIFFER = """mtllib two.mtl
o first
v -1.5 -1 0
v -0.5 -1 0.3
v -1 1 0.1
usemtl blue
f 1 2 3
o second
v -0.6 -1 -0.4
v 0.6 -1 0.2
v 0 1.2 -0.1
usemtl red
f 4 5 6
o third
v 0.4 -1 0.1
v 1.6 -1 -0.3
v 1.1 1 0.2
usemtl blue
f 7 8 9
"""
MTL_TWO = "newmtl red\nKd 0.9 0.1 0.1\nnewmtl blue\nKd 0.1 0.2 0.9\n"


def test_every_array_matches_the_cli_raw_file_byte_for_byte(cli, tmp_path):
    # Three objects over two materials (the first and the third share one): an object index
    # given for a material index, or the other way round, cannot pass.
    (tmp_path / "three.obj").write_text(OBJ_OBJECTS_AND_MATERIALS_DIFFER)
    (tmp_path / "two.mtl").write_text(MTL_TWO)
    model = str(tmp_path / "three.obj")
    scene = hsr.Scene.load(model)
    assert len(scene.objects) == 3
    cases = [("zbuffer", "window", "world"), ("scanline", "linear", "eye"),
             ("abuffer", "distance", "world"), ("painter", "window", "eye"), ("raycast", "linear", "world")]
    for algorithm, depth, normals in cases:
        raw = tmp_path / ("raw-" + algorithm)
        subprocess.run([cli, "render", model, "--size", "96x72", "--output", "none", "--raw", str(raw),
                        "--depth", depth, "--normals", normals, "--algorithm", algorithm], check=True)
        manifest = json.loads((raw / "manifest.json").read_text())
        camera = hsr.Camera.from_json(json.dumps(manifest["camera"]))
        out = hsr.render(scene, camera, algorithm=algorithm, depth=depth, normals=normals)
        arrays = [("depth", out.depth), ("ids", out.ids), ("objects", out.objects),
                  ("materials", out.materials), ("normals", out.normals), ("overdraw", out.overdraw)]
        if algorithm == "abuffer":
            arrays.append(("coverage", out.coverage))
        else:
            assert out.coverage is None and not (raw / "coverage.npy").exists()
        for name, array in arrays:
            on_disk = np.load(raw / (name + ".npy"))
            assert array is not None, (algorithm, name)
            assert on_disk.dtype == array.dtype and on_disk.shape == array.shape, (algorithm, name)
            assert on_disk.tobytes() == array.tobytes(), (algorithm, name)
        drawn = out.ids != hsr.NO_ID
        # The scene tells the two apart: objects 0..2, materials 0..1 (or with a default first)
        assert set(np.unique(out.objects[drawn])) == {0, 1, 2}, algorithm
        assert len(np.unique(out.materials[drawn])) == 2, algorithm
        assert (out.objects[drawn] != out.materials[drawn]).any(), algorithm


def test_every_algorithm_by_name_agrees_with_the_reference_on_ids():
    scene = hsr.Scene.load("demo")
    camera = hsr.Camera.frame(scene, 96, 72)
    ref = hsr.render(scene, camera, algorithm="zbuffer")
    names = [a["name"] for a in hsr.algorithms()]
    assert "zbuffer" in names and "raycast" in names and len(names) >= 12
    for a in hsr.algorithms():
        out = hsr.render(scene, camera, algorithm=a["name"])
        agree = (out.ids == ref.ids).mean()
        assert out.ids.shape == (72, 96)
        if not a["demonstration"]:
            assert agree > 0.97, (a["name"], agree)



def test_a_textbook_algorithm_and_its_fast_sibling_draw_the_same_frame():
    scene = hsr.Scene.load("demo")
    camera = hsr.Camera.frame(scene, 96, 72)
    by_name = {a["name"]: a for a in hsr.algorithms()}
    textbooks = [a for a in by_name.values() if a["textbook"]]
    assert {a["name"] for a in textbooks} >= {"zbuffer-textbook", "scanline-textbook",
                                              "raycast-textbook", "abuffer-textbook"}
    for a in textbooks:
        fast = by_name[a["sibling"]]
        assert fast["sibling"] == a["name"] and not fast["textbook"]
        want = hsr.render(scene, camera, algorithm=a["name"])
        got = hsr.render(scene, camera, algorithm=fast["name"], threads=2)
        assert (want.ids == got.ids).all(), a["name"]
        assert (want.depth.view("u4") == got.depth.view("u4")).all(), a["name"]
        assert (want.color == got.color).all(), a["name"]


def test_a_calibrated_camera_puts_a_point_at_its_pixel():
    # A small square 4 units in front of an OpenCV camera, around the ray of pixel (37, 21)
    fx, fy, cx, cy = 90.0, 80.0, 40.5, 30.25
    u, v, z = 37, 21, 4.0
    x, y = (u - cx) / fx * z, (v - cy) / fy * z
    pose_cv = np.eye(4)  # OpenCV camera at the origin looking down world +z, y down
    hx, hy = 1.2 * z / fx, 1.2 * z / fy
    verts = np.array([[x - hx, y - hy, z], [x + hx, y - hy, z], [x + hx, y + hy, z], [x - hx, y + hy, z]], np.float32)
    scene = hsr.scene_from_arrays(verts, np.array([[0, 1, 2, 3]]))
    cam = hsr.camera_from_intrinsics(fx, fy, cx, cy, 80, 60, pose=pose_cv, near=0.5, far=50)
    out = hsr.render(scene, cam, depth="linear")
    rows, cols = np.nonzero(out.ids != hsr.NO_ID)
    assert len(rows) in (4, 9) and abs(cols.mean() - u) <= 0.5 and abs(rows.mean() - v) <= 0.5
    assert abs(out.depth[v, u] - z) < 1e-3
    # The same camera in OpenGL's axes: y and z turned
    pose_gl = pose_cv @ np.diag([1.0, -1.0, -1.0, 1.0])
    cam_gl = hsr.camera_from_intrinsics(fx, fy, cx, cy, 80, 60, pose=pose_gl, convention="opengl", near=0.5, far=50)
    assert (hsr.render(scene, cam_gl).ids == out.ids).all()
    np.testing.assert_allclose(cam.pose("opencv"), pose_cv, atol=1e-6)
    assert cam.intrinsics == (fx, fy, cx, cy)


def test_camera_json_round_trip_and_views():
    scene = hsr.Scene.load("spheres:100")
    cam = hsr.Camera.frame(scene, 64, 48)
    back = hsr.Camera.from_json(cam.to_json())
    np.testing.assert_array_equal(back.projection_matrix(), cam.projection_matrix())
    views = hsr.Camera.list_from_json(json.dumps([json.loads(cam.orbit(k, 4).to_json()) for k in range(4)]))
    assert len(views) == 4
    with pytest.raises(hsr.Error, match="width"):
        hsr.Camera.from_json('{"eye": [0, 0, 1]}')


def test_the_gl_facade():
    scene = hsr.Scene.load("demo")
    cam = hsr.Camera.frame(scene, 64, 48)
    gl = hsr.gl
    ctx = gl.Context(cam)
    ctx.enable(gl.DEPTH_TEST)
    ctx.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT)
    ctx.draw(scene)
    with_depth = ctx.arrays()
    assert (with_depth["ids"] == hsr.render(scene, cam, shade=True).ids).all()
    ctx.disable(gl.DEPTH_TEST)
    ctx.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT)
    ctx.draw(scene)
    assert (ctx.arrays()["ids"] != with_depth["ids"]).any()  # drawn in order: painter's mistake


def test_ray_queries():
    v, f = square(z=-3.0)
    rs = hsr.RayScene(hsr.scene_from_arrays(v, f))
    o = np.zeros((3, 3), np.float32)
    d = np.array([[0, 0, -1], [0.1, 0.1, -1], [0, 1, 0]], np.float32)
    hits = rs.intersect(o, d)
    np.testing.assert_allclose(hits["t"][:2], [3.0, 3.0], rtol=1e-6)
    assert hits["polygon"][0] == 0 and hits["polygon"][2] == hsr.NO_ID and np.isinf(hits["t"][2])
    np.testing.assert_allclose(hits["normal"][0], [0, 0, 1], atol=1e-6)
    assert list(rs.occluded(o, d)) == [True, True, False]
    nan = np.array([[np.nan, 0, 0]], np.float32)
    assert rs.intersect(nan, d[:1])["polygon"][0] == hsr.NO_ID


def test_rendering_releases_the_gil():
    scene = hsr.Scene.load("spheres:200000")
    cam = hsr.Camera.frame(scene, 640, 480)
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    time.sleep(0.01)
    before = len(ticks)
    start = time.perf_counter()
    hsr.render(scene, cam, algorithm="bsp", threads=1)
    elapsed = time.perf_counter() - start
    after = len(ticks)
    stop.set()
    t.join()
    # The other thread kept running while the C++ core worked (with the GIL held it could not)
    assert elapsed > 0.05
    assert after - before >= 10, (after - before, elapsed)
