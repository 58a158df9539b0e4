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


def run_in_latlong(dbase, name, *command):
    """Run a command in a lat/long (EPSG:4326) location ``name`` under ``dbase``.

    The location is made on first use; the command runs in its own GRASS
    session (not the test session). Returns the location path and the
    finished process (text output).
    """
    import os
    import subprocess

    location = os.path.join(dbase, name)
    if not os.path.isdir(location):
        subprocess.run(["grass", "-c", "EPSG:4326", location, "-e"], check=True,
                       capture_output=True)
    env = dict(os.environ)
    env.pop("GISRC", None)
    proc = subprocess.run(["grass", os.path.join(location, "PERMANENT"), "--exec"] + list(command),
                          capture_output=True, text=True, env=env)
    return location, proc


def failing_tool_env(directory, *tools):
    """An environment whose PATH finds a fake of each GRASS tool ``tools`` first in
    ``directory``: it prints an ERROR: line and fails, as a tool that breaks
    inside a module would. Pass it as ``env=`` to the module run."""
    import os

    os.makedirs(str(directory), exist_ok=True)
    for tool in tools:
        path = os.path.join(str(directory), tool)
        with open(path, "w") as f:
            f.write("#!/bin/sh\necho \"ERROR: {} failed on purpose (test)\" >&2\nexit 1\n".format(
                tool))
        os.chmod(path, 0o755)
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(directory), env["PATH"]])
    return env
