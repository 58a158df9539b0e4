"""Which of the thesis's 651 aligned Delft 1961 footprints the chain misses, and why.

Run it in the mapset where demo/delft_1961.sh ran (it needs that run's maps:
current, thesis61, plots1961 and delft_gt_points from the import, plots,
aligned, footprints and delft_classes from the chain), e.g.:

    grass -c EPSG:28992 /tmp/a95/loc -e
    grass /tmp/a95/loc/PERMANENT --exec bash demo/delft_1961.sh /tmp/a95/out ../shared/data
    grass /tmp/a95/loc/PERMANENT --exec python3 testsuite/diagnose_alignment.py

(with the suite on the module path, as demo/run_demo.sh sets it up). It prints

1. the figure "thesis's aligned footprints present as aligned buildings",
   measured three ways: by the footprint's identity in v.histo.align's
   output (it keeps the footprints' categories); by exact geometry there;
   and in the model's footprints (v.histo.subdivide's output, which lod2
   turns into buildings), by geometry, a footprint counting as present when
   it differs from the thesis's by at most the area it shares with other
   current footprints (those overlaps must be given to one of them: the
   model has no overlapping footprints);
2. the same alignment (library, the chain's options) on the thesis's own
   final plots and with the thesis's year rule (year <= map year, -i);
3. every missed footprint with its cause: built in the map's year, outside
   the map raster (the thesis's plots come from the whole sheet), or by the
   classes of the map cells under it (building cells: our plot outline
   differs; landmark drawings, class church; street or water: the map
   prints no building there), with its best similarity on our plots and on
   the thesis's and the thesis plot it goes to there, flagged when that plot
   holds no ground-truth point (one of the thesis's false positives: its
   precision is 29 of 33 plots);
4. the thesis's plots less than half covered by any one of ours, with the
   classes under them, their ground-truth points and footprints.

Nothing is written. Diagnosis only: not run by make test.
"""

import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

import numpy as np  # noqa: E402
import shapely  # noqa: E402

from reconstruction.align.stage import AlignmentConfig, align, construction_years  # noqa: E402

YEAR, BUFFER, OVERLAP = 1961, 10.0, 0.6     # the chain's options (the thesis's Table B.3)
BUILDING, WATER, STREET, LANDMARK = 1, 3, 4, 5  # classes of the Delft training points
NAMES = {BUILDING: "building", 2: "text", WATER: "water", STREET: "street", LANDMARK: "church",
         6: "symbol"}
#: a missed footprint "on a landmark drawing" when at least this share of its cells is class 5
LANDMARK_SHARE = 0.1


def _same(a, b, tolerance):
    """Whether geometries a and b differ by at most ``tolerance`` (area, per pair)."""
    return shapely.area(shapely.symmetric_difference(a, b)) <= tolerance


def thesis_footprints(current, thesis):
    """Indices into ``current`` of the thesis's aligned footprints (identical geometry)."""
    a, b = shapely.STRtree(current).query(thesis, predicate="intersects")
    same = _same(thesis[a], current[b], 1e-6 * shapely.area(thesis[a]))
    assert np.array_equal(np.unique(a[same]), np.arange(len(thesis)))
    return np.unique(b[same])


def shared_with_neighbours(current, which):
    """Area each footprint ``which`` of ``current`` shares with the other footprints."""
    tree = shapely.STRtree(current)
    a, b = tree.query(current[which], predicate="intersects")
    other = which[a] != b
    shared = np.zeros(len(which))
    np.add.at(shared, a[other], shapely.area(shapely.intersection(
        current[which[a[other]]], current[b[other]])))
    return shared


def present(reference, tolerance, geoms):
    """Which ``reference`` geometries have one among ``geoms`` within ``tolerance`` of them."""
    found = np.zeros(len(reference), dtype=bool)
    if len(geoms):
        a, b = shapely.STRtree(geoms).query(reference, predicate="intersects")
        found[np.unique(a[_same(reference[a], geoms[b], tolerance[a])])] = True
    return found


