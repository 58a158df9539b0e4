"""The synthetic town over time: determinism, the truth of its history, today's footprints,
JSON and GRASS output."""

import collections
import math
import os
import subprocess
import sys

import numpy as np
import pytest
import shapely
from shapely import affinity

import synthetic_epochs as se
import synthetic_map as sm

HERE = os.path.dirname(os.path.abspath(__file__))


@pytest.fixture(scope="module")
def town():
    return se.generate_town(seed=1)


@pytest.fixture(scope="module")
def small():
    return se.generate_town(seed=2, size=400)


def _last(t):
    return len(t.years) - 1


def _true_plots(t, epoch):
    return [t.true_plot(epoch, i) for i in range(len(t.maps[epoch].plots))]


def _event_of_after(t):
    """{(epoch, plot): the event whose after holds it}."""
    return {ref: ev for ev in t.history for ref in ev.after}


def _origin(t, ref):
    """Follow a plot back through unchanged and split events: the epoch it is new in
    (None: it comes from a plot of epoch 0, or through a change that adds ground)."""
    by_after = _event_of_after(t)
    while ref[0] > 0:
        ev = by_after[ref]
        if ev.kind == "new":
            return ref[0]
        if ev.kind not in ("unchanged", "split"):
            return None
        ref = ev.before[0]
    return None


def _year_agrees(year, since, years):
    """A construction year that agrees with the ground's history (as the module promises)."""
    if year is None or year == 9999 or year > years[-1]:
        return True
    if since is None:
        return False
    if since == 0:
        return year < years[0]
    return years[since - 1] < year < years[since]


def test_same_seed_gives_identical_town_and_other_seed_another(small):
    again = se.generate_town(seed=2, size=400)
    assert again.years == small.years and again.offsets == small.offsets
    for a, b in zip(again.maps, small.maps):
        for name in ("rgb", "truth", "drawn", "gt_points", "ink_cover"):
            assert np.array_equal(getattr(a, name), getattr(b, name)), name
        assert np.array_equal(a.training["xy"], b.training["xy"])
        assert [p.wkb for p in a.plots] == [p.wkb for p in b.plots]
    assert again.history == small.history
    assert [p.wkb for p in again.current.polygons] == [p.wkb for p in small.current.polygons]
    assert again.current.years == small.current.years and again.current.ids == small.current.ids
    assert (again.conflicts, again.current_plot, again.current_since) == (
        small.conflicts, small.current_plot, small.current_since)
    other = se.generate_town(seed=3, size=400)
    assert [p.wkb for p in other.maps[1].plots] != [p.wkb for p in small.maps[1].plots]


def test_first_epoch_is_the_single_map_and_later_maps_are_drawn_anew(town):
    single = sm.generate(seed=1)
    first = town.maps[0]
    assert np.array_equal(first.rgb, single.rgb)
    assert [p.wkb for p in first.plots] == [p.wkb for p in single.plots]
    assert town.offsets[0] == (0.0, 0.0)
    for later in town.maps[1:]:
        assert later.region() == first.region() and later.shape == first.shape
        # own noise, labels and symbols: the pictures differ well beyond the changed plots
        assert np.mean(np.abs(later.rgb.astype(int) - first.rgb.astype(int))) > 3
        assert not np.array_equal(later.training["xy"], first.training["xy"])


@pytest.mark.parametrize("transition", [0, 1])
def test_every_kind_of_change_in_every_transition(town, transition):
    events = town.events(transition=transition)
    kinds = collections.Counter(ev.kind for ev in events)
    assert set(kinds) == set(se.EVENT_KINDS), kinds
    n_before = len(town.maps[transition].plots)
    assert 0.6 <= kinds["unchanged"] / n_before <= 0.8, kinds


