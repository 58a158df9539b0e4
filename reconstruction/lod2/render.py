"""A picture of a city model, rendered off-screen with pyvista (VTK).

Roofs red, walls white, ground grey, as in the thesis's Fig. 5.22; the
buildings copied from an existing model in a second colour scheme (blue
roofs, pale blue walls); an oblique view from an azimuth (degrees clockwise
from north, where the camera stands) and an elevation (degrees above the
horizon); optionally the historical map draped on the ground.

No display is needed: without ``DISPLAY`` VTK is told to open an EGL
window (``VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow``), which Mesa's
software renderer serves (Debian packages ``libegl1`` and
``libgl1-mesa-dri``).
"""

import ctypes.util
import os
from dataclasses import dataclass

import numpy as np

from ..cityjson import geometry as citygeometry
from ..core.errors import InputError
# the suite's one palette (the web page's and the glTF's too), and the surfaces' kinds
from ..view.scene import BACKGROUND, COLOURS, COPIED_COLOURS, KIND


@dataclass(frozen=True)
class View:
    """Where the camera looks from: azimuth (degrees clockwise from north)
    and elevation (degrees above the horizon)."""
    azimuth: float = 210.0
    elevation: float = 35.0


@dataclass(frozen=True)
class Surfaces:
    """The faces to draw: ``points`` (n, 3) relative to ``origin``; ``rings``
    and ``ring_start`` (exterior rings, indices into points); ``kind`` per
    face (0 ground, 1 wall, 2 roof, 3 other) and ``copied`` per face."""
    points: np.ndarray
    rings: np.ndarray
    ring_start: np.ndarray
    kind: np.ndarray
    copied: np.ndarray
    origin: np.ndarray


def _top(objects, oid):
    seen = set()
    while objects.get(oid, {}).get("parents") and oid not in seen:
        seen.add(oid)
        oid = objects[oid]["parents"][0]
    return oid


def surfaces(document, copied=()):
    """The exterior rings of the highest-LoD geometries of every city object
    of a CityJSON document (dict), with their semantic kind; ``copied``: ids
    of the top-level objects to draw in the second colour scheme."""
    objects = document.get("CityObjects", {})
    copied = set(copied or ())
    rings, kinds, flags = [], [], []
    for oid, obj in objects.items():
        geoms = [g for g in obj.get("geometry", ()) if g.get("type") in citygeometry.SURFACE_DEPTH]
        if not geoms:
            continue
        top = max(citygeometry.lod_value(g.get("lod")) for g in geoms)
        is_copied = _top(objects, oid) in copied
        for g in geoms:
            if citygeometry.lod_value(g.get("lod")) != top:
                continue
            faces, types = citygeometry.surface_types(g)
            for face, kind in zip(faces, types):
                if face and len(face[0]) >= 3:
                    rings.append(face[0])
                    kinds.append(KIND.get(kind, -1))
                    flags.append(is_copied)
    t = document.get("transform") or {"scale": [1, 1, 1], "translate": [0, 0, 0]}
    vertices = np.asarray(document.get("vertices") or np.zeros((0, 3)), dtype=float).reshape(-1, 3)
    xyz = vertices * t["scale"] + t["translate"]
    origin = xyz.min(axis=0) if len(xyz) else np.zeros(3)
    flat, start = citygeometry.flat_indices(rings)
    kind = np.asarray(kinds, dtype=np.int64)
    points = xyz - origin
    unknown = kind < 0
    if unknown.any():
        kind[unknown] = _kind_by_normal(points, flat, start)[unknown]
    return Surfaces(points, flat, start, kind, np.asarray(flags, dtype=bool), origin)


def _kind_by_normal(points, flat, start):
    """Ground, wall or roof of every ring by its Newell normal (as solids.semantics)."""
    sizes = np.diff(start)
    nxt = np.arange(len(flat)) + 1
    nxt[start[1:] - 1] = start[:-1]
    p, q = points[flat], points[flat[nxt]]
    terms = np.column_stack([(p[:, 1] - q[:, 1]) * (p[:, 2] + q[:, 2]),
                             (p[:, 2] - q[:, 2]) * (p[:, 0] + q[:, 0]),
                             (p[:, 0] - q[:, 0]) * (p[:, 1] + q[:, 1])])
    normal = np.add.reduceat(terms, start[:-1], axis=0) if len(sizes) else np.zeros((0, 3))
    nz = normal[:, 2] / np.maximum(np.linalg.norm(normal, axis=1), 1e-300)
    kind = np.full(len(nz), 2, dtype=np.int64)
    kind[np.abs(nz) < np.sin(np.radians(5.0))] = 1
    kind[nz < -np.cos(np.radians(5.0))] = 0
    return kind


