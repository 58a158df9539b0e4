"""The README's tutorial as data, for the tests that keep it true.

- :func:`stage_commands`: the commands of its "Stage N" sections (one string
  each, continuation lines joined);
- :func:`chain_commands`: the command lines of demo/chain.sh itself, with
  its parameters put in (its stage 1 and pictures; the modules run in the
  stage functions of demo/steps.sh);
- :func:`module_commands` / :func:`printed_commands`: the tutorial's module
  commands, and those a run of the chain printed ("--- run: ..."), as
  comparable tuples;
- :func:`quoted_outputs`: what its stage sections quote of the modules'
  messages (backticked spans of several words), pieces split at "...".
"""

import os
import re

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHAIN = os.path.join(ROOT, "demo", "chain.sh")
# Names the chain sets itself (its output folder, its own folder): kept as written.
KEPT = {"OUT", "HERE"}


def _read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def _joined(text):
    return text.replace("\\\n", " ")


def _normal(command):
    return " ".join(command.split())


def stage_sections(readme=None):
    """The text of each "### Stage N" section of the README's "## Tutorial"."""
    text = readme if readme is not None else _read(os.path.join(ROOT, "README.md"))
    tutorial = text.split("\n## Tutorial\n", 1)[1].split("\n## ", 1)[0]
    return [part for part in re.split(r"\n(?=### )", tutorial) if part.startswith("### Stage")]


def stage_commands(readme=None):
    commands = []
    for section in stage_sections(readme):
        for block in re.findall(r"```sh\n(.*?)```", section, re.S):
            commands += [_normal(line) for line in _joined(block).splitlines() if line.strip()]
    return commands


def quoted_outputs(readme=None):
    pieces = []
    for section in stage_sections(readme):
        prose = re.sub(r"```.*?```", "", section, flags=re.S)
        for span in re.findall(r"`([^`]+)`", prose):
            if span.count(" ") >= 3:
                pieces += [_normal(p) for p in span.split("...") if p.strip()]
    return pieces


def chain_commands(path=CHAIN):
    """demo/chain.sh's command lines, its variables replaced by their last value."""
    text = _joined(_read(path))
    values = {}
    for name, value in re.findall(r"(?:^|;\s*|then\s+)([A-Z][A-Z_]*)=(\"[^\"]*\"|[^\s;]*)",
                                  text, re.M):
        if name not in KEPT and value.strip('"'):
            # a value the environment may set (SEED=${SEED:-1}): its default
            default = re.fullmatch(r"\$\{" + name + r":-([^}]*)\}", value.strip('"'))
            values[name] = default.group(1) if default else value.strip('"')

    def expand(line):
        for _ in range(5):  # values that name other variables
            line = re.sub(r"\$\{([A-Z][A-Z_]*)\}|\$([A-Z][A-Z_]*)\b",
                          lambda m: values.get(m.group(1) or m.group(2), m.group(0)), line)
        return line.replace('"$HERE/../', "").replace('"$HERE/', "demo/")

    commands = []
    for line in text.splitlines():
        line = line.split(" # ", 1)[0].strip()
        if line and not line.startswith("#"):
            commands.append(_normal(expand(line)).replace('.py"', ".py"))
    return commands


#: the output folder as the tutorial writes it ("$OUT/name") and as compared
OUT_MARK = "<OUT>"


def _comparable(command):
    """A module command as (module, its sorted arguments): GRASS options
    mean the same in any order."""
    words = command.split()
    return (words[0], tuple(sorted(words[1:])))


def module_commands(readme=None):
    """The tutorial's commands of the suite's modules (``r.histo.*``, ``v.histo.*``)."""
    return [_comparable(re.sub(r'"\$OUT/([^"]*)"', OUT_MARK + r"/\1", c))
            for c in stage_commands(readme) if re.match(r"[rv]\.histo\.", c)]


def printed_commands(log, out):
    """The module commands a chain run printed, its output folder ``out`` marked."""
    return [_comparable(_normal(line.split("--- run: ", 1)[1].replace(str(out), OUT_MARK)))
            for line in log.splitlines() if line.startswith("--- run: ")]
