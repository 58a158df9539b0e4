"""Where a CityJSON model from v.histo.lod2 has its roof ends, read from the geometry alone.

An *end* of a building is an edge of its footprint with a gable end or a
crow-stepped facade (a wall standing on the edge that rises above the eaves)
or a hip end (the roof face on the edge steeper than the building's
shallowest eaves face, by more than half a degree). A face's pitch is only
known to the model's coordinate resolution (1 mm) over its width: a sliver
face, a few millimetres high as the skeleton makes over a footprint's very
short edges, or a needle along the slope, is degrees off. Such faces take no part: the
shallowest face is the shallowest whose pitch is known within
:data:`PITCH_TOL`, and a face is a hip end only when it is steeper by more
than half a degree beyond its own uncertainty. A wall face is vertical
within solidset.SEMANTIC_ANGLE (5 degrees): its top may lean in from the
edge by as much. The footprint ring is the
ground surface reversed (edge k runs from its vertex k to k + 1), as
v.histo.lod2 writes it; edges shared with other footprints are found with
:func:`reconstruction.lod2.street_edges.street_edges` on the rings read back.
"""

import numpy as np

from reconstruction.lod2 import street_edges as se
from reconstruction.geom.solidset import SEMANTIC_ANGLE

#: the coordinate resolution of the models read (m): v.histo.lod2 writes millimetres
RESOLUTION = 1e-3
#: a face's pitch is known when its uncertainty is at most this (degrees)
PITCH_TOL = 0.25
#: how far a wall face may lean per metre of height: v.histo.lod2 makes a face
#: a WallSurface when it is vertical within solidset.SEMANTIC_ANGLE degrees
LEAN = float(np.tan(np.radians(SEMANTIC_ANGLE)))


def _surfaces(obj):
    geom = obj["geometry"][0]
    shell = geom["boundaries"][0]
    types = [s["type"] for s in geom["semantics"]["surfaces"]]
    kinds = [types[v] for v in geom["semantics"]["values"][0]]
    return shell, kinds


def buildings(model):
    """Per building: (id, footprint ring (n, 3) absolute, walls, roofs, attributes),
    walls and roofs as lists of (k, 3) vertex arrays."""
    t = np.array(model["transform"]["translate"], dtype=float)
    s = np.array(model["transform"]["scale"], dtype=float)
    v = np.array(model["vertices"], dtype=float) * s + t
    out = []
    for oid, obj in model["CityObjects"].items():
        shell, kinds = _surfaces(obj)
        ground = [v[surface[0]] for surface, k in zip(shell, kinds) if k == "GroundSurface"]
        walls = [v[surface[0]] for surface, k in zip(shell, kinds) if k == "WallSurface"]
        roofs = [v[surface[0]] for surface, k in zip(shell, kinds) if k == "RoofSurface"]
        ring = ground[0][::-1]
        out.append((oid, ring, walls, roofs, obj.get("attributes", {})))
    return out


def _newell(face):
    """Newell's normal of a face (k, 3), its length twice the face's area."""
    x, y, z = face[:, 0], face[:, 1], face[:, 2]
    xn, yn, zn = np.roll(x, -1), np.roll(y, -1), np.roll(z, -1)
    return np.array([np.sum((y - yn) * (z + zn)), np.sum((z - zn) * (x + xn)),
                     np.sum((x - xn) * (y + yn))])


def _pitch(face):
    """Pitch (degrees) of a planar face (k, 3): Newell's normal."""
    n = _newell(face)
    return float(np.degrees(np.arccos(min(abs(n[2]) / max(np.linalg.norm(n), 1e-12), 1.0))))


def _pitch_error(face, resolution=RESOLUTION):
    """Uncertainty (degrees) of the pitch of ``face`` (k, 3): two coordinate
    steps of ``resolution`` over its width (twice its area over its diameter,
    a triangle's smallest altitude), which is small for a sliver, be it a few
    millimetres high or a needle along the slope."""
    diameter = float(np.max(np.linalg.norm(face[:, None] - face[None], axis=-1)))
    width = np.linalg.norm(_newell(face)) / max(diameter, 1e-12)
    return float(np.degrees(np.arctan2(2.0 * resolution, width)))


def _on_edge(points, a, b, tol=2e-3):
    """True when every point (k, 3) lies over the segment a -> b (xy)."""
    d = b[:2] - a[:2]
    ln = float(np.hypot(*d))
    u = d / max(ln, 1e-12)
    rel = points[:, :2] - a[:2]
    along = rel @ u
    side = rel[:, 0] * u[1] - rel[:, 1] * u[0]
    return bool(np.all(np.abs(side) < tol) and np.all(along > -tol) and np.all(along < ln + tol))


