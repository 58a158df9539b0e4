"""A scan's colour planes registered to each other (reconstruction.geom.registration)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reconstruction.geom import registration
from reconstruction.geom.grid import MapImage


def drawn_map(seed=1, size=120):
    """Three bands of one drawing: rectangles of random colours on paper, a
    little noise; every edge in every band."""
    rng = np.random.default_rng(seed)
    rgb = np.empty((size, size, 3))
    rgb[:] = (238.0, 231.0, 212.0)
    for _ in range(40):
        r0, c0 = rng.integers(0, size - 10, 2)
        h, w = rng.integers(4, 30, 2)
        rgb[r0:r0 + h, c0:c0 + w] = rng.uniform(40, 240, 3)
    rgb += rng.normal(0, 3, rgb.shape)
    return [rgb[..., k] for k in range(3)]


def moved(band, shift):
    """``band`` with its content ``shift`` (rows, cols) cells south / east (what
    a misregistered plane looks like), wrapped round at the edges."""
    return np.roll(band, shift, axis=(0, 1))


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2), st.integers(-2, 2), st.integers(-2, 2), st.integers(0, 1000))
def test_a_band_off_by_whole_cells_is_found_and_moved_back(which, dr, dc, seed):
    bands = drawn_map(seed)
    truth = [b.copy() for b in bands]
    bands[which] = moved(bands[which], (dr, dc))
    found = registration.band_shifts(bands)
    expected = [(0, 0)] * 3
    expected[which] = (dr, dc)
    assert list(found.shifts) == expected
    assert found.moved == ([] if (dr, dc) == (0, 0) else [which])
    back = registration.registered(bands[which], found.shifts[which])
    inner = (slice(2, -2), slice(2, -2))
    assert np.array_equal(back[inner], truth[which][inner])


def test_bands_in_register_stay_and_say_so_quietly():
    bands = drawn_map(3)
    found = registration.band_shifts(bands)
    assert found.shifts == ((0, 0),) * 3 and not found.moved
    message = found.message(["r", "g", "b"])
    assert message.level == "verbose"
    image = MapImage(np.dstack(bands).clip(0, 255).astype(np.uint8), (0, 120, 0, 120))
    assert registration.register_image(image, registration.image_shifts(image)) is image


def test_a_moved_band_is_named_with_its_shift():
    bands = drawn_map(4)
    bands[0] = moved(bands[0], (0, 1))
    found = registration.band_shifts(bands)
    names = ["map.red", "map.green", "map.blue"]
    message = found.message(names)
    assert message.level == "message"
    assert "<map.red> lies 1 cell east of <map.green>" in message.text
    left = found.message(names, registered=False)
    assert left.level == "warning" and "flag -b" in left.text
    rgb = np.dstack(bands).clip(0, 255).astype(np.uint8)
    image = MapImage(rgb, (0, 120, 0, 120))
    back = registration.register_image(image, registration.image_shifts(image)).rgb
    assert np.array_equal(back[:, :-1, 0], rgb[:, 1:, 0])      # red moved back a cell
    assert np.array_equal(back[..., 1:], rgb[..., 1:])


def test_one_ink_printed_out_of_register_moves_no_band():
    # a colour plate printed a cell off: its ink moves, seen in every band;
    # the black lines stay where they are in all three
    rng = np.random.default_rng(5)
    size = 120
    rgb = np.full((size, size, 3), (238.0, 231.0, 212.0))
    for _ in range(25):                          # red ink, one cell east of its place
        r0, c0 = rng.integers(0, size - 20, 2)
        rgb[r0:r0 + 12, c0 + 1:c0 + 17] = (230.0, 120.0, 110.0)
    for _ in range(25):                          # black lines
        r0, c0 = rng.integers(0, size - 20, 2)
        rgb[r0, c0:c0 + 18] = rgb[r0:r0 + 18, c0] = (30.0, 30.0, 30.0)
    rgb += rng.normal(0, 3, rgb.shape)
    assert not registration.band_shifts([rgb[..., k] for k in range(3)]).moved


def test_registered_takes_what_r_mapcalc_takes():
    band = np.arange(12.0).reshape(3, 4)
    back = registration.registered(band, (1, -1))     # out = band[1,-1]
    assert back[0, 1] == band[1, 0] and back[1, 3] == band[2, 2]
    # nothing to take along the edges: the cell's own value
    assert (back[2] == band[2]).all() and (back[:, 0] == band[:, 0]).all()


def test_no_data_is_left_out_of_the_estimate():
    bands = drawn_map(6)
    bands[2] = moved(bands[2], (-1, 0))
    for b in bands:
        b[:30, :30] = np.nan
    assert registration.band_shifts(bands).shifts == ((0, 0), (0, 0), (-1, 0))


@pytest.mark.parametrize("count", [1, 2])
def test_fewer_bands(count):
    bands = drawn_map(7)[:count]
    assert registration.band_shifts(bands).shifts == ((0, 0),) * count


def test_the_estimate_reads_the_central_window_only():
    assert registration.central_window((3000, 500)) == (988, 2012, 0, 500)
    bands = drawn_map(8, size=120)
    bands[1] = moved(bands[1], (1, 0))
    # a map larger than the window, no data around the drawing: the same shifts
    wide = [np.pad(b, 600, mode="constant", constant_values=np.nan) for b in bands]
    assert registration.band_shifts(wide).shifts == registration.band_shifts(bands).shifts