class Cells:
    """The classified map: the classes of the cells inside a geometry."""

    def __init__(self, classes, region):
        self.classes = classes
        self.extent = shapely.box(region["w"], region["s"], region["e"], region["n"])
        xs = region["w"] + (np.arange(region["cols"]) + 0.5) * region["ewres"]
        ys = region["n"] - (np.arange(region["rows"]) + 0.5) * region["nsres"]
        self.x, self.y = np.meshgrid(xs, ys)

    def shares(self, geom):
        """(share of ``geom`` inside the map, {class: share of its cells})."""
        inside = shapely.area(shapely.intersection(geom, self.extent)) / geom.area
        values = self.classes[shapely.contains_xy(geom, self.x, self.y)]
        values = values[np.isfinite(values)]
        if not len(values):
            return inside, {}
        return inside, {int(k): float(np.mean(values == k)) for k in np.unique(values)}


def _classes(shares):
    return ", ".join("{} {:.0%}".format(NAMES.get(c, c), s) for c, s in sorted(shares.items()))


def best_similarity(plots, footprint):
    """The highest similarity (Eq. 3.9 on the buffered plot) of a footprint with ``plots``."""
    grown = shapely.buffer(plots, BUFFER)
    sim = shapely.area(shapely.intersection(grown, footprint)) / np.minimum(
        footprint.area, shapely.area(grown))
    return float(sim.max())


def cause(year, inside, shares):
    if year >= YEAR:
        return "built in {} itself (the thesis counted year <= map year: -i)".format(YEAR)
    if inside < 0.5:
        return "outside the map raster (the thesis's plots come from the whole sheet)"
    if shares.get(BUILDING, 0) >= 0.5:
        return "on building cells: our plot outline differs from the thesis's"
    if shares.get(LANDMARK, 0) >= LANDMARK_SHARE:
        return "on a landmark drawing (class church, not the building class)"
    return "the map prints no building there (street or water cells)"


def aligned_share(plots, cats, current, years, thesis, include_year=False):
    config = AlignmentConfig(year=YEAR, buffer=BUFFER, overlap=OVERLAP,
                             include_year=include_year)
    result = align(plots, cats, current, years, config)
    return result, np.isin(thesis, result.aligned)


def read_maps():
    import grass.script as gs

    from reconstruction import grassio

    maps = {}
    for name in ("current", "thesis61", "plots1961", "plots", "aligned", "footprints"):
        geoms, columns = grassio.read_areas(name)
        maps[name] = (np.array(geoms, dtype=object), columns)
    maps["gt_points"] = shapely.points(grassio.read_points("delft_gt_points")[0])
    info = gs.parse_command("r.info", map="delft_classes", flags="g")
    region = dict(n=float(info["north"]), s=float(info["south"]), e=float(info["east"]),
                  w=float(info["west"]), nsres=float(info["nsres"]),
                  ewres=float(info["ewres"]), rows=int(info["rows"]), cols=int(info["cols"]))
    env = dict(os.environ, GRASS_REGION=gs.region_env(raster="delft_classes"))
    classes = grassio.read_raster("delft_classes", env=env)
    return maps, Cells(classes, region)


def report_figure(maps, current, cats, thesis, pct):
    print("1. The thesis's aligned footprints present as aligned buildings (chain's run)")
    aligned, al_cols = maps["aligned"]
    by_cat = np.isin(cats[thesis], al_cols["cat"])
    exact = present(current[thesis], 1e-6 * shapely.area(current[thesis]), aligned)
    shared = shared_with_neighbours(current, thesis)
    tolerance = shared + 1e-6 * shapely.area(current[thesis])
    footprints, fp_cols = maps["footprints"]
    model = footprints[np.array(fp_cols["source"]) == "aligned"]
    in_model = present(current[thesis], tolerance, model)
    print("  v.histo.align output, by the footprint's identity (category): " + pct(by_cat.sum()))
    print("  v.histo.align output, by exact geometry:                      " + pct(exact.sum()))
    print("  model footprints (subdivide output), geometry within the area shared with")
    print("    neighbouring footprints:                                    " + pct(
        in_model.sum()))
    print("  {} of the thesis's footprints share area with a neighbour ({:.2f} m2 in all, "
          "at most {:.1%} of one)".format(int((shared > 0).sum()), shared.sum(),
                                          (shared / shapely.area(current[thesis])).max()))