def _rise(wall, a, b, level):
    """Length along the edge a -> b over which ``wall`` (k, 3) rises above ``level``:
    the extent of its vertices above it and of its boundary's crossings of it."""
    u = (b - a)[:2] / max(float(np.hypot(*(b - a)[:2])), 1e-12)
    p, q = wall, np.roll(wall, -1, axis=0)
    dz = q[:, 2] - p[:, 2]
    cross = (p[:, 2] - level) * (q[:, 2] - level) < 0
    t = (level - p[cross, 2]) / dz[cross]
    pts = np.concatenate([wall[wall[:, 2] > level, :2],
                          p[cross, :2] + t[:, None] * (q[cross, :2] - p[cross, :2])])
    if len(pts) < 2:
        return 0.0
    along = (pts - a[:2]) @ u
    return float(along.max() - along.min())


def ends_of(ring, walls, roofs, eaves_z, tol=0.05, resolution=RESOLUTION):
    """The edges of ``ring`` with a roof end: {edge: "wall" | "hip"}. A wall
    end rises above the eaves over at least half the edge (a gable end, a
    stepped facade; not the side of a stepped facade, flush with the party
    wall); a hip end see the module doc (``resolution``: the coordinates')."""
    n = len(ring)
    out = {}
    eaves_faces = []
    for face in roofs:
        low = np.abs(face[:, 2] - eaves_z) < tol
        if low.sum() >= 2:
            p = _pitch(face)
            eaves_faces.append((face, p, _pitch_error(face, resolution)))
    # the long faces: the shallowest sloped face whose pitch is known (flat
    # pieces at the eaves are no faces of it)
    sloped = [(p, e) for _, p, e in eaves_faces if p > 1.0]
    shallow = min((p for p, e in sloped if e <= PITCH_TOL),
                  default=min(sloped, key=lambda pe: pe[1])[0] if sloped else None)
    # a wall face is vertical within SEMANTIC_ANGLE: its top may lean in by that much
    tall = [(w, 2e-3 + (float(w[:, 2].max()) - eaves_z) * LEAN) for w in walls
            if w[:, 2].max() > eaves_z + tol]
    steep = [] if shallow is None else [
        face[np.abs(face[:, 2] - eaves_z) < tol] for face, pitch, error in eaves_faces
        if pitch - error > shallow + 0.5]
    for k in range(n):
        a, b = ring[k], ring[(k + 1) % n]
        length = float(np.hypot(*(b - a)[:2]))
        for w, lean in tall:
            if _on_edge(w, a, b, lean) and _rise(w, a, b, eaves_z + tol) >= 0.5 * length:
                out[k] = "wall"
                break
        if k in out:
            continue
        for low in steep:
            if _on_edge(low, a, b) and \
                    np.ptp(low[:, :2] @ ((b - a)[:2] / max(length, 1e-12))) > 0.5 * length:
                out[k] = "hip"
                break
    return out


def model_ends(model):
    """Per building (in model order): id, ring (n, 2), its ends (edge -> kind),
    the shared flags of its edges, and its attributes."""
    rows = buildings(model)
    resolution = float(max(model["transform"]["scale"]))
    rings = [r[1][:, :2] for r in rows]
    res = se.street_edges(rings)
    out = []
    for i, (oid, ring, walls, roofs, attrs) in enumerate(rows):
        z = float(attrs.get("ground_height", 0.0)) + float(attrs.get("eaves_height", 0.0))
        shared = res.shared[res.edges.start[i]:res.edges.start[i + 1]]
        out.append((oid, ring[:, :2], ends_of(ring, walls, roofs, z, resolution=resolution),
                    shared, attrs))
    return out, res


def ends_on_shared(model):
    """Counts: buildings, ends, ends on shared edges (by kind), far/street split."""
    rows, res = model_ends(model)
    total = on_shared = 0
    kinds = {"wall": 0, "hip": 0}
    for oid, ring, ends, shared, attrs in rows:
        for k, kind in ends.items():
            total += 1
            if shared[k]:
                on_shared += 1
                kinds[kind] += 1
    return {"buildings": len(rows), "ends": total, "on_shared": on_shared, **kinds}


def tops_outside(model, tol=1e-9):
    """(id, top, ridge_height_low, ridge_height_high) of every building of
    ``model`` whose top (the highest vertex of its solid above its
    ``ground_height``) lies outside its ridge interval by more than ``tol``
    (m: the floating point of the subtraction; the model is exact to the
    millimetre); buildings without an interval are not looked at (issue 49,
    item 5)."""
    out = []
    for oid, ring, walls, roofs, attrs in buildings(model):
        low, high = attrs.get("ridge_height_low"), attrs.get("ridge_height_high")
        if low is None or high is None:
            continue
        top = max(float(np.max(f[:, 2])) for f in [ring] + walls + roofs) - attrs["ground_height"]
        if not low - tol <= top <= high + tol:
            out.append((oid, round(top, 3), low, high))
    return out
