"""Helpers shared by the module tests (on sys.path through the root conftest.py)."""


def run_module(module, flags="", **kwargs):
    """Run a GRASS module; return its exit code, standard output and error as text."""
    import grass.script as gs

    proc = gs.start_command(module, flags=flags, stdout=gs.PIPE, stderr=gs.PIPE, **kwargs)
    out, err = proc.communicate()
    return proc.returncode, gs.decode(out), gs.decode(err)


def key_values(stdout):
    """The key=value lines a module prints (flag -g, -v, ...) as a dict of strings."""
    return dict(line.split("=", 1) for line in stdout.splitlines() if "=" in line)


def run_in_latlong(dbase, name, *command):
    """Run a command in a lat/long (EPSG:4326) location ``name`` under ``dbase``.

    The location is made on first use; the command runs in its own GRASS
    session (not the test session). Returns the location path and the
    finished process (text output).
    """
    import os
    import subprocess

    location = os.path.join(dbase, name)
    if not os.path.isdir(location):
        subprocess.run(["grass", "-c", "EPSG:4326", location, "-e"], check=True,
                       capture_output=True)
    env = dict(os.environ)
    env.pop("GISRC", None)
    proc = subprocess.run(["grass", os.path.join(location, "PERMANENT"), "--exec"] + list(command),
                          capture_output=True, text=True, env=env)
    return location, proc


def timed_children(runs, fn):
    """As :func:`timed` for work done by child processes (GRASS modules): the
    median wall time, the median CPU time of the children (user + system) and
    the last result."""
    import resource
    import statistics
    import time

    def children():
        r = resource.getrusage(resource.RUSAGE_CHILDREN)
        return r.ru_utime + r.ru_stime

    wall, cpu, result = [], [], None
    for _ in range(runs):
        w, c = time.perf_counter(), children()
        result = fn()
        wall.append(time.perf_counter() - w)
        cpu.append(children() - c)
    return statistics.median(wall), statistics.median(cpu), result


def timed(runs, fn):
    """Run ``fn()`` ``runs`` times: the median wall time, the median CPU time
    (which a busy shared machine inflates less) and the last result."""
    import statistics
    import time

    wall, cpu, result = [], [], None
    for _ in range(runs):
        w, c = time.perf_counter(), time.process_time()
        result = fn()
        wall.append(time.perf_counter() - w)
        cpu.append(time.process_time() - c)
    return statistics.median(wall), statistics.median(cpu), result


def import_delft_alignment(shared_data, heights=False):
    """Import the alignment fixture of Delft into the current mapset; never written elsewhere.

    ``current``: the 12,567 current footprints of Delft, each with the construction year
    (``bouwjaar``) of the identical footprint among those the thesis aligned for 1961 and
    for 1880, NULL where there is none (their own table did not survive); ``plots1961``,
    ``plots1880``: the thesis's plots. Returns the categories in ``current`` of the
    thesis's aligned footprints (``thesis1961``, ``thesis1880``) and ``years``
    ({cat: year}).

    ``heights``: also give ``current`` the thesis's measured height columns
    (ground_0_2, roof_0_25, roof_0_99, i.e. ground-0.2, roof-0.25, roof-0.99 of
    the 3D BAG) where the footprint is one of the thesis's aligned 1880
    footprints (a building that stood in 1880 and stands today has today's
    height), NULL elsewhere.
    """
    import os

    import numpy as np
    import shapely

    import grass.script as gs

    from reconstruction import grassio

    s61 = os.path.join(shared_data, "delft_1961_subset")
    s80 = os.path.join(shared_data, "delft_1880")
    for path, output, extra in [
            (os.path.join(s61, "input", "building_footprints_delft.shp"), "current", {}),
            (os.path.join(s61, "thesis_output", "aligned_entities_current_dataset.shp"),
             "thesis61", {}),
            (os.path.join(s61, "thesis_output", "final_plots_delft_1961.shp"), "plots1961", {}),
            (os.path.join(s80, "final_plots_delft_1880.shp"), "plots1880", {}),
            # its table has a column "index", an SQL keyword: renamed
            (os.path.join(s80, "final_all_footprints.shp"), "final1880", {
                "columns": "cat,idx,feaid,bouwjaar,pand_id,r025,r075,r099,g00,g01,g02,g03,g04,"
                           "g05,nrg"})]:
        gs.run_command("v.in.ogr", input=path, output=output, flags="o", quiet=True,
                       overwrite=True, **extra)
    current, columns = grassio.read_areas("current")
    current = np.array(current, dtype=object)
    thesis, years, measured = {}, {}, {}
    for year, name, keep in ((1961, "thesis61", None), (1880, "final1880", "pand_id")):
        geoms, cols = grassio.read_areas(name)
        rows = [i for i in range(len(geoms)) if keep is None or cols[keep][i]]
        ref = np.array([geoms[i] for i in rows], dtype=object)
        a, b = shapely.STRtree(current).query(ref, predicate="intersects")
        same = shapely.area(shapely.symmetric_difference(ref[a], current[b])) < \
            1e-6 * shapely.area(ref[a])
        # every one of them is there, exactly once
        assert np.array_equal(np.unique(a[same]), np.arange(len(ref)))
        assert np.bincount(a[same]).max() == 1
        thesis[year] = {columns["cat"][j] for j in b[same]}
        for i, j in zip(a[same], b[same]):
            value = int(cols["bouwjaar"][rows[i]])
            assert years.setdefault(columns["cat"][j], value) == value
            if year == 1880:
                measured[columns["cat"][j]] = tuple(
                    float(cols[c][rows[i]]) for c in ("g02", "r025", "r099"))
    names = ("ground_0_2", "roof_0_25", "roof_0_99")
    gs.run_command("v.db.addcolumn", map="current", quiet=True, columns=",".join(
        ["bouwjaar integer"] + ["{} double precision".format(n) for n in names if heights]))
    sql = grassio.temp_file(".sql")
    with open(sql, "w") as f:
        f.write("BEGIN TRANSACTION;\n")
        f.writelines("UPDATE current SET bouwjaar = {} WHERE cat = {};\n".format(y, c)
                     for c, y in sorted(years.items()))
        if heights:
            f.writelines("UPDATE current SET {} WHERE cat = {};\n".format(
                ", ".join("{} = {!r}".format(n, v) for n, v in zip(names, h)), c)
                for c, h in sorted(measured.items()))
        f.write("COMMIT;\n")
    gs.run_command("db.execute", input=sql, quiet=True)
    return {"thesis1961": thesis[1961], "thesis1880": thesis[1880], "years": years}


