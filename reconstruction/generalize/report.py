"""What v.histo.generalize tells its user once the plots are generalised:
:func:`report` (``reconstruction.generalize.report``); with flag -g the
figures are the script's standard output instead (:func:`shell_figures`).

The lines printed before the work go out as they happen, through the
``say`` of :class:`~reconstruction.generalize.pipeline.GeneralizeInputs`.
"""

from ..core.messages import note, warning
from .stage import METHOD


def report(result, config):
    """The warnings of the steps that needed a fallback method, then (without
    flag -g) the assessment figures in one message."""
    messages = [warning(("Step {}: {} plots kept their outline: no sound fit to the map's lines "
                         "(see column '{}')" if step.startswith("fit") else
                         "Step {}: {} plots needed a fallback method (see column '{}')").format(
        step, count, METHOD)) for step, count in result.report.fallbacks.items()]
    if not config.shell:
        messages.append(note(", ".join(
            "{} {}".format(k, round(v, 4) if isinstance(v, float) else v)
            for k, v in result.report.scalars().items())))
    return messages


def shell_figures(result):
    """The lines flag -g prints: each figure as key=value (empty when not measurable)."""
    return ["{}={}".format(key, "" if value is None else value)
            for key, value in result.report.scalars().items()]
