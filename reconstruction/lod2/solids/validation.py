"""Validity of LoD2 solids, as val3dity checks a Solid.

:func:`validate` checks, on the millimetre geometry that is written, in bulk
over a :class:`~reconstruction.geom.solidset.SolidSet`: rings of at least three
distinct vertices, no duplicate consecutive vertices, no self-intersecting
or degenerate (zero-area) ring, faces planar within 1 mm, every edge used
exactly twice in opposite directions (closed, 2-manifold along edges,
consistently oriented), V - E + F = 2 (one fan of faces around every vertex:
2-manifold at the vertices, no handle), one connected shell, positive volume
(outward orientation); and, as val3dity (issue 11): no two vertices closer
than its 1 mm snap tolerance, no face turned downwards above the ground (shell
self-intersection), no triangle of a face's constrained Delaunay
triangulation whose normal deviates more than 20 degrees from the face's.
"""

import math

import numpy as np

from ...geom.rings import components, gather, starts
from ...geom.solidset import close_pairs, face_geometry

PLANARITY_TOL = 0.001
#: val3dity's planarity tolerance (its default): largest distance of a
#: vertex to the face's least-squares plane
VAL3DITY_PLANARITY = 0.01
#: largest angle (degrees) between a face's normal and its triangles' (val3dity's default)
NORMALS_TOL = 20.0
#: a face is turned downwards when its unit normal's z is below -DOWN_TOL:
#: walls tilted by the millimetre rounding are within 2e-3 of vertical;
#: folded slivers of straight skeletons a fraction of a millimetre wide
#: are turned far over (val3dity sees them cut their neighbours)
DOWN_TOL = 0.01


def _closed_rings(points, begin):
    """Shapely linear rings of the runs of ``points`` (one ring after the
    other) that start at the offsets ``begin``, each closed on its first point."""
    import shapely

    ends = np.r_[begin[1:], len(points)]
    closed = np.insert(points, ends, points[begin], axis=0)
    ids = np.repeat(np.arange(len(begin)), ends - begin + 1)
    return shapely.linearrings(closed, indices=ids)


def _plane_coordinates(rel, unit):
    """Points ``rel`` (relative to their face's centroid) in an orthonormal
    frame of their face's plane (``unit``: the face's unit normal, one row
    per point): x, y in the plane, z off it."""
    helper = np.zeros_like(unit)
    helper[:, 2] = 1.0
    steep = np.abs(unit[:, 2]) > 0.9
    helper[steep] = [1.0, 0.0, 0.0]
    u = np.cross(helper, unit)
    u /= np.linalg.norm(u, axis=1)[:, None]
    v = np.cross(unit, u)
    return np.column_stack([np.einsum("ij,ij->i", rel, u), np.einsum("ij,ij->i", rel, v),
                            np.einsum("ij,ij->i", rel, unit)])


def _bent_faces(rings):
    """Indices of the ``rings`` (shapely linear rings of faces in their
    plane's frame, :func:`_plane_coordinates`) with a triangle of their
    constrained Delaunay triangulation whose normal deviates from the face's
    (z) by more than :data:`NORMALS_TOL` degrees, as val3dity tests
    planarity: it triangulates each face on its fitted plane (Delaunay
    triangles depend on the projection: on a vertical wall, dropping an
    axis instead gave other triangles than val3dity's, and missed a sliver
    between the collinear corners of a crow-stepped facade). GEOS
    triangulates in x, y and keeps every vertex's z: the triangles come
    back in 3D."""
    import shapely

    tris = shapely.constrained_delaunay_triangles(shapely.polygons(rings))
    corners, owner = shapely.get_coordinates(tris, include_z=True, return_index=True)
    if not len(corners):
        return np.zeros(0, dtype=np.int64)
    q = corners.reshape(-1, 4, 3)[:, :3]          # triangles are closed rings of 4 points
    face = owner[::4]
    n = np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0])
    length = np.linalg.norm(n, axis=1)
    cos = np.abs(n[:, 2]) / np.maximum(length, 1e-300)
    bad = (length > 1e-12) & (cos < math.cos(math.radians(NORMALS_TOL)))
    return np.unique(face[bad])


