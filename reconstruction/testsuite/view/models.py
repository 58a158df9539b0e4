"""Small CityJSON models for the tests of reconstruction.view: flat-roofed prisms on
outlines in metres, stored on a millimetre grid in the Dutch RD system (EPSG:7415)."""

ORIGIN = (84000.0, 446000.0, 0.0)


def prism(outline, height):
    """A flat-roofed building on ``outline`` (counter-clockwise (x, y) corners): its
    vertices and Solid with semantics, indices from 0."""
    n = len(outline)
    vertices = [(x, y, 0.0) for x, y in outline] + [(x, y, height) for x, y in outline]
    faces = [[list(range(n))[::-1]], [list(range(n, 2 * n))]]
    faces += [[[i, (i + 1) % n, n + (i + 1) % n, n + i]] for i in range(n)]
    kinds = [{"type": "GroundSurface"}, {"type": "RoofSurface"}, {"type": "WallSurface"}]
    solid = {"type": "Solid", "lod": "2.2", "boundaries": [faces],
             "semantics": {"surfaces": kinds, "values": [[0, 1] + [2] * n]}}
    return vertices, solid


def document(buildings):
    """A CityJSON document of ``{id: (outline, height)}`` in millimetres."""
    vertices, objects = [], {}
    for oid, (outline, height) in buildings.items():
        v, solid = prism([(x + ORIGIN[0], y + ORIGIN[1]) for x, y in outline], height)
        start = len(vertices)
        vertices += v
        solid["boundaries"] = [[[[i + start for i in ring] for ring in face]
                                for face in solid["boundaries"][0]]]
        objects[oid] = {"type": "Building", "geometry": [solid],
                        "attributes": {"roof_type": "flat", "eaves_height": height}}
    return {"type": "CityJSON", "version": "2.0",
            "transform": {"scale": [0.001] * 3, "translate": list(ORIGIN)},
            "metadata": {"referenceSystem": "https://www.opengis.net/def/crs/EPSG/0/7415"},
            "CityObjects": objects,
            "vertices": [[round((c - t) / 0.001) for c, t in zip(p, ORIGIN)] for p in vertices]}


L_SHAPE = [(0, 0), (12, 0), (12, 5), (5, 5), (5, 10), (0, 10)]
SQUARE = [(20, 0), (28, 0), (28, 8), (20, 8)]
