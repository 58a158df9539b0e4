"""The crow-stepped facades stay those of the builder before the gable
profiles (issue 31): the same vertices and faces, bit for bit.

The reference is ``stepped_arrays`` as it was at commit :data:`REFERENCE`
(read from the repository's history with git, so the test skips in a copy
without it), run on the same bodies as the suite's facade builder.
"""

import importlib.util
import os
import subprocess

import numpy as np
import pytest

from reconstruction.lod2.roofs import plan as roofs
from reconstruction.lod2.roofs.model import RoofConfig
from stepped_rectangles import DRAWS, rectangles

#: the last commit with the crow-stepped builder of its own (``roofs/stepped.py``)
REFERENCE = "4dd7475"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(
    os.path.abspath(__file__))))))


@pytest.fixture(scope="module")
def reference():
    """``stepped.py`` of :data:`REFERENCE` as a module of the roofs package."""
    try:
        source = subprocess.run(["git", "-C", ROOT, "show",
                                 REFERENCE + ":reconstruction/lod2/roofs/stepped.py"],
                                capture_output=True, text=True, timeout=60)
    except OSError as error:
        pytest.skip("git cannot run: {}".format(error))
    if source.returncode != 0:
        pytest.skip("commit {} is not in this copy's history".format(REFERENCE))
    spec = importlib.util.spec_from_loader("reconstruction.lod2.roofs._stepped_reference",
                                           loader=None)
    module = importlib.util.module_from_spec(spec)
    module.__package__ = "reconstruction.lod2.roofs"
    exec(compile(source.stdout, "stepped.py@" + REFERENCE, "exec"), module.__dict__)
    return module


def footprints():
    """Rectangles of the stepped property test (any turn, size, roof and
    step), trapezoids, slanted street edges and pentagons."""
    u = np.random.default_rng(7).random((300, DRAWS))
    rects, _, attic, uniforms = rectangles(u)
    rings = [xy - xy[0] for xy in rects]
    rng = np.random.default_rng(8)
    for k in range(120):
        w, d = rng.uniform(4, 12), rng.uniform(8, 20)
        s0, s1 = rng.uniform(-1.5, 1.5, 2)
        rings.append(np.array([[0, 0], [w, s0], [w + s1, d], [0, d]], dtype=float))
    for k in range(60):
        w, d = rng.uniform(5, 10), rng.uniform(9, 16)
        rings.append(np.array([[0, 0], [w, 0], [w + rng.uniform(0.5, 2), d / 2], [w, d],
                               [0, d]], dtype=float))
    extra = len(rings) - len(rects)
    attic = np.r_[attic, rng.uniform(1.0, 7.0, extra)]
    uniforms = np.r_[uniforms, rng.random((extra, 3))]
    return rings, attic, uniforms


def bodies(rings, attic, uniforms, config):
    """The arguments of the facade builder, per envelope batch, as make_roofs makes them."""
    plan = roofs.plan_roofs(rings, ["stepped"] * len(rings), attic, uniforms, config)
    for jobs, env in roofs._batch_envelope(plan.envelope):
        env = env.scaled_to(np.array([attic[j.index] for j in jobs], dtype=float))
        rows = np.array([k for k, j in enumerate(jobs) if j.body], dtype=int)
        owner = [jobs[k].index for k in rows]
        facades = [plan.facades[i] for i in owner]
        yield (np.stack([rings[i] for i in owner]), [f.end for f in facades], env.take(rows),
               [f.step for f in facades])


def test_crow_stepped_facades_are_the_reference_builders_bit_for_bit(reference):
    from reconstruction.lod2.roofs import facades
    config = RoofConfig(step=(0.12, 0.7))
    rings, attic, uniforms = footprints()
    groups = 0
    for xy, ends, body, steps in bodies(rings, attic, uniforms, config):
        want = reference.stepped_arrays(xy, ends, body, steps, config.thickness)
        got = facades.facade_arrays(xy, ends, body, ["stepped"] * len(xy), steps,
                                      config.thickness)
        assert len(got) == len(want)
        for g, w in zip(got, want):
            assert g.kind == w.kind
            for field in ("index", "xy", "vertices", "faces", "counts", "zmax", "wall_mid"):
                a, b = getattr(g, field), getattr(w, field)
                assert a.dtype == b.dtype and a.shape == b.shape, field
                assert a.tobytes() == b.tobytes(), field
        groups += len(want)
    assert groups >= 20
