"""What v.histo.subdivide tells its user: :func:`announce` (before the work) and
:func:`report` (what the subdivision repaired, clipped, measured and wrote)."""

from ..core import contract
from ..core.messages import note, verbose, warning
from ..geom.ink import REGION_STROKES


def announce(inputs, config):
    """The messages before the work: an aligned map without a plot column, the plot count."""
    messages = []
    if inputs.plot_column_missing:
        messages.append(note(
            "Aligned map <{}> has no {} column: each aligned footprint goes to the plot "
            "it overlaps most".format(config.aligned, contract.PLOT)))
    messages.append(note("Subdividing {} plots...".format(len(inputs.plots))))
    return messages


def _repairs(rep, config):
    """Warnings and messages about what the subdivision repaired, clipped and measured."""
    out = []
    if rep.plots.repaired:
        out.append(warning("{} invalid plots repaired (make_valid)".format(rep.plots.repaired)))
    if rep.plots.skipped:
        out.append(warning("{} plots without area skipped".format(rep.plots.skipped)))
    if rep.plots.overlapping_pairs:
        out.append(warning("{} pairs of overlapping plots: the shared area ({:.2f} square map "
                           "units) went to the larger plot of each pair".format(
                               rep.plots.overlapping_pairs, rep.plots.overlap_area)))
    if not config.aligned:
        return out
    if rep.aligned.repaired:
        out.append(warning("{} invalid aligned footprints repaired".format(rep.aligned.repaired)))
    if rep.aligned.clipped:
        out.append(warning("{} aligned footprints overlapping earlier ones were clipped".format(
            rep.aligned.clipped)))
    if rep.aligned_without_plot:
        out.append(warning("{} aligned footprints without a plot left out".format(
            rep.aligned_without_plot)))
    if rep.generated_dropped or rep.generated_clipped:
        out.append(note("Generated footprints overlapping aligned ones: {} clipped, "
                        "{} dropped".format(rep.generated_clipped, rep.generated_dropped)))
    if config.calibrate and rep.calibrated:
        out.append(note("Calibrated from {} aligned footprints: length={:.2f},{:.2f} "
                        "depth={:.2f},{:.2f}".format(rep.calibration_samples,
                                                     *(rep.length + rep.depth))))
    elif config.calibrate:
        out.append(warning("Too few aligned footprints on a street ({}) to calibrate: length= "
                           "and depth= kept".format(rep.calibration_samples)))
    return out


def previous_messages(rep, config):
    """What a dynamic chain's earlier epoch (previous=) gave: how the plots changed since,
    the map's offset and the footprints kept."""
    kept = rep.previous
    if kept is None:
        return []
    counts = kept.matches.counts()
    dx, dy = kept.matches.offset
    out = [note("Plots since <{}>: {}; {} gone (map offset {:.2f},{:.2f})".format(
        config.previous_plots, ", ".join("{} {}".format(n, k) for k, n in counts.items()
                                         if k != "gone" and n) or "none", counts["gone"],
        dx, dy)),
           note("{} footprints kept from <{}> ({} in unchanged plots)".format(
               rep.kept, config.previous, sum(p in kept.done for p in kept.plot)))]
    if kept.realigned:
        out.append(note("{} earlier aligned footprints aligned again (the current ones "
                        "stand in for them)".format(kept.realigned)))
    if rep.kept_clipped or rep.kept_dropped:
        out.append(note("Kept footprints overlapping this epoch's aligned ones: {} clipped, "
                        "{} dropped".format(rep.kept_clipped, rep.kept_dropped)))
    return out


def drawn_messages(drawn, rep, config):
    """What the map's lines gave (map=): the scale they were read at and the plots they
    divide."""
    if drawn is None:
        return []
    scale = drawn.scale
    out = [note("Lines drawn in the plots read on <{}>: strokes {:.1f} cells wide ({}), least "
                "unit {:.3g} square map units ({}); {} of {} plots divided into {} drawn "
                "footprints{}".format(
                    config.maps[0], scale.stroke,
                    "stroke= given" if config.stroke else "measured",
                    scale.min_area, "min_parcel= given" if config.min_parcel
                    else "{} stroke widths square".format(REGION_STROKES),
                    rep.drawn_plots - drawn.whole, drawn.plots_read, rep.drawn - drawn.whole,
                    ", {} undivided plots one footprint each (-d)".format(drawn.whole)
                    if config.whole else ", the others subdivided as without map="))]
    if drawn.plots_read == 0:
        out.append(warning("No plot lies on the map <{}>: check the region and the map".format(
            config.maps[0])))
    return out


def report(result, config, started=None, finished=None):
    """The messages of a :class:`~.pipeline.SubdivisionResult` run with ``config``.

    ``started``, ``finished``: ``time.perf_counter()`` when the module
    started reading and when it had written the footprints; with both, the
    verbose timing line. The summary of the footprints written only when
    there are footprints (none: the module stops with an error).
    """
    subdivision = result.subdivision
    rep = subdivision.report
    messages = _repairs(rep, config) + previous_messages(rep, config)
    if not subdivision.geometries:
        return messages
    if started is not None and finished is not None:
        began, done = result.clock
        messages.append(verbose("Timing (s): read {:.2f}, subdivide {:.2f}, write {:.2f}".format(
            began - started, done - began, finished - done)))
    messages.extend(drawn_messages(result.drawn, rep, config))
    counts = {c: subdivision.case.count(c) for c in sorted(set(subdivision.case))}
    messages.append(note("{} footprints written to <{}> ({} generated, {} aligned{}{}); by case: "
                         "{}".format(len(subdivision.geometries), config.output, rep.generated,
                                     len(subdivision.geometries) - rep.generated - rep.kept
                                     - rep.drawn,
                                     ", {} drawn".format(rep.drawn) if result.drawn else "",
                                     ", {} kept".format(rep.kept) if rep.previous else "",
                                     ", ".join("{}: {}".format(c, n)
                                               for c, n in counts.items()))))
    return messages
