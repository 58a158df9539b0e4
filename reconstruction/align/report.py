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
    if counts.candidates and not counts.aligned:
        messages.append(_nothing_aligned(result, config))
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


def _nothing_aligned(result, config):
    """The warning of a run where no candidate aligned: the boxes of the footprints and
    of the plots when they do not meet, even with the plots grown by the buffer and
    the shift (another region or reference system), else the best similarity reached."""
    counts, fp, plots = result.alignment.report, result.footprints_extent, result.plots_extent
    if fp is not None and plots is not None and not fp.meets(plots,
                                                             config.buffer + config.shift):
        return warning("The {} candidate footprints of <{}> ({}) do not overlap the plots of "
                       "<{}> ({}): nothing aligned, <{}> is empty. Are they of another region "
                       "or reference system?".format(counts.candidates, config.footprints,
                                                     fp.text(), config.plots, plots.text(),
                                                     config.output))
    best = result.alignment.best_similarity
    return warning("None of the {} candidate footprints of <{}> aligned with a plot of <{}> "
                   "(best similarity {:.2f}, overlap= asks {:g}): <{}> is empty".format(
                       counts.candidates, config.footprints, config.plots,
                       float(best.max()) if len(best) else 0.0, config.overlap,
                       config.output))


def shell_counts(result):
    """The -g lines (``key=value``, one per count), printed on standard output."""
    return ["{}={}".format(key, value) for key, value in result.alignment.report.counts().items()]
