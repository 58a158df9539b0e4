"""val3dity, the reference validator of CityJSON solids, as a test oracle.

The build in ``../shared/tools/val3dity/`` (Debian 12, x86-64) checks what a
file holds after its ``transform`` quantisation. :func:`val3dity_report`
runs it on one file and sums the report up; :func:`require_val3dity` skips a
test with a message where it cannot run (absent, or its runtime libraries
missing: ``make deps`` installs them).
"""

import collections
import json
import os
import subprocess
import tempfile
from dataclasses import dataclass, field

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VAL3DITY = os.path.abspath(os.path.join(ROOT, "..", "shared", "tools", "val3dity", "val3dity"))


@dataclass
class Val3dityReport:
    """What val3dity says of one file: object counts and error codes of the invalid ones."""

    objects: int
    invalid: list = field(default_factory=list)       # ids of invalid city objects
    codes: collections.Counter = field(default_factory=collections.Counter)

    @property
    def valid(self):
        return self.objects - len(self.invalid)

    def __str__(self):
        return "{} of {} valid{}".format(
            self.valid, self.objects,
            "" if not self.codes else " (errors: {})".format(
                ", ".join("{} x{}".format(k, v) for k, v in sorted(self.codes.items()))))


def val3dity_problem():
    """Why val3dity cannot run here, or None when it can."""
    if not os.path.exists(VAL3DITY):
        return "val3dity not found at '{}' (it is only beside the project checkout)".format(VAL3DITY)
    try:
        proc = subprocess.run([VAL3DITY, "--version"], capture_output=True, text=True, timeout=60)
    except OSError as error:
        return "val3dity cannot start: {}".format(error)
    if proc.returncode != 0:
        return "val3dity cannot run (its runtime libraries: `make deps`): {}".format(
            (proc.stderr or proc.stdout).strip()[:300])
    return None


def require_val3dity():
    """Skip the calling test with a clear message where val3dity cannot run."""
    import pytest

    problem = val3dity_problem()
    if problem:
        pytest.skip(problem)


def val3dity_report(path):
    """Run val3dity on a CityJSON (or CityJSONSeq) file and sum its report up."""
    with tempfile.TemporaryDirectory() as tmp:
        report_path = os.path.join(tmp, "report.json")
        command = [VAL3DITY, path, "--report", report_path]
        stdin = None
        if path.endswith(".jsonl"):
            command = [VAL3DITY, "stdin", "--report", report_path]
            stdin = open(path, "rb")
        try:
            proc = subprocess.run(command, stdin=stdin, capture_output=True, text=True)
        finally:
            if stdin:
                stdin.close()
        if not os.path.exists(report_path):
            raise RuntimeError("val3dity wrote no report: {}".format(proc.stdout[-500:]))
        with open(report_path) as f:
            report = json.load(f)
    result = Val3dityReport(objects=len(report["features"]))
    for feature in report["features"]:
        if feature["validity"]:
            continue
        result.invalid.append(feature["id"])
        for error in feature.get("errors", []):
            result.codes[error["code"]] += 1
        for primitive in feature.get("primitives", []):
            for error in primitive.get("errors", []):
                result.codes[error["code"]] += 1
    return result