def failing_tool_env(directory, *tools):
    """An environment whose PATH finds a fake of each GRASS tool ``tools`` first in
    ``directory``: it prints an ERROR: line and fails, as a tool that breaks
    inside a module would. Pass it as ``env=`` to the module run."""
    import os

    os.makedirs(str(directory), exist_ok=True)
    for tool in tools:
        path = os.path.join(str(directory), tool)
        with open(path, "w") as f:
            f.write("#!/bin/sh\necho \"ERROR: {} failed on purpose (test)\" >&2\nexit 1\n".format(
                tool))
        os.chmod(path, 0o755)
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(directory), env["PATH"]])
    return env


#: the kinds of ``reconstruction.subdivide.stage.invariant_violations``: the acceptance runs
#: print each with its count (0 included)
INVARIANTS = ("invalid", "outside", "concave", "sliver", "no_street", "no_frontage", "wedge",
              "overlap")


def invariant_counts(bad):
    """``invariant_violations``'s result as text: every kind with its count."""
    kinds = INVARIANTS + tuple(sorted(set(bad) - set(INVARIANTS)))
    return ", ".join("{} {}".format(kind, len(bad.get(kind, ()))) for kind in kinds)


def plot_of_point(footprints, plots, cats):
    """The category of the plot holding each footprint's representative point (None: none)."""
    import numpy as np
    import shapely

    points = shapely.point_on_surface(np.array(footprints, dtype=object))
    at, plot = shapely.STRtree(plots).query(points, predicate="within")
    out = [None] * len(footprints)
    for i, j in zip(at, plot):
        out[int(i)] = cats[int(j)]
    return out


def plausibility(plots, cats, real, footprints, real_plot=None, plot=None):
    """Footprints against real ones, over the plots at least half covered by the real ones:
    the medians of (count x covered share / real count) and of (median area / median real
    area). A footprint's plot is given (``real_plot``, ``plot``) or, by default, the plot
    holding its representative point (issue 14's definition). Returns (plots used,
    count ratio, area ratio)."""
    import numpy as np
    import shapely

    real_plot = plot_of_point(real, plots, cats) if real_plot is None else real_plot
    plot = plot_of_point(footprints, plots, cats) if plot is None else plot
    counts, areas = [], []
    for cat, parcel in zip(cats, plots):
        ref = [g for g, c in zip(real, real_plot) if c == cat]
        if not ref:
            continue
        cover = shapely.union_all(ref).intersection(parcel).area / parcel.area
        if cover < 0.5:
            continue
        mine = [g.area for g, c in zip(footprints, plot) if c == cat]
        counts.append(len(mine) * cover / len(ref))
        areas.append(np.median(mine) / np.median([g.area for g in ref]) if mine else 0.0)
    return len(counts), float(np.median(counts)), float(np.median(areas))


def import_features(feats, name, tmp_path):
    """Import GeoJSON features (dicts) as vector map ``name`` (through a file in ``tmp_path``)."""
    import json

    import grass.script as gs

    path = str(tmp_path / (name + ".geojson"))
    with open(path, "w") as f:
        json.dump({"type": "FeatureCollection", "features": feats}, f)
    gs.run_command("v.in.ogr", input=path, output=name, flags="o", quiet=True)
    return name


def matched_share(found, truth, above=False):
    """Share of the ``truth`` polygons matched by one of ``found`` at IoU >= 0.5
    (``above``: > 0.5, as the object scores match)."""
    import shapely

    tree = shapely.STRtree(found)
    hits = 0
    for t in truth:
        ious = [found[i].intersection(t).area / found[i].union(t).area
                for i in tree.query(t, predicate="intersects")]
        best = max(ious) if ious else 0.0
        hits += best > 0.5 if above else best >= 0.5
    return hits / len(truth)
