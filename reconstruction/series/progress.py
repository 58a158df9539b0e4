"""What finished: a series run's bookkeeping, so that a rerun goes on where it stopped.

One JSON line per finished attempt in ``progress.jsonl`` of the output
folder, appended and flushed at once (a driver killed mid-way loses at
most the sheets it was running): the sheet, ``done`` or ``failed``, the
attempt, the seconds it took, the ``ERROR:`` line of a failure and the
fingerprint of the sheet's process chain. A sheet counts as done when its
last line says so for the same chain (a changed manifest or template runs
it again) and its model is there.
"""

import hashlib
import json
import os
from dataclasses import asdict, dataclass

from ..core.errors import InputError


@dataclass(frozen=True)
class Attempt:
    """One finished attempt of one sheet."""
    sheet: str
    status: str           # "done" or "failed"
    attempt: int
    seconds: float
    chain: str            # fingerprint of the process chain (:func:`fingerprint`)
    error: str = ""


def fingerprint(document):
    """A short fingerprint of a process chain (its document, as JSON)."""
    text = json.dumps(document, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class Progress:
    """The attempts recorded in ``path`` (read at once), and new ones appended."""

    def __init__(self, path):
        self.path = path
        self.last = {}
        if os.path.exists(path):
            with open(path, encoding="utf-8") as f:
                for number, line in enumerate(f, 1):
                    if not line.strip():
                        continue
                    try:
                        attempt = Attempt(**json.loads(line))
                    except (ValueError, TypeError):
                        if number == sum(1 for _ in open(path, encoding="utf-8")):
                            continue    # the last line, cut by a kill: that attempt is lost
                        raise InputError("'{}' line {} is not a record of an attempt".format(
                            path, number)) from None
                    self.last[attempt.sheet] = attempt

    def done(self, sheet, chain):
        """Whether ``sheet`` finished with the chain of fingerprint ``chain``."""
        a = self.last.get(sheet)
        return a is not None and a.status == "done" and a.chain == chain

    def record(self, attempt):
        """Append one attempt (written through at once)."""
        with open(self.path, "a", encoding="utf-8") as f:
            f.write(json.dumps(asdict(attempt), sort_keys=True) + "\n")
            f.flush()
            os.fsync(f.fileno())
        self.last[attempt.sheet] = attempt