def _headless():
    """Tell VTK to open an EGL window when there is no display."""
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return
    if ctypes.util.find_library("EGL") is None:
        raise InputError("Rendering without a display needs EGL (Debian packages libegl1 and "
                         "libgl1-mesa-dri)")
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def _mesh(s, pv):
    faces = np.insert(s.rings, s.ring_start[:-1], np.diff(s.ring_start))
    colours = np.where(s.copied[:, None], COPIED_COLOURS[s.kind], COLOURS[s.kind])
    mesh = pv.PolyData(s.points, faces=faces)
    mesh.cell_data["colour"] = colours.astype(np.uint8)
    edges = pv.PolyData(s.points, lines=faces)
    return mesh.triangulate(), edges


def _map_plane(map_image, origin, z, pv):
    west, east, south, north = map_image.extent
    corners = np.array([[west, south, z], [east, south, z], [east, north, z], [west, north, z]])
    plane = pv.PolyData(corners - origin, faces=np.array([4, 0, 1, 2, 3]))
    plane.active_texture_coordinates = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    # numpy_to_texture puts row 0 at texture coordinate 1 (north)
    texture = pv.numpy_to_texture(np.ascontiguousarray(map_image.rgb, dtype=np.uint8))
    return plane, texture


#: buildings drawn at most (issue 33, item 9): a picture costs about 17 KB
#: of memory per building drawn, and at 1,600 x 1,200 pixels more buildings
#: would be specks; v.histo.lod2 draws a larger model by the footprints
#: nearest the middle of them all (:func:`reconstruction.lod2.output.drawn_footprints`)
MAX_DRAWN = 10000

#: faces up to which every face is outlined by default (more: the outlines would grey the picture)
EDGE_FACES = 20000


def render(document, path, view=None, size=(1600, 1200), map_image=None, copied=(),
           edges=None):
    """Write a PNG picture of a CityJSON document (dict) to ``path``.

    ``view``: a :class:`View`; ``map_image``: a :class:`MapImage` draped at
    the lowest vertex of the model; ``copied``: ids of top-level objects
    drawn in the second colour scheme; ``edges``: outline every face (None:
    when the model has at most :data:`EDGE_FACES` faces).
    Returns the image as an (rows, columns, 3) uint8 array.
    """
    view = view or View()
    s = surfaces(document, copied)
    if len(s.kind) == 0:
        raise InputError("The model has no surfaces to draw")
    _headless()
    import pyvista as pv

    mesh, outline = _mesh(s, pv)
    plotter = pv.Plotter(off_screen=True, window_size=list(size), lighting="none")
    try:
        plotter.set_background(BACKGROUND)
        # a light at the camera: the faces turned to the viewer are lit best
        plotter.add_light(pv.Light(light_type="headlight"))
        plotter.add_mesh(mesh, scalars="colour", rgb=True, ambient=0.6, diffuse=0.55,
                         specular=0.0, show_scalar_bar=False)
        if edges or edges is None and len(s.kind) <= EDGE_FACES:
            plotter.add_mesh(outline, color=(60, 60, 60), line_width=1)
        if map_image is not None:
            plane, texture = _map_plane(map_image, s.origin, s.origin[2] - 0.05, pv)
            plotter.add_mesh(plane, texture=texture, ambient=1.0, diffuse=0.0, specular=0.0)
        lo, hi = s.points.min(axis=0), s.points.max(axis=0)
        centre = (lo + hi) / 2.0
        az, el = np.radians(view.azimuth), np.radians(view.elevation)
        direction = np.array([np.sin(az) * np.cos(el), np.cos(az) * np.cos(el), np.sin(el)])
        radius = max(float(np.linalg.norm(hi - lo)) / 2.0, 1.0)
        plotter.camera.focal_point = centre.tolist()
        plotter.camera.position = (centre + direction * radius * 3.0).tolist()
        plotter.camera.up = (0.0, 0.0, 1.0) if view.elevation < 89.9 else (0.0, 1.0, 0.0)
        plotter.reset_camera()
        plotter.camera.zoom(1.15)
        image = plotter.screenshot(path, return_img=True)
    finally:
        plotter.close()
    return image
