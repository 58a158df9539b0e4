"""LoD2 solids: footprint + heights + roof -> one closed, valid shell each, in bulk.

:func:`build_solids` builds the roofs of many buildings
(:func:`reconstruction.lod2.roofs.plan.make_roofs`), puts walls and a ground face
under them, rounds every shell to the millimetre grid as a
:class:`~reconstruction.geom.solidset.SolidSet` and validates it
(:func:`reconstruction.lod2.solids.validation.validate`). It never returns an invalid
solid: a roof that fails falls back to a simpler type (stepped -> gable ->
mansard -> flat), and a footprint whose flat prism still fails is dropped
and counted. A pitched roof on a footprint of more than
:data:`~reconstruction.lod2.solids.vertex_budget.MAX_ROOF_VERTICES` vertices stands on
its simplified outline (:mod:`~reconstruction.lod2.solids.vertex_budget`).
"""

import threading
from dataclasses import dataclass

import numpy as np

from ...core.processes import forked_pool
from ...core.work_limits import check_crow_steps
from ...geom.solidset import SolidSet, concat, from_parts, shell_parts, take
from ..outlines import outline_facts
from ..roofs.model import RoofConfig
from ..roofs.plan import make_roofs
from .validation import validate
from .vertex_budget import MAX_ROOF_VERTICES, needs_budget, simplify_rings

#: Fallback chain when a roof type fails validation.
FALLBACK = {"stepped": "gable", "neck": "gable", "bell": "gable", "spout": "gable",
            "half_hip": "gable", "gambrel": "gable", "cornice": "gable", "pyramid": "hip",
            "shed": "flat", "gable": "mansard", "hip": "mansard", "mansard": "flat", "flat": None}


class Buildings:
    """What :func:`build_solids` builds: one entry per footprint ring.

    ``footprints``: cleaned counter-clockwise rings (n, 2) in absolute
    coordinates (see :func:`reconstruction.lod2.outlines.clean_rings`);
    ``ground``, ``eaves``, ``attic``: terrain elevation, wall height above
    it and roof height above the eaves (m); ``roof_types``: the requested
    types; ``uniforms``: (B, 3) uniform numbers in [0, 1) (see
    :func:`reconstruction.lod2.roofs.plan.make_roofs`); ``street``: optional street
    edge index per footprint; ``shared``: optional per footprint a boolean
    array, True for its edges shared with a neighbour (no gable end, hip end
    or stepped facade goes there).
    """

    __slots__ = ("footprints", "ground", "eaves", "attic", "roof_types", "uniforms", "street",
                 "shared")

    def __init__(self, footprints, ground, eaves, attic, roof_types, uniforms, street=None,
                 shared=None):
        self.footprints = list(footprints)
        self.ground = np.asarray(ground, dtype=float)
        self.eaves = np.asarray(eaves, dtype=float)
        self.attic = np.asarray(attic, dtype=float)
        self.roof_types = np.array(roof_types, dtype=object)
        self.uniforms = np.asarray(uniforms, dtype=float).reshape(len(self.footprints), 3)
        self.street = None if street is None else list(street)
        self.shared = None if shared is None else list(shared)

    def __len__(self):
        return len(self.footprints)

    def subset(self, idx):
        """The buildings ``idx`` (indices or a slice)."""
        def pick(values):
            if isinstance(idx, slice):
                return values[idx]
            return [values[i] for i in idx]

        return Buildings(pick(self.footprints), self.ground[idx], self.eaves[idx],
                         self.attic[idx], self.roof_types[idx], self.uniforms[idx],
                         None if self.street is None else pick(self.street),
                         None if self.shared is None else pick(self.shared))


@dataclass(frozen=True, order=True)
class Fallback:
    """A roof that failed validation and fell back to the next type of :data:`FALLBACK`."""

    #: index of the building
    index: int
    #: the roof type that failed
    kind: str
    #: why (the validator's reasons)
    reason: str


@dataclass(frozen=True)
class BuiltSolids:
    """What :func:`build_solids` returns."""

    #: the valid solids, one per kept building, in building order
    solids: SolidSet
    #: the buildings kept (indices)
    kept: np.ndarray
    #: the roof type each kept building got after any fallback
    types: np.ndarray
    #: every roof that failed and fell back, by building
    log: list


