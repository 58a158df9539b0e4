"""The library's layering, checked from its source (issue 27).

The packages of ``reconstruction/`` stand in layers; an import may only go
down or stay inside its own package:

- ``core`` (errors, options, names, CRS, safe files, work limits, the data
  contract) imports nothing else of the library;
- ``geom`` (rings, polygons, overlaps, grids, solid sets) imports ``core``;
- ``cityjson`` and ``grassio`` import ``core`` and ``geom``; ``grassio`` is
  the only package that imports GRASS (``grass.script``, ``grass.exceptions``);
- ``epochs`` (several dated maps of one town: plots matched between epochs,
  lifespans, the model of all epochs) imports ``core``, ``geom`` and ``cityjson``;
- ``view`` (a model made ready for a browser or glTF) imports ``core``, ``geom``,
  ``cityjson`` and ``epochs``;
- ``series`` (a map series: manifest, process chains, sheet edges, the merged
  model) imports ``core``, ``geom`` and ``cityjson``; it runs no GRASS itself;
- the stages ``classify``, ``generalize``, ``align``, ``subdivide``, ``lod2``
  and the module v.histo.timeline's ``timeline``
  import the packages above and their own modules, never another stage.

Across packages only public names travel (no ``_name``, no ``_module``), the
modules import each other without a cycle, and every import is at the top of
its module except the lazy imports of heavy optional dependencies listed in
:data:`LAZY`, kept inside functions for start-up time.

The checks are functions over a mapping {module name: source text}, so the
tests below show each of them failing on a small made-up package as well as
passing on the real one.
"""

import ast
import os

import pytest

LIBRARY = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# What each package may import besides itself.
LAYERS = {
    "core": set(),
    "geom": {"core"},
    "cityjson": {"core", "geom"},
    "grassio": {"core", "geom"},
    "epochs": {"core", "geom", "cityjson"},
    "view": {"core", "geom", "cityjson", "epochs"},
    "series": {"core", "geom", "cityjson"},
}
STAGES = ("classify", "generalize", "align", "subdivide", "lod2", "timeline")
for _stage in STAGES:
    LAYERS[_stage] = {"core", "geom", "cityjson", "grassio", "epochs", "view"}

GRASS_PACKAGE = "grassio"

# Imports kept inside functions, on purpose: each is a heavy third-party
# module (tens to hundreds of milliseconds, or a native library) that only
# some runs need, and every module run imports the library anew.
LAZY = {
    "shapely",                 # 50 ms; r.histo.classify and the CityJSON writers never need it
    "shapely.geometry",
    "scipy.spatial",           # Delaunay, cKDTree: only the stages that search neighbours
    "scipy.sparse",            # connected groups of plots: only with an earlier epoch
    "scipy.sparse.csgraph",
    "sklearn.ensemble",        # scikit-learn: 0.5 s, only r.histo.classify's classifiers
    "sklearn.neighbors",
    "sklearn.pipeline",
    "sklearn.preprocessing",
    "sklearn.svm",
    "pyvista",                 # VTK: about 1 s, only v.histo.lod2 render= and viewer=
    "PIL",                     # only the map of a viewer
    "pyproj",                  # PROJ: only 3D Tiles (tiles=), put on the globe
    "pyproj.exceptions",
    "pySVCGAL.pySVCGAL",       # CGAL's skeleton (a native library): only concave roofs
    "orjson",                  # only where copied buildings are written
    "jsonschema",              # only the schema check of written models
    "referencing",
    "referencing.jsonschema",
    "grass.script.array",      # numpy <-> GRASS rasters: only where rasters are read or written
}


def library_sources(root=LIBRARY):
    """{dotted module name: source} of every library module (tests left out)."""
    sources = {}
    for folder, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d not in ("testsuite", "__pycache__"))
        for name in sorted(files):
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                parts = os.path.relpath(path, os.path.dirname(root))[:-3].split(os.sep)
                if parts[-1] == "__init__":
                    parts = parts[:-1]
                with open(path, encoding="utf-8") as f:
                    sources[".".join(parts)] = f.read()
    return sources


class Import:
    """One import statement: the module it reads, the names it takes, where it stands."""

    def __init__(self, module, names, line, top_level):
        self.module, self.names, self.line, self.top_level = module, names, line, top_level


