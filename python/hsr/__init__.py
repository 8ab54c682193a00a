"""hsr: hidden-surface removal with every classic algorithm, for Python and NumPy.

    import hsr
    scene = hsr.Scene.load("model.ply")            # or hsr.Scene.load("spheres:1000")
    camera = hsr.Camera.frame(scene, 640, 480)     # or hsr.camera_from_intrinsics(...)
    out = hsr.render(scene, camera, depth="linear", normals="world")
    out.color        # (H, W, 3) uint8, top row first
    out.depth        # (H, W) float32: window z, or scene units ("linear", "distance"; inf = nothing)
    out.ids          # (H, W) uint32 polygon id, 4294967295 where nothing was drawn
    out.objects      # (H, W) uint32 object index: the mask of object k is out.objects == k
    out.normals      # (H, W, 3) float32 when asked for ("world" or "eye")

Every algorithm by name (hsr.algorithms()), the GL-style facade (hsr.gl.Context), ray
queries (hsr.RayScene) and batches on Dask (hsr.batch). The arrays own the buffers the C++
core filled (no copy); the GIL is released while it renders.
"""

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from . import _hsr
from ._hsr import Camera, Error, RayScene, Scene, algorithms, gl, render_files

__all__ = ["Scene", "Camera", "Error", "RayScene", "Frame", "render", "render_files", "algorithms",
           "gl", "camera_from_intrinsics", "scene_from_arrays", "view", "options", "NO_ID"]

NO_ID = 0xFFFFFFFF  # ids, objects, materials where nothing was drawn


@dataclass
class Frame:
    """What render() returns: NumPy arrays, top row first, and the run's figures."""
    color: np.ndarray      # (H, W, 3) uint8, a view of rgba
    rgba: np.ndarray       # (H, W, 4) uint8
    depth: np.ndarray      # (H, W) float32, in the convention asked for
    ids: np.ndarray        # (H, W) uint32
    objects: np.ndarray    # (H, W) uint32
    materials: np.ndarray  # (H, W) uint32
    overdraw: np.ndarray   # (H, W) uint32
    normals: Optional[np.ndarray] = None   # (H, W, 3) float32, nan where nothing was drawn
    coverage: Optional[np.ndarray] = None  # (H, W) float32, antialiasing algorithms only
    stats: dict = field(default_factory=dict)  # counts, stage times, the camera, the tables


def render(scene, camera, algorithm="zbuffer", depth="window", normals=None, **options):
    """Renders `scene` from `camera` with `algorithm` (any of hsr.algorithms()).

    depth: "window" (OpenGL window z in [0, 1], 1 where nothing was drawn), "linear" (along the
    view axis) or "distance" (along the pixel's ray), both in scene units, inf where nothing
    was drawn. normals: None, "world" or "eye". The options are the render state of
    hsr.options(), as the command line names them without the dashes: the OpenGL-style
    controls (cull, front_face, polygon_mode, point_size, depth_func, depth_test, depth_mask,
    clear_depth, outline, shade, facing), threads, samples, fragment_memory (MiB) and the BSP
    tree's bsp_splitter, bsp_seed and bsp_candidates; each checked as `hsr render` checks it.
    """
    arrays = _hsr.render(scene, camera, depth, normals or "", dict(options, algorithm=algorithm))
    return Frame(**arrays)


def view(scene, **options):
    """The camera the view options of hsr.options() describe, as `hsr render` makes it from
    its flags: size=(width, height) (default 800 x 600), eye, target, up, fov, ortho, near,
    far, intrinsics=(fx, fy, cx, cy) and camera_index (a scene file's camera, or "auto");
    fitted to `scene` where not given."""
    return _hsr.view(scene, options)


def options():
    """Every option render() and view() take, from the table the command line and the web page
    share: name, kind, view, default, help, choices, range, needs (the capability an algorithm
    needs to take a value other than the default) and cli (the command line's spelling)."""
    return _hsr.options()


def scene_from_arrays(vertices, faces, name="mesh", color=None):
    """A scene of one object from an N x 3 vertex array and an M x k face array (k >= 3,
    counter-clockwise seen from the front). Polygon ids are the face rows' indices."""
    scene = Scene()
    scene.name = name
    scene.add_mesh(vertices, faces, name=name, color=color)
    return scene


def camera_from_intrinsics(fx, fy, cx, cy, width, height, pose=None, convention="opencv",
                           near=None, far=None, scene=None):
    """A calibrated pinhole camera: intrinsics in pixels (OpenCV's convention: pixel centres at
    integers, (0, 0) the top-left pixel's centre), and a 4x4 camera-to-world pose in OpenCV's
    axes (x right, y down, z forward) or OpenGL's (x right, y up, looking down -z). Near and
    far: as given, else fitted around `scene`, else 0.1 and 1000."""
    camera = Camera()
    camera.width, camera.height = int(width), int(height)
    camera.intrinsics = (fx, fy, cx, cy)
    if pose is not None:
        camera.set_pose(np.asarray(pose, dtype=np.float64), convention)
    if scene is not None:
        camera.fit_near_far(scene)
    else:
        camera.near, camera.far = 0.1, 1000.0
    if near is not None:
        camera.near = near
    if far is not None:
        camera.far = far
    camera.validate()
    return camera
