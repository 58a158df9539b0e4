"""What a stage tells its user: messages, warnings and verbose lines, as data.

Each stage's ``report`` function returns a list of :class:`Message` built
from its result (pure, tested without GRASS); the module script hands them
to :func:`reconstruction.grassio.say`, which prints each with GRASS's
``gs.message``, ``gs.warning``, ``gs.verbose`` or ``gs.info``.
"""

from dataclasses import dataclass

#: the levels of a message, as GRASS prints them
LEVELS = ("message", "warning", "verbose", "info")


@dataclass(frozen=True)
class Message:
    """One line for the user: ``text`` at ``level`` (one of :data:`LEVELS`)."""
    text: str
    level: str = "message"

    def __post_init__(self):
        if self.level not in LEVELS:
            raise ValueError("A message's level is one of {}, not {!r}".format(
                ", ".join(LEVELS), self.level))


def note(text):
    """A message printed by default (``gs.message``)."""
    return Message(text, "message")


def warning(text):
    """A warning (``gs.warning``: ``WARNING: ...``)."""
    return Message(text, "warning")


def verbose(text):
    """A line printed with ``--verbose`` only (``gs.verbose``)."""
    return Message(text, "verbose")


def info(text):
    """An informative message (``gs.info``)."""
    return Message(text, "info")