def _is_package(name, sources):
    return any(other.startswith(name + ".") for other in sources)


def imports(name, source, sources):
    """The imports of one module, relative ones resolved to dotted names."""
    tree = ast.parse(source)
    package = name if _is_package(name, sources) else name.rpartition(".")[0]
    found = []

    def visit(node, top_level):
        for child in ast.iter_child_nodes(node):
            nested = top_level and not isinstance(
                child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda))
            if isinstance(child, ast.Import):
                for alias in child.names:
                    found.append(Import(alias.name, (), child.lineno, top_level))
            elif isinstance(child, ast.ImportFrom):
                if child.level:
                    base = package.split(".")
                    base = base[:len(base) - child.level + 1]
                    module = ".".join(base + ([child.module] if child.module else []))
                else:
                    module = child.module
                found.append(Import(module, tuple(a.name for a in child.names),
                                    child.lineno, top_level))
            visit(child, nested)

    visit(tree, True)
    return found


def _library_targets(imp, sources):
    """The library modules an import runs: the module itself or the
    submodules it names."""
    submodules = [imp.module + "." + n for n in imp.names if imp.module + "." + n in sources]
    if imp.module in sources and len(submodules) < max(len(imp.names), 1):
        submodules.insert(0, imp.module)
    return submodules


def _package_of(module):
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else None


def layering_problems(sources):
    """Every import that breaks the rules above, as readable lines."""
    problems = []
    root = next(iter(sources)).split(".")[0]
    for name, source in sorted(sources.items()):
        own = _package_of(name)
        for imp in imports(name, source, sources):
            where = "{} line {}".format(name, imp.line)
            if imp.module.split(".")[0] == "grass" and own != GRASS_PACKAGE:
                problems.append("{}: imports {} outside {}/".format(where, imp.module, GRASS_PACKAGE))
            internal = imp.module == root or imp.module.startswith(root + ".")
            if not imp.top_level:
                if internal:
                    problems.append("{}: imports {} inside a function".format(
                        where, ", ".join(_library_targets(imp, sources)) or imp.module))
                elif imp.module not in LAZY and not all(
                        imp.module + "." + n in LAZY for n in imp.names or ("?",)):
                    problems.append("{}: imports {} inside a function (not in LAZY)".format(
                        where, imp.module))
            if not internal:
                continue
            for target in _library_targets(imp, sources) or [imp.module]:
                other = _package_of(target)
                if other is None or own is None or other == own:
                    continue
                if other not in LAYERS.get(own, set()):
                    problems.append("{}: {} imports {} (allowed: {})".format(
                        where, own, target, ", ".join(sorted(LAYERS.get(own, ()))) or "nothing"))
                private = [p for p in target.split(".") + list(imp.names) if p.startswith("_")
                           and p != "__init__"]
                if private:
                    problems.append("{}: takes the private {} of {}".format(
                        where, ", ".join(private), other))
    return problems


def import_cycles(sources):
    """The import cycles among the modules (each as a list of names)."""
    graph = {}
    for name, source in sources.items():
        edges = set()
        for imp in imports(name, source, sources):
            for target in _library_targets(imp, sources):
                edges.add(target)
                # importing a module of another package runs that package's
                # __init__ first (and its parents')
                parts = target.split(".")
                for k in range(2, len(parts)):
                    parent = ".".join(parts[:k])
                    if not name.startswith(parent + ".") and name != parent:
                        edges.add(parent)
        edges.discard(name)
        graph[name] = sorted(edges)
    cycles, state, stack = [], {}, []

    def walk(node):
        state[node] = "open"
        stack.append(node)
        for nxt in graph.get(node, ()):
            if state.get(nxt) == "open":
                cycles.append(stack[stack.index(nxt):] + [nxt])
            elif nxt not in state:
                walk(nxt)
        stack.pop()
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            walk(node)
    return cycles


# ---------------------------------------------------------------------------
# The real library
# ---------------------------------------------------------------------------

def test_the_library_has_no_layering_problem():
    assert layering_problems(library_sources()) == []


def test_the_library_has_no_import_cycle():
    assert import_cycles(library_sources()) == []


