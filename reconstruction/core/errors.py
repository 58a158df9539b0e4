"""The one error convention of the suite.

The library raises :class:`InputError` for bad input, with the message a user
should read (no traceback wanted); a module script turns it into one
``ERROR:`` line through :func:`reconstruction.grassio.maps.run_main`.
``InputError`` is a ``ValueError``, so callers that catch ``ValueError`` keep
working.
"""


class InputError(ValueError):
    """Bad input: an option, a map or a value a user gave. Its text is the message to show."""