@pytest.mark.parametrize("which", ["town", "small"])
def test_history_covers_every_plot_of_every_transition_once(which, request):
    t = request.getfixturevalue(which)
    shape = {"unchanged": (1, 1), "split": (1, 2), "merged": (2, 1), "extended": (1, 1),
             "new": (0, 1), "demolished": (1, 0)}
    for ev in t.history:
        assert (len(ev.before), len(ev.after)) == shape[ev.kind], ev
        e = se._transition_of(ev)
        assert all(b[0] == e for b in ev.before) and all(a[0] == e + 1 for a in ev.after)
    befores = collections.Counter(ref for ev in t.history for ref in ev.before)
    afters = collections.Counter(ref for ev in t.history for ref in ev.after)
    last = _last(t)
    assert befores == collections.Counter(
        (e, i) for e in range(last) for i in range(len(t.maps[e].plots)))
    assert afters == collections.Counter(
        (e, i) for e in range(1, last + 1) for i in range(len(t.maps[e].plots)))


def test_offsets_are_small_and_recorded(town):
    for e, (dx, dy) in enumerate(town.offsets[1:], start=1):
        assert 0.49 <= math.hypot(dx, dy) <= 1.51
        # the drawing really moved: the truth raster matches the offset plots, not the true ones
        smap = town.maps[e]
        rows, cols, drawn = sm.plots_sampled(smap, 5)
        assert np.array_equal(drawn, smap.truth[rows, cols] == sm.BUILDING)


def test_unchanged_plots_identical_up_to_the_offset(town):
    unchanged = town.events("unchanged")
    assert unchanged
    for ev in unchanged:
        (e0, i), (e1, j) = ev.before[0], ev.after[0]
        (ax, ay), (bx, by) = town.offsets[e0], town.offsets[e1]
        moved = affinity.translate(town.maps[e0].plots[i], bx - ax, by - ay)
        assert moved.equals_exact(town.maps[e1].plots[j], 1e-6)
        assert town.true_plot(e0, i).equals(town.true_plot(e1, j))
        assert town.maps[e0].plot_kinds[i] == town.maps[e1].plot_kinds[j]
    # and no changed plot passes for unchanged
    for ev in town.history:
        if ev.kind in ("split", "merged", "extended"):
            before = shapely.union_all([town.true_plot(*b) for b in ev.before])
            after = shapely.union_all([town.true_plot(*a) for a in ev.after])
            assert before.symmetric_difference(after).area > 5, ev


def test_changes_do_what_their_kind_says(town):
    for ev in town.history:
        before = [town.true_plot(*b) for b in ev.before]
        after = [town.true_plot(*a) for a in ev.after]
        if ev.kind == "split":
            a, b = after
            assert a.intersection(b).area == 0 and a.distance(b) >= 2.0  # a passage between
            assert before[0].buffer(0.01).contains(a) and before[0].buffer(0.01).contains(b)
            assert a.area + b.area < before[0].area
        elif ev.kind == "merged":
            assert before[0].distance(before[1]) <= se._MERGE_GAP
            assert all(after[0].buffer(0.01).contains(p) for p in before)
        elif ev.kind == "extended":
            assert after[0].buffer(0.01).contains(before[0])
            assert after[0].area - before[0].area >= 20
        elif ev.kind == "new":
            earlier = shapely.union_all(_true_plots(town, ev.after[0][0] - 1))
            assert after[0].intersection(earlier).area == 0
        elif ev.kind == "demolished":
            later = shapely.union_all(_true_plots(town, ev.before[0][0] + 1))
            assert before[0].intersection(later).area == 0


@pytest.mark.parametrize("seed", range(4))
def test_ground_cleared_in_a_transition_is_no_plot_on_the_next_map(seed):
    # one plot covering most of the town: it is the one demolished, and nothing may be
    # built or grown on its ground before the next map
    only = shapely.box(10, 10, 90, 90)
    later, gardens, events, new = se._transition(
        np.random.default_rng(seed), [(only, "single", 0.0)], [], set(), shapely.Polygon(),
        100.0, (1880, 1915))
    assert [e[0] for e in events][0] == "demolished"
    assert all(p.intersection(only).area == 0 for p, _, _ in later)


