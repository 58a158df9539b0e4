"""r.histo.classify in tiles (memory= smaller than the map): the same classes as one tile."""

import numpy as np
import pytest

pytestmark = pytest.mark.grass

SIDE = 400  # metres (cells) of the cut of the synthetic map


@pytest.fixture
def cut(synthetic, mapset):
    """The north-west 400 x 400 m of the synthetic map and its training points."""
    import grass.script as gs

    r = synthetic.region
    gs.run_command("g.region", n=r["n"], s=r["n"] - SIDE, w=r["w"], e=r["w"] + SIDE, res=r["res"])
    gs.run_command("v.in.region", output="box", quiet=True)
    gs.run_command("v.select", ainput=synthetic.training, binput="box", output="train_cut",
                   operator="overlap", quiet=True)
    smap = synthetic.smap
    rows, cols = smap.to_pixel(smap.training["xy"])
    labels = set(int(v) for v in smap.training["label"][(rows < SIDE) & (cols < SIDE)])
    return synthetic, sorted(labels & {2, 6})


def _classify(syn, remove, output, **kwargs):
    """Run the module (verbose); returns what it wrote on stderr."""
    import grass.script as gs

    return gs.read_command("r.histo.classify", input="{},{},{}".format(syn.red, syn.green, syn.blue),
                           training="train_cut", output=output, remove=",".join(map(str, remove)),
                           seed=1, nprocs=2, verbose=True, stderr=gs.STDOUT, **kwargs)


def test_tiled_run_agrees_with_one_tile(cut):
    import grass.script as gs

    from reconstruction import grassio

    syn, remove = cut
    assert remove, "the cut holds training points of text or symbols"
    assert "tiles" not in _classify(syn, remove, "whole")
    # memory=20 MB: outer windows of 277 cells, 9 tiles of the 400 x 400 cut
    assert "segmenting 9 tiles" in " ".join(_classify(syn, remove, "tiled", memory=20).split())
    whole = grassio.read_raster("whole", dtype=np.int32)
    tiled = grassio.read_raster("tiled", dtype=np.int32)
    both = (whole > 0) & (tiled > 0)
    agreement = float((whole[both] == tiled[both]).mean())
    print("tiled (9 tiles) and one tile agree on {:.2%} of {} cells".format(agreement, both.sum()))
    assert both.mean() > 0.99
    # tiles this small are mostly overlap (64 cells a side): 98.1 % when measured; the
    # issue's 99 % is for the default memory= (tiles of about 1,000 cells) on 16 megapixels
    assert agreement >= 0.975
    assert not gs.list_strings("raster", pattern="tmp_histo_*")
