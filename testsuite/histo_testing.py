"""Helpers shared by the module tests (on sys.path through the root conftest.py)."""


def run_module(module, flags="", **kwargs):
    """Run a GRASS module; return its exit code, standard output and error as text."""
    import grass.script as gs

    proc = gs.start_command(module, flags=flags, stdout=gs.PIPE, stderr=gs.PIPE, **kwargs)
    out, err = proc.communicate()
    return proc.returncode, gs.decode(out), gs.decode(err)


def key_values(stdout):
    """The key=value lines a module prints (flag -g, -v, ...) as a dict of strings."""
    return dict(line.split("=", 1) for line in stdout.splitlines() if "=" in line)
