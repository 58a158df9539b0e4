"""Files written whole or not at all, through links, never over devices (issue 12, item 6)."""

import os
import pathlib
import stat

import pytest

from reconstruction.core import crs as epsg
from reconstruction.core import safefile
from reconstruction.core.errors import InputError
from reconstruction.core.options import integer_column


def test_a_new_file_gets_the_usual_permissions_and_no_temporary_file_remains(tmp_path):
    path = tmp_path / "a.json"
    safefile.write_text(str(path), "new")
    assert path.read_text() == "new"
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask
    assert os.listdir(str(tmp_path)) == ["a.json"]


def test_a_replaced_file_keeps_its_permissions_and_a_part_file_is_left_alone(tmp_path):
    path = tmp_path / "a.json"
    path.write_text("old")
    path.chmod(0o640)
    (tmp_path / "a.json.part").write_text("someone's")
    safefile.write_text(str(path), "new")
    assert path.read_text() == "new" and stat.S_IMODE(path.stat().st_mode) == 0o640
    assert (tmp_path / "a.json.part").read_text() == "someone's"


def test_a_failure_leaves_the_old_file_and_nothing_else(tmp_path):
    path = tmp_path / "a.csv"
    path.write_text("old")
    with pytest.raises(RuntimeError):
        with safefile.replacing(str(path), newline="") as f:
            f.write("half")
            raise RuntimeError("interrupted")
    assert path.read_text() == "old" and os.listdir(str(tmp_path)) == ["a.csv"]


def test_a_link_is_written_through(tmp_path):
    target = tmp_path / "sub" / "model.json"
    target.parent.mkdir()
    target.write_text("old")
    link = tmp_path / "link.json"
    link.symlink_to(target)
    safefile.write_text(str(link), "new")
    assert link.is_symlink() and target.read_text() == "new"
    assert sorted(os.listdir(str(target.parent))) == ["model.json"]


@pytest.mark.parametrize("path", ["/dev/null", "/dev/full", "/"])
def test_something_else_than_a_regular_file_is_never_replaced(path):
    with pytest.raises(InputError, match="not a regular file"):
        safefile.write_text(path, "x")



def test_files_written_together_appear_together(tmp_path):
    model, picture = tmp_path / "m.json", tmp_path / "m.png"
    model.write_text("old model")
    with safefile.together() as files:
        with open(files.reserve(str(model)), "w") as f:
            f.write("new model")
        assert model.read_text() == "old model"      # nothing is in place before the end
        with files.open(str(picture), "wb") as f:
            f.write(b"png")
    assert model.read_text() == "new model" and picture.read_bytes() == b"png"
    assert sorted(os.listdir(str(tmp_path))) == ["m.json", "m.png"]


@pytest.mark.parametrize("failure", [KeyboardInterrupt, RuntimeError, SystemExit])
def test_a_failure_after_one_file_of_a_set_leaves_every_target_as_it_was(tmp_path, failure):
    model, picture = tmp_path / "m.json", tmp_path / "m.png"
    model.write_text("old model")
    with pytest.raises(failure):
        with safefile.together() as files:
            with files.open(str(model)) as f:
                f.write("new model")
            files.reserve(str(picture), ".png")
            raise failure()
    assert model.read_text() == "old model" and os.listdir(str(tmp_path)) == ["m.json"]


def test_an_output_whose_directory_cannot_hold_it_is_named_before_anything_is_written(tmp_path):
    model = tmp_path / "m.json"
    model.write_text("old model")
    with pytest.raises(InputError, match=r"Cannot write '/proc/x.png'"):
        with safefile.together() as files:
            files.reserve(str(model))
            files.reserve("/proc/x.png", ".png")
    assert model.read_text() == "old model" and os.listdir(str(tmp_path)) == ["m.json"]


def test_one_file_twice_in_a_set_is_refused(tmp_path):
    link = tmp_path / "link.json"
    link.symlink_to(tmp_path / "m.json")
    with pytest.raises(InputError, match="given twice"):
        with safefile.together() as files:
            files.reserve(str(tmp_path / "m.json"))
            files.reserve(str(link))
    assert sorted(os.listdir(str(tmp_path))) == ["link.json"]


def test_an_interruption_during_the_renames_waits_until_every_file_is_in_place(tmp_path,
                                                                                monkeypatch):
    import signal

    paths = [tmp_path / "{}.json".format(i) for i in range(3)]
    replace = os.replace
    seen = []

    def replace_and_interrupt(tmp, target):
        replace(tmp, target)
        seen.append(target)
        if len(seen) == 1:
            signal.raise_signal(signal.SIGINT)       # Ctrl-C after the first rename

    monkeypatch.setattr(safefile.os, "replace", replace_and_interrupt)
    with pytest.raises(KeyboardInterrupt):
        with safefile.together() as files:
            for path in paths:
                with files.open(str(path)) as f:
                    f.write("new")
    assert len(seen) == 3 and all(p.read_text() == "new" for p in paths)
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler

def test_epsg_codes():
    if epsg.proj_db() is None:
        pytest.skip("PROJ's proj.db is not installed")
    assert epsg.known(28992) and epsg.known(7415)
    assert not epsg.known(999999999) and not epsg.known(1)


def test_epsg_codes_without_proj_db_are_checked_for_plausibility(tmp_path):
    missing = str(tmp_path / "proj.db")
    assert epsg.known(28992, missing) and not epsg.known(999999999, missing)


def test_integer_columns_refuse_fractions_and_text():
    assert integer_column([1, 2.0, "3", None, ""], "plot", "m") == [1, 2, 3, None, None]
    for bad in (1.5, "two", float("nan"), float("inf")):
        with pytest.raises(InputError, match="Column <plot> of vector map <m> must hold whole"):
            integer_column([1, bad], "plot", "m")


def test_a_directory_is_written_whole_with_its_files_or_not_at_all(tmp_path):
    # issue 52, item 2 (tiles=): a directory output appears with a file, replaces an old
    # one whole (its files gone), and a failure leaves the old one and no temporary one
    target = tmp_path / "tiles"
    with safefile.together() as files:
        (pathlib.Path(files.reserve_dir(str(target))) / "a.json").write_text("1")
        model = files.reserve(str(tmp_path / "model.json"))
        pathlib.Path(model).write_text("m")
        assert not target.exists()
    assert (target / "a.json").read_text() == "1" and (tmp_path / "model.json").exists()
    assert stat.S_IMODE(os.stat(target).st_mode) & 0o700 == 0o700
    with safefile.together() as files:
        (pathlib.Path(files.reserve_dir(str(target))) / "b.json").write_text("2")
    assert sorted(os.listdir(target)) == ["b.json"]
    with pytest.raises(RuntimeError):
        with safefile.together() as files:
            (pathlib.Path(files.reserve_dir(str(target))) / "c.json").write_text("3")
            raise RuntimeError("failed while writing")
    assert sorted(os.listdir(target)) == ["b.json"]
    assert sorted(os.listdir(tmp_path)) == ["model.json", "tiles"]
    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError, match="is not a directory"):
        with safefile.together() as files:
            files.reserve_dir(str(tmp_path / "file"))
