"""Plain rectangles on which a crow-stepped gable can always be built.

The generator of the property test of ``roof=stepped``
(``reconstruction/testsuite/lod2/solids/test_stepped_rectangles.py``) and of
the count of its fallbacks on many rectangles
(``testsuite/benchmarks/bench_stepped_rectangles.py``): one building per row
of :data:`DRAWS` uniform numbers in [0, 1), so that hypothesis and a seeded
numpy generator draw the same buildings.

Every building is a rectangle of 3 to 25 by 3 to 40 m, turned by any angle,
with eaves of 2.5 to 25 m and a roof of 1 m to 0.9 times its shorter side
(at most 12 m: gables up to 61 degrees, 30 steps), and any crow-step height
and thickness of :class:`~reconstruction.lod2.roofs.model.RoofConfig`: the
facade strip fits, no step count reaches
:data:`~reconstruction.lod2.roofs.facades.MAX_STEPS` and every step is
several centimetres wide, so a valid stepped facade exists on each.
"""

import math

import numpy as np

#: uniform numbers per building: width, depth, eaves, roof height, angle, the roof's three
DRAWS = 8
#: the coordinates of the first building; the others stand in rows of 200, 50 m apart
ORIGIN = np.array([85000.0, 446000.0])


def rectangles(uniforms):
    """Buildings of ``uniforms`` ((N, :data:`DRAWS`) numbers in [0, 1)):
    ``(footprints, eaves, attic, roof_uniforms)``, footprints as
    counter-clockwise rings (4, 2) in RD New coordinates, each 50 m from the
    next, and roof uniforms (N, 3) for
    :class:`~reconstruction.lod2.solids.build.Buildings`."""
    u = np.asarray(uniforms, dtype=float).reshape(-1, DRAWS)
    width = 3.0 + 22.0 * u[:, 0]
    depth = 3.0 + 37.0 * u[:, 1]
    eaves = 2.5 + 22.5 * u[:, 2]
    top = np.minimum(12.0, 0.9 * np.minimum(width, depth))
    attic = 1.0 + (top - 1.0) * u[:, 3]
    angle = 2.0 * math.pi * u[:, 4]
    footprints = []
    for k in range(len(u)):
        xy = np.array([[0.0, 0.0], [depth[k], 0.0], [depth[k], width[k]], [0.0, width[k]]])
        c, s = math.cos(angle[k]), math.sin(angle[k])
        at = ORIGIN + 50.0 * np.array([k % 200, k // 200])
        footprints.append(xy @ np.array([[c, s], [-s, c]]) + at)
    return footprints, eaves, attic, u[:, 5:8]