def assemble(xy, roof, ground, eaves):
    """One shell from a footprint (local coordinates), a
    :class:`~reconstruction.lod2.roofs.model.Roof` and heights.

    Returns ``(vertices, faces)`` with vertices (V, 3) in local x, y and
    absolute z, faces as lists of indices, or None when the roof's boundary
    does not follow the footprint.
    """
    n = len(xy)
    rv = roof.vertices
    verts = np.empty((n + len(rv), 3))
    verts[:n, :2] = xy
    verts[:n, 2] = ground
    verts[n:, :2] = rv[:, :2]
    verts[n:, 2] = rv[:, 2] + ground + eaves
    verts[n:2 * n, :2] = xy          # exact footprint under the eaves
    faces = [list(range(n - 1, -1, -1))]
    if roof.boundary:
        faces.extend([i, (i + 1) % n, n + (i + 1) % n, n + i] for i in range(n))
    elif roof.chains is not None:
        faces.extend([i, (i + 1) % n] + [n + k for k in reversed(chain)]
                     for i, chain in enumerate(roof.chains))
    else:
        nxt = {}
        directed = set()
        for f in roof.faces:
            for a, b in zip(f, f[1:] + f[:1]):
                directed.add((a, b))
        for a, b in directed:
            if (b, a) not in directed and abs(rv[a, 2]) < 1e-9 and abs(rv[b, 2]) < 1e-9:
                if a in nxt:
                    return None
                nxt[a] = b
        for i in range(n):
            chain = [i]
            target = (i + 1) % n
            while chain[-1] != target:
                k = nxt.get(chain[-1])
                if k is None or len(chain) > len(rv):
                    return None
                chain.append(k)
            faces.append([i, target] + [n + k for k in reversed(chain)])
    faces.extend([n + k for k in f] for f in roof.faces)
    return verts, faces


def group_parts(group, origins, ground, eaves):
    """Flat arrays ``(vertices, rings, face sizes, face owners)`` of the
    solids of one :class:`~reconstruction.lod2.roofs.model.RoofGroup`: ground,
    walls and roof of every footprint in one numpy pass. The walls are
    quads, or pentagons along the footprint edges whose roof boundary has a
    vertex between the edge's ends (``wall_mid``)."""
    idx = group.index
    xy = group.xy
    G, n, _ = xy.shape
    extra = group.vertices                # roof vertices past the footprint
    C = extra.shape[1]
    Vb = 2 * n + C
    org = origins[idx]
    z0 = np.asarray(ground, dtype=float)[idx]
    z1 = z0 + np.asarray(eaves, dtype=float)[idx]
    v = np.empty((G, Vb, 3))
    v[:, :n, :2] = xy + org[:, None, :]
    v[:, :n, 2] = z0[:, None]
    v[:, n:2 * n, :2] = v[:, :n, :2]
    v[:, n:2 * n, 2] = z1[:, None]
    v[:, 2 * n:, :2] = extra[..., :2] + org[:, None, :]
    v[:, 2 * n:, 2] = extra[..., 2] + z1[:, None]
    base = (np.arange(G) * Vb)[:, None]
    j = np.arange(n)
    ground_r = (base + j[::-1]).ravel()
    mid = group.wall_mid
    if mid is None:
        walls_r = (base[:, :, None] + np.stack([j, (j + 1) % n, n + (j + 1) % n, n + j],
                                               axis=1)).ravel()
        wall_sizes = np.full(G * n, 4)
    else:
        w = np.empty((G, n, 5), dtype=np.int64)
        w[..., 0], w[..., 1], w[..., 2] = j, (j + 1) % n, n + (j + 1) % n
        w[..., 3] = np.where(mid >= 0, n + mid, n + j)
        w[..., 4] = n + j
        walls_r = (base[:, :, None] + w)[np.broadcast_to(
            (np.arange(5) < 4) | (mid >= 0)[..., None], w.shape)]
        wall_sizes = np.where(mid >= 0, 5, 4).ravel()
    cnt = group.counts
    K = group.faces.shape[2]
    use = cnt >= 3
    mask = (np.arange(K) < cnt[..., None]) & use[..., None]
    roof_r = (base[:, :, None] + n + group.faces)[mask]
    roof_sizes = cnt[use]
    roof_owner = np.broadcast_to(idx[:, None], cnt.shape)[use]
    rings = np.concatenate([ground_r, walls_r, roof_r])
    sizes = np.concatenate([np.full(G, n), wall_sizes, roof_sizes])
    owner = np.concatenate([idx, np.repeat(idx, n), roof_owner])
    return v.reshape(-1, 3), rings, sizes, owner


# ---------------------------------------------------------------------------
# Buildings in bulk, with fallback
# ---------------------------------------------------------------------------