def report_runs(maps, current, years, thesis, pct):
    """Section 2; returns, per run, which of the thesis's footprints are aligned, and the
    thesis plot each of them goes to on the thesis's plots (with its year rule)."""
    print("\n2. The same alignment (library, year={} buffer={:g} overlap={:g})".format(
        YEAR, BUFFER, OVERLAP))
    runs, thesis_plot = {}, {}
    for label, name in (("our plots", "plots"), ("the thesis's final plots", "plots1961")):
        plots, columns = maps[name]
        for include in (False, True):
            result, found = aligned_share(plots, columns["cat"], current, years, thesis,
                                          include)
            runs[label, include] = found
            print("  {:<26} {:<13} {} aligned, of them the thesis's: {}".format(
                label, "year <= map" if include else "year < map", len(result.aligned),
                pct(found.sum())))
            if name == "plots1961" and include:
                thesis_plot = dict(zip(result.aligned.tolist(), result.plot.tolist()))
    return runs, thesis_plot


def report_missed(maps, cells, current, cats, years, thesis, runs, thesis_plot, empty):
    found, on_thesis = runs["our plots", False], runs["the thesis's final plots", False]
    missed = np.flatnonzero(~found)
    print("\n3. The {} missed on our plots (year < map year), by cause".format(len(missed)))
    plots, tplots = maps["plots"][0], maps["plots1961"][0]
    rows, counts, on_empty = [], {}, 0
    for k in missed:
        geom = current[thesis[k]]
        inside, shares = cells.shares(geom)
        why = cause(years[thesis[k]], inside, shares)
        counts[why] = counts.get(why, 0) + 1
        plot = thesis_plot.get(thesis[k])
        on_empty += plot in empty
        rows.append((why, "    cat {:>5} built {:4.0f} {:4.0f} m2  similarity ours {:.2f} thesis "
                          "{:.2f} (plot {}{}){}  inside map {:.0%}  cells {}".format(
                              cats[thesis[k]], years[thesis[k]], geom.area,
                              best_similarity(plots, geom), best_similarity(tplots, geom),
                              "none" if plot is None else plot,
                              ", no ground-truth point" if plot in empty else "",
                              "" if on_thesis[k] else " (missed on the thesis's plots too)",
                              inside, _classes(shares))))
    for why, count in sorted(counts.items(), key=lambda item: -item[1]):
        print("  {:>3}  {}".format(count, why))
        for row in sorted(r for w, r in rows if w == why):
            print(row)
    print("  {} of the {} lie on thesis plots that hold no ground-truth building point "
          "(plots {}: the thesis's false positives)".format(
              on_empty, len(missed), ", ".join(str(c) for c in sorted(empty))))


def report_plots(maps, cells, thesis_plot):
    print("\n4. The thesis's plots less than half covered by any one of ours")
    plots = maps["plots"][0]
    tplots, columns = maps["plots1961"]
    xy = shapely.get_coordinates(maps["gt_points"])
    per_plot = {}
    for plot in thesis_plot.values():
        per_plot[plot] = per_plot.get(plot, 0) + 1
    for cat, plot in zip(columns["cat"], tplots):
        cover = shapely.area(shapely.intersection(plots, plot)) / plot.area
        if cover.max() >= 0.5:
            continue
        inside, shares = cells.shares(plot)
        points = int(shapely.contains_xy(plot, xy[:, 0], xy[:, 1]).sum())
        print("  plot {:>2}: {:5.0f} m2, {:.0%} covered by one of ours ({:.0%} by all), inside "
              "map {:.0%}, {} ground-truth points, {} of the thesis's footprints, cells "
              "{}".format(cat, plot.area, cover.max(), cover.sum(), inside, points,
                          per_plot.get(cat, 0), _classes(shares)))


def main():
    maps, cells = read_maps()
    current, columns = maps["current"]
    cats = np.array(columns["cat"])
    years = construction_years(columns["bouwjaar"])
    thesis = thesis_footprints(current, maps["thesis61"][0])
    n = len(thesis)

    def pct(k):
        return "{} of {} ({:.1f} %)".format(int(k), n, 100.0 * k / n)

    tplots, tcols = maps["plots1961"]
    xy = shapely.get_coordinates(maps["gt_points"])
    empty = {c for c, p in zip(tcols["cat"], tplots)
             if not shapely.contains_xy(p, xy[:, 0], xy[:, 1]).any()}
    report_figure(maps, current, cats, thesis, pct)
    runs, thesis_plot = report_runs(maps, current, years, thesis, pct)
    report_missed(maps, cells, current, cats, years, thesis, runs, thesis_plot, empty)
    report_plots(maps, cells, thesis_plot)


if __name__ == "__main__":
    main()