def test_plots_of_every_epoch_valid_inside_and_apart(town):
    for e, smap in enumerate(town.maps):
        frame = shapely.box(smap.west, smap.south, smap.east, smap.north).buffer(-2)
        plots = np.array(smap.plots, dtype=object)
        assert all(p.geom_type == "Polygon" and p.is_valid and frame.contains(p) for p in plots)
        a, b = shapely.STRtree(plots).query(plots, predicate="intersects")
        assert np.all(a == b), e  # no two plots of an epoch touch
        assert len(smap.gt_points) == len(plots) == len(smap.plot_kinds)


def test_event_years_strictly_between_the_epochs(town, small):
    for t in (town, small):
        for ev in t.history:
            if ev.kind == "unchanged":
                assert ev.year is None
                continue
            e = se._transition_of(ev)
            assert isinstance(ev.year, int) and t.years[e] < ev.year < t.years[e + 1], ev


def test_current_since_is_the_history_of_the_ground(town):
    last = _last(town)
    plots = [shapely.union_all(_true_plots(town, e)).buffer(1e-6) for e in range(last + 1)]
    for poly, since in zip(town.current.polygons, town.current_since):
        p = poly.representative_point()
        inside = [plots[e].covers(p) for e in range(last + 1)]
        if since is None:
            assert not inside[last]
        else:
            assert all(inside[since:]) and (since == 0 or not inside[since - 1])
    assert set(town.current_since) >= {0, 1, 2, None}


def test_current_years_agree_with_the_history_except_the_conflicts(town, small):
    for t in (town, small):
        years = t.years
        bad = [i for i, (y, s) in enumerate(zip(t.current.years, t.current_since))
               if not _year_agrees(y, s, years)]
        assert bad == t.conflicts
        # mostly built in the period the ground became a plot in (modern blocks aside)
        for since in range(len(years)):
            ys = [y for i, (y, s, kind) in enumerate(zip(t.current.years, t.current_since,
                                                         t.current.kind))
                  if s == since and kind != "rebuilt" and i not in t.conflicts]
            if since == 0:
                assert np.mean([y is not None and y < years[0] for y in ys]) > 0.6
            elif len(ys) >= 5:
                assert np.mean([y is not None and years[since - 1] < y < years[since]
                                for y in ys]) > 0.5


def test_conflicts_are_old_years_on_plots_new_in_the_second_map(town):
    assert town.conflicts
    for i in town.conflicts:
        assert town.current.years[i] < town.years[0]
        ref = town.current_plot[i]
        assert ref is not None and _origin(town, ref) == 1
        # the plot is absent from the first map: its ground was no plot then
        first = shapely.union_all(_true_plots(town, 0))
        assert town.current.polygons[i].intersection(first).area < 1.0


def test_current_footprints_stand_in_their_plots(town):
    last = _last(town)
    plots = _true_plots(town, last)
    assert len(town.current_plot) == len(town.current.polygons) == len(town.current.ids)
    assert len(set(town.current.ids)) == len(town.current.ids)
    for poly, ref, kind, cat in zip(town.current.polygons, town.current_plot, town.current.kind,
                                    town.current.plot):
        assert poly.is_valid and poly.area > 5
        if ref is None:
            assert kind == "outside" and cat == 0
            continue
        assert ref[0] == last and cat == ref[1] + 1
        share = poly.intersection(town.true_plot(*ref)).area / poly.area
        if kind == "straddling":  # over two plots and the street: the plot that holds most
            assert share >= max(poly.intersection(p).area / poly.area for p in plots)
        else:
            assert share > (0.4 if kind == "offset" else 0.95), (kind, share)


def test_demolished_plots_have_no_current_footprints(town):
    demolished = town.events("demolished")
    assert demolished
    points = [p.representative_point() for p in town.current.polygons]
    for ev in demolished:
        e = ev.before[0][0]
        ground = town.true_plot(*ev.before[0])
        on = [i for i, p in enumerate(points) if ground.covers(p)]
        for i in on:
            # only a building put up after the next map (or of unknown year) may stand there
            y = town.current.years[i]
            assert i in town.conflicts or y is None or y == 9999 or y > town.years[e + 1], (ev, y)
            assert town.current_since[i] is None or town.current_since[i] >= e + 2
        if e + 1 == _last(town):
            assert all(town.current.kind[i] == "outside" for i in on)


