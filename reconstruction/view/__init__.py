"""City models for people to look at: a browser viewer and glTF (issue 29).

- ``scene``: a CityJSON model (of one date, or of v.histo.timeline over
  several) as triangles by building in typed arrays (:func:`build_scene`,
  a :class:`Scene`; of a CityJSONSeq file a batch of features at a time,
  :func:`scene_of_seq`);
- ``html``: the self-contained page that shows a scene in a browser
  (:func:`viewer_html`, written piece by piece by :func:`write_viewer`; its
  script ``viewer.js`` and style ``viewer.css``);
- ``gltf``: a scene as one binary glTF file, a node per building
  (:func:`glb_bytes`, written building by building by :func:`write_glb`);
- ``tiles``: a scene as 3D Tiles 1.1, a quadtree of glTF tiles with each
  building's id, years and attributes as metadata (:func:`write_tileset`).

Imports ``core``, ``geom``, ``cityjson`` and ``epochs``; used by the stages
that write models (``lod2``, ``timeline``).
"""

from . import gltf, html, scene, tiles
from .gltf import glb_bytes, write_glb
from .html import viewer_html, write_viewer
from .scene import Scene, build_scene, scene_of_seq
from .tiles import write_tileset

__all__ = ["Scene", "build_scene", "glb_bytes", "gltf", "html", "scene", "scene_of_seq",
           "tiles", "viewer_html", "write_glb", "write_tileset", "write_viewer"]
