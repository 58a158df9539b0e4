"""What r.histo.classify tells its user once the map is classified:
:func:`report` (``reconstruction.classify.report``).

The progress lines printed while it works (the segmentations tried, the
chosen one, the tiles) go out as they happen, through the ``say`` of
:class:`~reconstruction.classify.pipeline.ClassifyInputs`; the tuning table
of flag -p is the script's standard output (:func:`~reconstruction.classify.stage.tuning_table`).
"""

from ..core.messages import note, verbose


def report(result, config):
    """The messages after the run: how the classes were cleaned (when they
    were) and, with --verbose, the time of each step (the output's too, when
    the script added it: :meth:`~reconstruction.classify.stage.ClassifyResult.timed`)."""
    messages = []
    if result.rule:
        messages.append(note(rule_message(result.rule, config, result.grid)))
    messages.append(verbose("Timing (s): {}".format(
        ", ".join("{} {:.1f}".format(k, v) for k, v in result.timing))))
    return messages


def rule_message(rule, config, grid):
    """What the cleaning did, in map units, for the module's message."""
    if rule is None:
        return None
    cell_area = grid.nsres * grid.ewres
    resolution = min(grid.nsres, grid.ewres)

    reasons = {
        "window": "derived from the thickest removed letter or symbol: {:g} cells of {:g} "
                  "map units".format(round(rule.thickness, 1), round(resolution, 3)),
        "min_area": "derived: a square as thick",
        "min_width": "derived: {} cells, the mixed cells along a scan's edges".format(
            rule.width_cells)}

    def how(name):
        return " ({})".format(reasons[name]) if name in rule.derived else ""

    parts = []
    if config.remove:
        parts.append("removed classes {} with a {}x{} moving window{}".format(
            ",".join(map(str, config.remove)), rule.window, rule.window, how("window")))
    parts.append("minimum mapping unit {:g} square map units{}".format(
        round(rule.min_cells * cell_area, 2), how("min_area")))
    parts.append("minimum width {:g} map units{}".format(
        round(rule.width_cells * resolution, 2), how("min_width")))
    text = "; ".join(parts)
    return text[0].upper() + text[1:]