def build_solids(buildings, config=None, nprocs=1):
    """Valid LoD2 solids of many :class:`Buildings` with the roof parameters
    ``config`` (a :class:`~reconstruction.lod2.roofs.model.RoofConfig`).

    Returns the :class:`BuiltSolids`. The buildings are built :data:`STEP`
    at a time. With ``nprocs`` > 1 the work is shared by that many
    processes, each given whole steps (fewer processes when there are fewer
    steps): the calling process builds the first chunk itself,
    forked processes build the others from the input they inherit (only
    their results are sent back). The pitched roofs of concave footprints
    (CGAL's straight skeleton, which releases the interpreter while it runs)
    are built in a thread beside the others. The result depends on neither:
    every building depends only on its own footprint, heights, type and
    uniform numbers.
    """
    config = config or RoofConfig()
    check_crow_steps(config.step)
    B = len(buildings)
    steps = -(-B // STEP)
    nprocs = min(int(nprocs), steps)
    if nprocs <= 1:
        return _build_in_steps(buildings, config)

    # whole steps per process, so that every building is built in the same
    # step whatever nprocs is (the numbering of its vertices depends on its step)
    bounds = np.minimum(np.linspace(0, steps, nprocs + 1).round().astype(int) * STEP, B)
    _CHUNKS[:] = [(bounds, buildings, config)]
    try:
        with forked_pool(nprocs - 1) as pool:
            others = pool.map_async(_build_chunk, range(1, nprocs))
            results = [_build_chunk(0)] + others.get()
    finally:
        _CHUNKS[:] = []
    return _merge([(np.arange(a, b), r) for a, b, r in zip(bounds[:-1], bounds[1:], results)])


#: The work of build_solids over several processes, inherited by its forked processes.
_CHUNKS = []


def _build_chunk(k):
    """Build chunk ``k`` of the work in :data:`_CHUNKS`."""
    bounds, buildings, config = _CHUNKS[0]
    return _build_in_steps(buildings.subset(slice(bounds[k], bounds[k + 1])), config)


#: buildings built at a time by one process (issue 33, item 9): the working
#: arrays of roofs, faces and validation take about 20 KB per building, so
#: that a city built at once grew by 1.3 GB per 60,000 buildings; in steps
#: they stay under 50 MB, and the solids are the same (every building
#: depends only on its own input)
STEP = 2000


def _build_in_steps(buildings, config):
    """:func:`_build_beside` on :data:`STEP` buildings at a time, merged (the
    steps of :func:`build_solids` start at multiples of :data:`STEP`)."""
    if len(buildings) <= STEP:
        return _build_beside(buildings, config)
    return _merge(list(_steps(buildings, config)))


def build_solids_steps(buildings, config=None, nprocs=1):
    """:func:`build_solids` step by step, for a writer that streams (issue
    33, item 9: memory bounded by a step, not by the city): yields
    ``(indices, built)`` for every :data:`STEP` buildings in turn, ``built``
    the :class:`BuiltSolids` of the buildings ``indices`` (its ``kept`` and
    log indices among all the buildings). With ``nprocs`` > 1 that many
    steps are built at a time, one by this process, the others by forked
    processes. The solids are those of :func:`build_solids`."""
    for idx, built in _steps(buildings, config or RoofConfig(), nprocs):
        yield idx, _merge([(idx, built)])


def _steps(buildings, config, nprocs=1):
    """``(indices, built)`` of every step in turn, ``built`` indexing the
    step's own buildings."""
    check_crow_steps(config.step)
    B = len(buildings)
    bounds = np.minimum(np.arange(-(-B // STEP) + 1) * STEP, B)
    steps = len(bounds) - 1
    nprocs = min(int(nprocs), steps)
    if nprocs <= 1:
        for a, b in zip(bounds[:-1], bounds[1:]):
            yield np.arange(a, b), _build_beside(buildings.subset(slice(a, b)), config)
        return
    _CHUNKS[:] = [(bounds, buildings, config)]
    try:
        with forked_pool(nprocs - 1) as pool:
            for first in range(0, steps, nprocs):
                ks = list(range(first, min(first + nprocs, steps)))
                others = pool.map_async(_build_chunk, ks[1:])
                for k, built in zip(ks, [_build_chunk(ks[0])] + others.get()):
                    yield np.arange(bounds[k], bounds[k + 1]), built
    finally:
        _CHUNKS[:] = []


def _build_beside(buildings, config):
    """:func:`build_solids` in one process: the skeleton roofs in a thread beside the others."""
    if len(buildings):
        concave = ~outline_facts(buildings.footprints).convex
    else:
        concave = np.zeros(0, bool)
    skeleton = concave & (buildings.roof_types != "flat") & (buildings.attic > 1e-3)
    if not skeleton.any() or skeleton.all():
        return _build(buildings, config)
    parts = [np.nonzero(skeleton)[0], np.nonzero(~skeleton)[0]]
    results = [None, None]

    def run(k):
        try:
            results[k] = _build(buildings.subset(parts[k]), config)
        except BaseException as error:  # re-raised below
            results[k] = error

    worker = threading.Thread(target=run, args=(0,))
    worker.start()
    run(1)
    worker.join()
    for r in results:
        if isinstance(r, BaseException):
            raise r
    return _merge(list(zip(parts, results)))


def _merge(parts):
    """One :class:`BuiltSolids` from results on subsets of the buildings,
    ``[(building indices, result), ...]``: solids in building order, the log
    by building."""
    sets, kept, types, log = [], [], [], []
    for idx, built in parts:
        ss, k, t, lg = built.solids, built.kept, built.types, built.log
        sets.append(ss)
        kept.append(idx[k])
        types.append(t)
        log.extend(Fallback(int(idx[f.index]), f.kind, f.reason) for f in lg)
    kept = np.concatenate(kept)
    types = np.concatenate(types)
    perm = np.argsort(kept, kind="stable")
    merged = concat(sets)
    if np.any(perm != np.arange(len(perm))):
        merged, kept, types = take(merged, perm), kept[perm], types[perm]
    return BuiltSolids(merged, kept, types, sorted(log, key=lambda entry: entry.index))


def _build(buildings, config):
    """:func:`build_solids` in one thread: roofs, walls, validation, and
    again with the next type of :data:`FALLBACK` for the roofs that failed."""
    B = len(buildings)
    footprints = buildings.footprints
    street, shared = buildings.street, buildings.shared
    origins = np.array([xy[0] for xy in footprints], dtype=float).reshape(B, 2)
    local = [xy - o for xy, o in zip(footprints, origins)]
    types = buildings.roof_types.copy()
    uniforms = buildings.uniforms
    ground, eaves, attic = buildings.ground, buildings.eaves, buildings.attic
    accepted = []
    log = []
    # pitched roofs on footprints over the vertex budget stand on simplified
    # outlines (flat ones, also after a fallback, keep every vertex)
    over = np.nonzero(needs_budget(local, types))[0]
    simple = dict(zip(over.tolist(), simplify_rings([local[i] for i in over]).rings))
    for i, ring in simple.items():
        if ring is None:
            log.append(Fallback(i, types[i], "footprint of {} vertices cannot be simplified to "
                                "{}".format(len(local[i]), MAX_ROOF_VERTICES)))
            types[i] = "flat"
    todo = np.arange(B)
    while len(todo):
        T = len(todo)
        rings = [simple[i] if i in simple and types[i] != "flat" else local[i] for i in todo]
        # street and shared edges index the footprint's own ring, not a simplified one
        own = [rings[k] is local[i] for k, i in enumerate(todo)]
        roofs = make_roofs(rings, types[todo], attic[todo], uniforms[todo],
                           None if street is None else
                           [street[i] if o else None for o, i in zip(own, todo)], config,
                           None if shared is None else
                           [shared[i] if o else None for o, i in zip(own, todo)])
        types[todo] = roofs.kinds
        inbulk = np.zeros(T, dtype=bool)
        for g in roofs.groups:
            inbulk[g.index] = True
        shells, bad = [None] * T, [None] * T
        for k in np.nonzero(~inbulk)[0]:
            roof = roofs.single[k]
            i = todo[k]
            if roof is not None and roof.faces:
                shells[k] = assemble(rings[k], roof, float(ground[i]), float(eaves[i]))
                if shells[k] is None:
                    bad[k] = "roof boundary does not follow the footprint"
            else:
                bad[k] = "roof cannot be built on this footprint"
        org = origins[todo]
        parts = [shell_parts(shells, org, np.arange(T))]
        parts.extend(group_parts(g, org, ground[todo], eaves[todo]) for g in roofs.groups)
        ss = from_parts(parts, T, bad)
        reasons = validate(ss)
        good = np.array([r is None for r in reasons], dtype=bool)
        if good.any():
            accepted.append((take(ss, np.nonzero(good)[0]), todo[good]))
        retry = []
        for k in np.nonzero(~good)[0]:
            i = todo[k]
            log.append(Fallback(int(i), types[i], reasons[k]))
            nxt_type = FALLBACK.get(types[i])
            if nxt_type is not None:
                types[i] = nxt_type
                retry.append(i)
        todo = np.array(retry, dtype=int)
    if not accepted:
        return BuiltSolids(concat([]), np.zeros(0, dtype=int), types[:0], log)
    kept = np.concatenate([a[1] for a in accepted])
    merged = concat([a[0] for a in accepted])
    perm = np.argsort(kept, kind="stable")
    return BuiltSolids(take(merged, perm), kept[perm], types[kept[perm]], log)