def test_only_packages_at_the_top_of_the_library():
    top = sorted(f for f in os.listdir(LIBRARY) if f.endswith(".py"))
    assert top == ["__init__.py"]
    packages = {d for d in os.listdir(LIBRARY)
                if os.path.isfile(os.path.join(LIBRARY, d, "__init__.py"))}
    assert packages == set(LAYERS)


def test_no_library_file_over_700_lines():
    long = {name: source.count("\n") for name, source in library_sources().items()
            if source.count("\n") > 700}
    assert long == {}


@pytest.mark.parametrize("package", sorted(LAYERS))
def test_every_package_says_what_it_does_and_lists_its_public_names(package):
    sources = library_sources()
    tree = ast.parse(sources["reconstruction." + package])
    assert len(ast.get_docstring(tree) or "") > 80
    names = [node for node in tree.body if isinstance(node, ast.Assign)
             and any(getattr(t, "id", None) == "__all__" for t in node.targets)]
    assert names, "reconstruction/{}/__init__.py has no __all__".format(package)
    public = ast.literal_eval(names[0].value)
    bound = {a.asname or a.name for node in tree.body if isinstance(node, ast.ImportFrom)
             for a in node.names}
    bound |= {node.name for node in tree.body
              if isinstance(node, (ast.FunctionDef, ast.ClassDef))}
    assert sorted(set(public) - bound) == []


# ---------------------------------------------------------------------------
# The checks fail where they should (a small made-up library)
# ---------------------------------------------------------------------------

CLEAN = {
    "lib": '"""x"""',
    "lib.core": "from .errors import InputError\n",
    "lib.core.errors": "class InputError(ValueError):\n    pass\n",
    "lib.geom": "",
    "lib.geom.rings": "import numpy as np\nfrom ..core.errors import InputError\n",
    "lib.grassio": "",
    "lib.grassio.maps": "import grass.script as gs\nfrom ..geom import rings\n",
    "lib.lod2": "",
    "lib.lod2.stage": ("from ..geom.rings import np\nfrom .roofs import flat\n"
                       "def f():\n    import pyvista\n"),
    "lib.lod2.roofs": "def flat():\n    pass\n",
    "lib.subdivide": "",
    "lib.subdivide.stage": "from ..core import errors\n",
}


def changed(**replace):
    sources = dict(CLEAN)
    sources.update({k.replace("_", "."): v for k, v in replace.items()})
    return sources


def test_the_made_up_library_is_clean():
    assert layering_problems(CLEAN) == [] and import_cycles(CLEAN) == []


def test_a_cycle_is_found():
    sources = changed(lib_lod2_roofs="from .stage import f\ndef flat():\n    pass\n")
    assert import_cycles(sources) == [["lib.lod2.roofs", "lib.lod2.stage", "lib.lod2.roofs"]]


def test_a_cycle_through_a_package_init_is_found():
    sources = changed(lib_core="from .errors import InputError\nfrom ..geom import rings\n")
    assert import_cycles(sources)


def test_grass_outside_grassio_is_found():
    problems = layering_problems(changed(lib_lod2_roofs="import grass.script as gs\n"))
    assert problems == ["lib.lod2.roofs line 1: imports grass.script outside grassio/"]


def test_an_internal_import_inside_a_function_is_found():
    problems = layering_problems(changed(
        lib_lod2_stage="def f():\n    from .roofs import flat\n"))
    assert problems == ["lib.lod2.stage line 2: imports lib.lod2.roofs inside a function"]


def test_a_lazy_import_not_listed_is_found():
    problems = layering_problems(changed(lib_lod2_stage="def f():\n    import json\n"))
    assert problems == ["lib.lod2.stage line 2: imports json inside a function (not in LAZY)"]


def test_a_stage_importing_another_stage_is_found():
    problems = layering_problems(changed(lib_subdivide_stage="from ..lod2 import roofs\n"))
    assert len(problems) == 1 and "subdivide imports lib.lod2.roofs" in problems[0]


def test_a_lower_layer_importing_a_higher_one_is_found():
    problems = layering_problems(changed(lib_geom_rings="from ..grassio import maps\n"))
    assert len(problems) == 1 and "geom imports lib.grassio.maps" in problems[0]


def test_a_private_name_across_packages_is_found():
    problems = layering_problems(changed(
        lib_lod2_stage="from ..core.errors import _hidden\n"))
    assert problems == ["lib.lod2.stage line 1: takes the private _hidden of core"]
