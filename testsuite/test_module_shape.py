"""The five module scripts share one shape (issue 27): after the g.parser
header they parse (the stage's ``read_config``), read (grassio), run (the
stage's entry point), write (grassio) and print the stage's report, in at
most 100 lines of code; options become values in the stages' ``config.py``
only.

The checks are functions over source text, shown failing on a made-up
script as well as passing on the real ones.
"""

import ast
import io
import os
import re
import tokenize

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODULES = ("r.histo.classify", "v.histo.generalize", "v.histo.align", "v.histo.subdivide",
           "v.histo.lod2", "v.histo.timeline")
MAX_LINES = 100

# an option's text cast, or split, where it is read
CAST = re.compile(r"\b(int|float)\(\s*(options|opts)\s*\[|"
                  r"\b(options|opts)\s*\[[^\]]+\]\s*(or\s+[^)]+)?\)?\s*\.split\(|"
                  r"\b(options|opts)\s*\[[^\]]+\]\.split\(")


def code_lines_after_header(source):
    """The lines of code after the g.parser header (its last ``# %end``):
    blank lines, comments and docstrings not counted."""
    lines = source.split("\n")
    ends = [k for k, line in enumerate(lines) if line.strip() == "# %end"]
    start = ends[-1] + 1 if ends else 0
    body = "\n".join(lines[start:])
    docstrings = set()
    for node in ast.walk(ast.parse(body)):
        if isinstance(node, (ast.Module, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            first = node.body[0] if node.body else None
            if (isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
                    and isinstance(first.value.value, str)):
                docstrings.update(range(first.lineno, first.end_lineno + 1))
    code = set()
    for tok in tokenize.generate_tokens(io.StringIO(body).readline):
        if tok.type in (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT,
                        tokenize.DEDENT, tokenize.ENDMARKER):
            continue
        code.update(n for n in range(tok.start[0], tok.end[0] + 1) if n not in docstrings)
    return len(code)


def option_casts(source):
    """Lines that cast or split an option's text themselves."""
    return [line.strip() for line in source.split("\n") if CAST.search(line)]


def _script(module):
    with open(os.path.join(ROOT, module, module + ".py"), encoding="utf-8") as f:
        return f.read()


@pytest.mark.parametrize("module", MODULES)
def test_script_is_at_most_100_lines_of_code_after_its_header(module):
    assert code_lines_after_header(_script(module)) <= MAX_LINES


@pytest.mark.parametrize("module", MODULES)
def test_script_casts_no_option_itself(module):
    assert option_casts(_script(module)) == []


def test_options_become_values_in_the_stages_config_only():
    found = {}
    library = os.path.join(ROOT, "reconstruction")
    for folder, dirs, files in os.walk(library):
        dirs[:] = [d for d in dirs if d not in ("testsuite", "__pycache__")]
        for name in files:
            path = os.path.join(folder, name)
            if name.endswith(".py") and name != "config.py":
                with open(path, encoding="utf-8") as f:
                    casts = option_casts(f.read())
                if casts:
                    found[os.path.relpath(path, library)] = casts
    assert found == {}


def description_problems(source):
    """Options whose ``descriptions:`` do not pair each listed value with one
    text: g.parser splits them at every ``;``, so a ``;`` inside a text
    makes a "Bug in UI description" warning at every run."""
    problems = []
    for block in re.findall(r"# %option\n(.*?)# %end", source, re.S):
        fields = dict(re.findall(r"# % (\w+): (.*)", block))
        if "descriptions" not in fields:
            continue
        parts = fields["descriptions"].split(";")
        values = set(fields.get("options", "").split(","))
        keys = parts[0::2]
        if len(parts) % 2 or not set(keys) <= values:
            problems.append((fields.get("key"), [k for k in keys if k not in values]))
    return problems


@pytest.mark.parametrize("module", MODULES)
def test_every_option_description_pairs_a_listed_value(module):
    assert description_problems(_script(module)) == []


@pytest.mark.parametrize("stage", ("classify", "generalize", "align", "subdivide", "lod2"))
def test_every_stage_has_one_config_one_entry_point_and_one_report(stage):
    package = os.path.join(ROOT, "reconstruction", stage)
    with open(os.path.join(package, "config.py"), encoding="utf-8") as f:
        config = ast.parse(f.read())
    assert "read_config" in {n.name for n in config.body if isinstance(n, ast.FunctionDef)}
    with open(os.path.join(package, "__init__.py"), encoding="utf-8") as f:
        init = ast.parse(f.read())
    public = next(ast.literal_eval(n.value) for n in init.body if isinstance(n, ast.Assign)
                  and any(getattr(t, "id", None) == "__all__" for t in n.targets))
    assert {"read_config", "run", "report"} <= set(public)


# ---------------------------------------------------------------------------
# The checks fail where they should
# ---------------------------------------------------------------------------

MADE_UP = '''#!/usr/bin/env python3
"""A module."""
# %module
# % description: x
# %end
# %option
# % key: year
# %end

import sys


def main(options, flags):
    """Docstring lines
    are not code."""
    # nor are comments
    year = int(options["year"])
    names = options["input"].split(",")

    return year, names
'''


def test_a_semicolon_inside_a_description_is_found():
    header = ("# %option\n# % key: features\n# % options: a,b\n"
              "# % descriptions: a;first (x; y);b;second\n# %end\n")
    assert description_problems(header) == [("features", [" y)", "second"])]
    assert description_problems(header.replace("x; y", "x, y")) == []


def test_the_counter_counts_code_only():
    assert code_lines_after_header(MADE_UP) == 5


def test_a_cast_option_is_found():
    assert option_casts(MADE_UP) == ['year = int(options["year"])',
                                     'names = options["input"].split(",")']
    assert option_casts('seed = int(options["seed"] or 1)') == ['seed = int(options["seed"] or 1)']
    assert option_casts('x = parse_list(options["input"])') == []
