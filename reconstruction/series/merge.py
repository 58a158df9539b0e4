"""The sheets' models merged into one CityJSONSeq of the series.

Each sheet's chain builds only the plots it owns (:mod:`.edges`), so the
sheets' buildings should neither repeat nor overlap. Where two sheets saw a
plot on their edge differently (each classified its own copy of the
margin) and both built it, the merge keeps one: of two buildings of
different sheets whose footprints overlap (more than ``tolerance`` m²), it
keeps the one of the sheet that holds the larger part of the two
footprints together (:func:`.edges.owner_sheet`; neither: the earlier
sheet) and names the other in the report. Ids stay as the sheets wrote
them, except an id two sheets both use, which gets its sheet's name and a
``/`` in front. The buildings are copied as they are (every LoD, their
attributes) through :mod:`reconstruction.cityjson.copied` and written as
CityJSONSeq by :class:`reconstruction.cityjson.seq.SeqWriter`.
"""

import collections
import dataclasses
from dataclasses import dataclass, field

from ..cityjson import copied as citycopied
from ..cityjson import existing, seq
from ..core.errors import InputError
from . import edges


@dataclass
class MergeReport:
    """Buildings per sheet as built and as kept; the buildings left out
    (sheet, id, the sheet whose building they overlapped); ids renamed."""
    built: dict = field(default_factory=dict)
    kept: dict = field(default_factory=dict)
    dropped: list = field(default_factory=list)
    renamed: int = 0

    @property
    def buildings(self):
        return sum(self.kept.values())


@dataclass(frozen=True)
class SheetModel:
    """A sheet's model as read: its number in the series, name and model."""
    index: int
    name: str
    model: object


def renamed(model, names):
    """``model`` with the city objects of ``names`` (old id -> new id)
    renamed, in the objects, their children and parents and the buildings."""
    if not names:
        return model

    def new(oid):
        return names.get(oid, oid)

    objects = {}
    for oid, obj in model.objects.items():
        obj = dict(obj)
        for key in ("children", "parents"):
            if key in obj:
                obj[key] = [new(o) for o in obj[key]]
        objects[new(oid)] = obj
    return dataclasses.replace(model, objects=objects, buildings=[new(b) for b in model.buildings])


def _unique_ids(sheets):
    """The sheets' models with ids shared by two sheets prefixed by the sheet name."""
    seen = collections.Counter(oid for s in sheets for oid in s.model.objects)
    out, count = [], 0
    for s in sheets:
        names = {oid: "{}/{}".format(s.name, oid) for oid in s.model.objects if seen[oid] > 1}
        count += len(names)
        out.append(dataclasses.replace(s, model=renamed(s.model, names)))
    return out, count


def overlapping(sheets, extents, tolerance=0.01):
    """The buildings to leave out: [(sheet position, building index, sheet
    position of the one kept)], by the rule above."""
    import shapely

    geoms, owner = [], []
    for k, s in enumerate(sheets):
        fps = existing.footprints(s.model)
        for b in range(len(s.model.buildings)):
            g = fps.geometry(b)
            if g is not None and not g.is_empty:
                geoms.append(g)
                owner.append((k, b))
    tree = shapely.STRtree(geoms)
    left, dropped = set(), []
    pairs = tree.query(geoms, predicate="intersects")
    for i, j in sorted(zip(pairs[0].tolist(), pairs[1].tolist())):
        if i >= j or owner[i][0] == owner[j][0] or i in left or j in left:
            continue
        if geoms[i].intersection(geoms[j]).area <= tolerance:
            continue
        both = geoms[i].union(geoms[j])
        a, b = sheets[owner[i][0]], sheets[owner[j][0]]
        parts = [(s.index, both.intersection(shapely.box(*extents[s.index])).area)
                 for s in (a, b)]
        won = edges.owner_sheet(parts)
        keep_i = won == a.index if won is not None else a.index < b.index
        lose, win = (j, i) if keep_i else (i, j)
        left.add(lose)
        dropped.append((owner[lose][0], owner[lose][1], owner[win][0]))
    return dropped


def merge_sheets(models, series, f, title=None):
    """Write the CityJSONSeq of the series to the binary file ``f``.

    ``models``: (sheet name, path of its CityJSON model) of the sheets that
    finished, in any order (they are taken in manifest order). Returns a
    :class:`MergeReport`."""
    order = {s.name: k + 1 for k, s in enumerate(series.sheets)}
    unknown = [n for n, _ in models if n not in order]
    if unknown:
        raise InputError("The series has no sheet <{}>".format(unknown[0]))
    sheets = [SheetModel(order[n], n, existing.read_model(p))
              for n, p in sorted(models, key=lambda m: order[m[0]])]
    if not sheets:
        raise InputError("No sheet finished: nothing to merge")
    sheets, count = _unique_ids(sheets)
    report = MergeReport(renamed=count)
    extents = {k + 1: s.extent for k, s in enumerate(series.sheets)}
    dropped = overlapping(sheets, extents)
    left = {(k, b) for k, b, _ in dropped}
    combined, kept, start = None, [], 0
    for k, s in enumerate(sheets):
        n = len(s.model.buildings)
        report.built[s.name] = n
        mine = [b for b in range(n) if (k, b) not in left]
        report.kept[s.name] = len(mine)
        kept.extend(start + b for b in mine)
        combined = s.model if combined is None else existing.combined(combined, s.model)
        start += n
    report.dropped = [(sheets[k].name, sheets[k].model.buildings[b], sheets[w].name)
                      for k, b, w in dropped]
    copies = citycopied.copy_buildings(combined, kept, lods="all", keep_numbering=False)
    lo = copies.extent()[0] if len(copies.vertices) else [0, 0, 0]
    writer = seq.SeqWriter(f, lo, combined.reference_system,
                           title or "Map series of {} sheets".format(len(series.sheets)),
                           copied=copies)
    try:
        writer.finish()
    finally:
        writer.close()
    return report