def validate(ss, tol=PLANARITY_TOL):
    """Check every solid; returns a list with None (valid) or the reasons
    (joined by "; ")."""
    import shapely

    S = len(ss)
    reasons = list(ss.bad)

    def flag(solids, reason):
        for s in np.unique(solids):
            if ss.bad[s] is not None:
                continue
            if reasons[s] is None:
                reasons[s] = reason
            elif reason not in reasons[s]:
                reasons[s] += "; " + reason

    F = len(ss.face_start) - 1
    nf = np.diff(ss.solid_start)
    flag(np.nonzero(nf < 4)[0], "fewer than 4 faces")
    if F == 0:
        return reasons
    faces = face_geometry(ss)
    p, nxt, entry_face, normal, centroid, sizes = faces.points, faces.next, faces.entry_face, faces.normal, faces.centroid, faces.sizes
    ss.face_normal = normal
    face_solid = ss.face_solid
    area2 = np.linalg.norm(normal, axis=1)
    # degenerate rings: zero area
    degenerate = area2 < 2e-7
    flag(face_solid[degenerate], "degenerate ring (zero area)")
    unit = normal / np.maximum(area2, 1e-300)[:, None]
    # planarity: distance of each vertex to the least-squares plane (as
    # val3dity). The plane through the centroid normal to the Newell normal
    # bounds it: the least-squares plane's largest distance is at most the
    # root of its sum of squares, at most that of any other plane through
    # the centroid, at most sqrt(k) times that plane's largest distance; only
    # faces this bound does not clear need the least-squares fit
    rel = p - centroid[entry_face]
    dist = np.abs(np.einsum("ij,ij->i", rel, unit[entry_face]))
    maxdist = np.maximum.reduceat(dist, ss.face_start[:-1])
    fit_faces = np.nonzero((maxdist * np.sqrt(sizes) > tol) & ~degenerate)[0]
    if len(fit_faces):
        e0 = ss.face_start[fit_faces]
        k = sizes[fit_faces]
        r = rel[gather(e0, k)]
        first = starts(k)
        cov = np.add.reduceat(r[:, :, None] * r[:, None, :], first, axis=0)
        _, vecs = np.linalg.eigh(cov)
        fit = np.repeat(vecs[:, :, 0], k, axis=0)
        signed = np.einsum("ij,ij->i", r, fit)
        high, low = np.maximum.reduceat(signed, first), np.minimum.reduceat(signed, first)
        lsq = np.maximum(high, -low)
        # a face is planar within tol when some plane is that near all its
        # vertices: its Newell plane, or the least-squares plane's parallel
        # halfway between its farthest vertices on either side. A
        # millimetre-rounded crow-stepped facade can be 0.7-1.1 mm from its
        # Newell and its least-squares planes but within 0.9 mm of that
        # parallel; planar, as long as val3dity's own test (the
        # least-squares plane itself, within its 1 cm) passes too
        near = (maxdist[fit_faces] <= tol) | ((high - low) / 2 <= tol)
        far = (lsq > tol) & (~near | (lsq > VAL3DITY_PLANARITY))
        flag(face_solid[fit_faces[far]], "non-planar face (> 1 mm)")
    z = ss.vertices[:, 2]
    fz_max = np.maximum.reduceat(z[ss.rings], ss.face_start[:-1])
    fz_min = np.minimum.reduceat(z[ss.rings], ss.face_start[:-1])
    # self-intersection: quads by segment tests in numpy, larger rings with
    # shapely, all projected on their plane
    quads = np.nonzero((sizes == 4) & ~degenerate)[0]
    if len(quads):
        axis = np.argmax(np.abs(unit[quads]), axis=1)
        cols = np.array([[1, 2], [0, 2], [0, 1]])[axis]
        q = p[ss.face_start[quads][:, None] + np.arange(4)]          # (Q, 4, 3)
        q2 = np.take_along_axis(q, np.repeat(cols[:, None, :], 4, axis=1), axis=2)

        def crosses(a, b, c, d):
            def orient(u, v, w):
                return np.sign((v[:, 0] - u[:, 0]) * (w[:, 1] - u[:, 1])
                               - (v[:, 1] - u[:, 1]) * (w[:, 0] - u[:, 0]))
            return (orient(a, b, c) * orient(a, b, d) < 0) & (orient(c, d, a) * orient(c, d, b) < 0)

        bow = crosses(q2[:, 0], q2[:, 1], q2[:, 2], q2[:, 3]) | \
            crosses(q2[:, 1], q2[:, 2], q2[:, 3], q2[:, 0])
        flag(face_solid[quads[bow]], "self-intersecting ring")
    big = np.nonzero((sizes >= 5) & ~degenerate)[0]
    if len(big):
        axis = np.argmax(np.abs(unit[big]), axis=1)
        sel = np.isin(entry_face, big)
        ef = entry_face[sel]
        pos = np.searchsorted(big, ef)
        drop = axis[pos]
        pts = p[sel]
        # the face's projection plane first, the dropped axis last (is_simple
        # works in x, y; the triangulation below keeps z)
        perm = np.array([[1, 2, 0], [0, 2, 1], [0, 1, 2]])
        xyz = np.take_along_axis(pts, perm[drop], axis=1)
        rings = _closed_rings(xyz, np.searchsorted(ef, big))
        simple = shapely.is_simple(rings)
        flag(face_solid[big[~simple]], "self-intersecting ring")
        # normals deviation (val3dity's 204): the triangles of each face's
        # constrained Delaunay triangulation against the face's normal;
        # horizontal faces (grounds, flat roofs and tops: every vertex at the
        # same height) have only horizontal triangles, and need none
        j = np.nonzero(simple & (fz_max[big] > fz_min[big]))[0]
        if len(j):
            tilted = np.isin(pos, j)
            plane = _plane_coordinates(pts[tilted] - centroid[ef[tilted]], unit[ef[tilted]])
            bent = j[_bent_faces(_closed_rings(plane, np.searchsorted(pos[tilted], j)))]
            flag(face_solid[big[bent]], "non-planar face (normals deviate > 20 degrees)")
    # vertices val3dity would snap together (closer than its 1 mm snap_tol)
    vsol_entry = face_solid[entry_face]
    used = np.zeros(len(ss.vertices), dtype=bool)
    used[ss.rings] = True
    vs = np.empty(len(ss.vertices), dtype=np.int64)
    vs[ss.rings] = vsol_entry
    close = close_pairs(ss.vertices[used], vs[used])
    flag(vs[used][close[:, 0]], "vertices closer than 1 mm (snapped by val3dity)")
    # self-intersection of the shell: the faces' signed areas projected on
    # the ground plane cover every point of it zero times in total (the shell
    # is closed); the ground face covers the footprint -1 times, vertical
    # walls not at all, so faces that all face upwards cover it exactly once:
    # the roof is the graph of a function over the footprint, which meets
    # itself and the walls only along shared edges (checked below). A face
    # turned downwards above the ground is where a roof folds over itself or
    # through a wall (e.g. straight skeletons of concave footprints); walls
    # tilted by the millimetre rounding are not
    s_min = np.minimum.reduceat(fz_min, ss.solid_start[:-1][nf > 0])
    zmin = np.zeros(S, dtype=z.dtype)
    zmin[nf > 0] = s_min
    down = (unit[:, 2] < -DOWN_TOL) & (fz_max > zmin[face_solid]) & ~degenerate
    flag(face_solid[down], "face turned downwards above the ground (shell self-intersection)")
    # edges: every undirected edge exactly twice, in opposite directions
    a = ss.rings
    b = ss.rings[nxt]
    N = max(len(ss.vertices), 1)
    ukey = np.minimum(a, b) * N + np.maximum(a, b)
    forward = a < b
    order = np.argsort(ukey, kind="stable")      # (timsort: faster on these runs)
    sk = ukey[order]
    E = len(sk)
    start = np.ones(E, dtype=bool)
    start[1:] = sk[1:] != sk[:-1]
    run_start = np.nonzero(start)[0]
    run_len = np.diff(np.append(run_start, E))
    entry_run_len = np.repeat(run_len, run_len)          # in sorted order
    once = order[entry_run_len == 1]
    flag(face_solid[entry_face[once]], "edge used only once (shell not closed)")
    many = order[entry_run_len > 2]
    flag(face_solid[entry_face[many]], "edge used more than twice (non-manifold)")
    pairs = run_start[run_len == 2]
    ea, eb = order[pairs], order[pairs + 1]
    same = forward[ea] == forward[eb]
    flag(face_solid[entry_face[ea[same]]],
         "edge used twice in the same direction (faces not consistently oriented)")
    # 2-manifold at the vertices: with every edge used twice, the shell is a
    # closed surface; V - E + F = 2 holds for a genus-0 surface whose every
    # vertex has one fan of faces (a vertex with k fans lowers it by k - 1)
    vsol = np.full(N, -1, dtype=np.int64)
    vsol[a] = face_solid[entry_face]
    nv = np.bincount(vsol[vsol >= 0], minlength=S)
    ne = np.bincount(face_solid[entry_face], minlength=S) / 2.0
    euler = nv - ne + nf
    flag(np.nonzero((euler != 2) & (nf > 0))[0],
         "non-manifold vertex or handle (V - E + F != 2)")
    # one connected shell
    if len(ea):
        labels = components(F, entry_face[ea], entry_face[eb])
        lo = np.minimum.reduceat(labels, ss.solid_start[:-1][nf > 0])
        hi = np.maximum.reduceat(labels, ss.solid_start[:-1][nf > 0])
        flag(np.nonzero(nf > 0)[0][lo != hi], "more than one shell")
    # volume (divergence theorem) must be positive: outward orientation
    vol = np.einsum("ij,ij->i", normal, centroid) / 6.0
    svol = np.zeros(S)
    np.add.at(svol, face_solid, vol)
    flag(np.nonzero(svol <= 1e-9)[0], "zero or negative volume (faces oriented inwards)")
    return reasons

