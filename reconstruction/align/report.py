"""What v.histo.align tells its user: :func:`report` (warnings, the verbose timing,
the summary and, with -g, the counts)."""

from ..core.messages import note, verbose, warning


def report(result, config, started=None, finished=None):
    """The messages of an :class:`~.pipeline.AlignmentResult` run with ``config``.

    ``started``, ``finished``: ``time.perf_counter()`` when the module started
    and when it had written its outputs; with both, the verbose timing line.
    The -g counts are no message (standard output): :func:`shell_counts`.
    """
    alignment = result.alignment
    counts = alignment.report
    messages = []
    if counts.without_year:
        messages.append(warning(
            "{} of {} footprints have no year in <{}> (NULL, empty or a placeholder "
            "such as 9999) and were left out".format(
                counts.without_year, counts.footprints, result.year_column)))
    if not counts.candidates:
        messages.append(warning("No footprint of <{}> was built before {}".format(
            config.footprints, config.map_year)))
    if counts.repaired:
        messages.append(warning("{} invalid geometries repaired".format(counts.repaired)))
    if started is not None and finished is not None:
        read, matched = result.clock
        messages.append(verbose("Timing (s): read {:.2f}, align {:.2f}, write {:.2f}".format(
            read - started, matched - read, finished - matched)))
    messages.append(note(
        "{} of {} candidate footprints (built before {}) aligned with {} of {} plots "
        "into <{}>{}".format(
            counts.aligned, counts.candidates, config.map_year, counts.plots_matched,
            counts.plots, config.output,
            "; {} plots matched at a shifted place".format(counts.shifted_plots)
            if alignment.shifts is not None else "")))
    return messages


def shell_counts(result):
    """The -g lines (``key=value``, one per count), printed on standard output."""
    return ["{}={}".format(key, value) for key, value in result.alignment.report.counts().items()]