def test_truth_json_round_trip(tmp_path, small):
    path = se.write_truth(small, str(tmp_path / "truth.json"))
    back = se.load_truth(path)
    assert back["years"] == list(small.years) and back["seed"] == 2
    assert back["offsets"] == small.offsets
    assert back["history"] == small.history
    assert back["conflicts"] == small.conflicts
    for epoch, smap in zip(back["epochs"], small.maps):
        assert len(epoch["plots"]) == len(smap.plots)
        assert all(a.equals_exact(b, 1e-9) for a, b in zip(epoch["plots"], smap.plots))
        assert epoch["kinds"] == smap.plot_kinds
    assert [c["bouwjaar"] for c in back["current"]] == small.current.years
    assert [c["plot"] for c in back["current"]] == small.current_plot
    assert all(c["polygon"].equals_exact(p, 1e-9)
               for c, p in zip(back["current"], small.current.polygons))


def test_years_must_increase():
    with pytest.raises(ValueError):
        se.generate_town(seed=1, size=300, years=(1900, 1880))


def test_command_line_outside_grass_refuses_but_writes_pictures(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "GISRC"}
    script = os.path.join(HERE, "synthetic_epochs.py")
    run = subprocess.run([sys.executable, script, "--size", "200"], env=env,
                         capture_output=True, text=True)
    assert run.returncode != 0 and "GRASS session" in run.stderr
    run = subprocess.run([sys.executable, script, "--size", "200", "--years", "1900,1950",
                          "--png", str(tmp_path / "png"), "--truth", str(tmp_path / "t.json")],
                         env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert sorted(os.listdir(tmp_path / "png")) == ["town_1900.png", "town_1950.png"]
    assert se.load_truth(str(tmp_path / "t.json"))["years"] == [1900, 1950]


# ---------------------------------------------------------------------------
# In GRASS
# ---------------------------------------------------------------------------

@pytest.mark.grass
def test_write_to_grass_every_epoch_and_the_current_footprints(grass_session, mapset):
    import grass.script as gs

    from reconstruction import grassio

    t = se.generate_town(seed=4, size=300, years=(1880, 1915))
    names = se.write_to_grass(t, "town")
    assert names["epochs"][1880]["red"] == "town_1880.red"
    assert names["current"] == "town_current"
    for year, smap in zip(t.years, t.maps):
        n = names["epochs"][year]
        univar = gs.parse_command("r.univar", map=n["blue"], flags="g")
        assert float(univar["mean"]) == pytest.approx(smap.rgb[..., 2].mean(), abs=1e-6)
        geoms, columns = grassio.read_features(n["plots"])
        by_cat = dict(zip(columns["cat"], geoms))
        assert sorted(by_cat) == list(range(1, len(smap.plots) + 1))
        assert max(by_cat[k + 1].symmetric_difference(p).area
                   for k, p in enumerate(smap.plots)) < 1e-3
        assert grassio.vector_counts(n["training"])["points"] == len(smap.training["label"])
        assert not gs.find_file("town_{}_current".format(year), element="vector")["name"]
    geoms, columns = grassio.read_areas(names["current"])
    assert columns["bouwjaar"] == t.current.years
    assert columns["identificatie"] == t.current.ids
    heights = sm.footprint_heights(t.current.polygons, t.seed)
    assert columns["b3_h_nok"] == heights["b3_h_nok"]


@pytest.mark.grass
def test_command_line_writes_the_town(grass_session, mapset, tmp_path):
    import grass.script as gs

    run = subprocess.run([sys.executable, os.path.join(HERE, "synthetic_epochs.py"),
                          "--seed", "5", "--size", "200", "--years", "1900,1930",
                          "--prefix", "tiny", "--truth", str(tmp_path / "t.json")],
                         cwd=str(tmp_path), capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    truth = se.load_truth(str(tmp_path / "t.json"))
    for year, epoch in zip((1900, 1930), truth["epochs"]):
        topo = gs.vector_info_topo("tiny_{}_plots".format(year))
        assert topo["centroids"] == len(epoch["plots"])
    assert gs.vector_info_topo("tiny_current")["centroids"] == len(truth["current"])
