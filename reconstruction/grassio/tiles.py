"""GRASS side of r.histo.classify's segmentations and tiles.

- :func:`run_segmentations`: i.segment for every tried parameter pair, grown
  once per threshold and reseeded per minimum size, ``nprocs`` at a time;
- :func:`segment_tiles`: i.segment with the chosen pair in each tile's outer
  window;

A window's region reaches a GRASS tool through ``GRASS_REGION`` in its
environment (:func:`window_env`): the current region is never changed.
"""

import os

import numpy as np

import grass.script as gs

from .maps import read_raster
from .run import doing, finish_tool
from .temp import forget_temp_map, temp_map


def cells_env(grid, row0, row1, col0, col1):
    """Environment whose region is the cells ``[row0, row1) x [col0, col1)`` of ``grid``."""
    env = os.environ.copy()
    env["GRASS_REGION"] = gs.region_env(
        n=grid.north - row0 * grid.nsres, s=grid.north - row1 * grid.nsres,
        w=grid.west + col0 * grid.ewres, e=grid.west + col1 * grid.ewres,
        rows=row1 - row0, cols=col1 - col0)
    return env


def window_env(grid, tile):
    """Environment whose region is ``tile``'s outer window of ``grid``."""
    return cells_env(grid, tile.orow0, tile.orow1, tile.ocol0, tile.ocol1)


def _start(inputs, pair, output, memory, seeds=None, env=None):
    extra = {} if seeds is None else {"seeds": seeds, "iterations": 1}
    return gs.start_command("i.segment", group=",".join(inputs), output=output,
                            threshold=pair[0], minsize=pair[1], memory=memory, quiet=True,
                            stderr=gs.PIPE, env=env, **extra)


def _run_all(jobs, nprocs):
    """Run chains of i.segment runs, ``nprocs`` chains at a time.

    ``jobs``: lists of ``(key, start function of the previous key's output
    or None, what)``. Yields each key as its run finishes; stops the runs
    still going when the caller stops, fails or is interrupted.
    """
    jobs = [list(chain) for chain in jobs]
    running = {}
    try:
        while jobs or running:
            while jobs and len(running) < nprocs:
                chain = jobs.pop(0)
                running[id(chain)] = (chain, chain[0][1]())
            key = next(iter(running))
            chain, proc = running.pop(key)
            name, _start_run, what = chain[0]
            with doing(what):
                finish_tool(proc, "i.segment")
            # the next runs start before the caller gets this one: while it reads and
            # works on it, ``nprocs`` runs go on
            if len(chain) > 1:
                running[key] = (chain[1:], chain[1][1]())
            while jobs and len(running) < nprocs:
                waiting = jobs.pop(0)
                running[id(waiting)] = (waiting, waiting[0][1]())
            yield name
    finally:
        for _chain, proc in running.values():
            proc.terminate()
            proc.wait()


def run_segmentations(inputs, config, chains, env=None):
    """i.segment for each (threshold, minsize) pair of ``config`` (in the region
    of ``env``), run as ``chains`` of ``(pair index, seed pair index or None)``
    (r.histo.classify's ``segmentation_chains``: each threshold grown once and
    its larger minimum sizes reseeded from the previous result, one growing
    iteration). Yields (index in pairs, temporary raster name) as each run
    finishes."""
    pairs = config.pairs
    names = [temp_map("raster", "seg") for _ in pairs]

    def job(i, seed):
        return (i, lambda: _start(inputs, pairs[i], names[i], config.memory,
                                  None if seed is None else names[seed], env),
                "segmenting with threshold={}, minsize={}".format(*pairs[i]))

    chains = [[job(i, seed) for i, seed in chain]
              for chain in chains]
    for i in _run_all(chains, config.nprocs):
        yield i, names[i]


def segment_tiles(inputs, pair, tiles, grid, config):
    """i.segment with ``pair`` in the outer window of each tile, ``nprocs`` at a
    time. Yields (tile index, temporary raster name) as each finishes."""
    names = [temp_map("raster", "tile") for _ in tiles]

    def job(k):
        return (k, lambda: _start(inputs, pair, names[k], config.memory,
                                  env=window_env(grid, tiles[k])),
                "segmenting tile {} of {}".format(k + 1, len(tiles)))

    for k in _run_all([[job(k)] for k in range(len(tiles))], config.nprocs):
        yield k, names[k]


def window_criteria(inputs, windows, grid, config, chains, criterion):
    """Every pair's (VW, Moran's I) in each window of a tuning sample:
    ``criteria[w][k]`` = ``criterion(segments, bands)``, after i.segment
    (``chains`` as in :func:`run_segmentations`) in each window's region.
    The percent shown counts the segmentations, every pair in every window."""
    criteria = []
    total = len(windows) * len(config.pairs)
    for w, window in enumerate(windows):
        env = window_env(grid, window)
        bands = [read_raster(name, np.float64, env) for name in inputs]
        row = [None] * len(config.pairs)
        done = []
        for k, name in run_segmentations(inputs, config, chains, env):
            row[k] = criterion(read_raster(name, np.int32, env), bands)
            done.append(name)
            gs.percent(w * len(config.pairs) + len(done), total, 1)
        gs.run_command("g.remove", type="raster", name=",".join(done), flags="f", quiet=True)
        for name in done:
            forget_temp_map("raster", name)
        criteria.append(row)
    return criteria
