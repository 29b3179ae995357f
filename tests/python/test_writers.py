"""writers: whole files, and a lock two processes share."""
import multiprocessing
import os
import time

import pytest

from heightmarch_tools import writers
from heightmarch_tools.errors import CannotWrite, Unusable


def test_atomic_write_replaces_whole_and_leaves_no_temporary(tmp_path):
    path = tmp_path / "f.txt"
    writers.atomic_write(str(path), "one")
    writers.atomic_write(str(path), "two")
    assert path.read_text() == "two" and oct(path.stat().st_mode & 0o777) == "0o644"
    assert sorted(os.listdir(tmp_path)) == ["f.txt"]


def test_atomic_write_into_a_missing_directory_is_one_line(tmp_path):
    with pytest.raises(CannotWrite) as e:
        writers.atomic_write(str(tmp_path / "none" / "f.txt"), "x")
    assert "cannot write" in str(e.value)


def _append_under_lock(path, text, hold):
    with writers.locked(path):
        before = open(path).read() if os.path.exists(path) else ""
        time.sleep(hold)  # a read-modify-write that takes a while
        writers.atomic_write(path, before + text)


def test_lock_serialises_two_read_modify_writes(tmp_path):
    path = str(tmp_path / "history.csv")
    workers = [multiprocessing.Process(target=_append_under_lock, args=(path, "%d\n" % i, 0.2)) for i in range(4)]
    for w in workers:
        w.start()
    for w in workers:
        w.join(30)
    assert sorted(open(path).read().split()) == ["0", "1", "2", "3"]


def test_lock_refuses_a_planted_link(tmp_path):
    os.symlink("/etc/passwd", tmp_path / "h.csv.lock")
    with pytest.raises(CannotWrite):
        with writers.locked(str(tmp_path / "h.csv")):
            pass


def test_a_subdirectory_of_the_run_is_never_a_link(tmp_path):
    (tmp_path / "elsewhere").mkdir()
    assert writers.subdirectory(str(tmp_path), "plots") == str(tmp_path / "plots") and (tmp_path / "plots").is_dir()
    os.symlink(tmp_path / "elsewhere", tmp_path / "linked")
    with pytest.raises(Unusable) as e:
        writers.subdirectory(str(tmp_path), "linked")
    assert str(e.value).endswith("linked: is a link, not a directory of the run's own to write into")


def test_a_plot_replaces_a_planted_link_instead_of_writing_through_it(tmp_path):
    from heightmarch_tools import report_plots
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me\n")
    os.symlink(victim, tmp_path / "plot.png")
    report_plots.save(report_plots.plt.figure(figsize=(2, 2)), str(tmp_path / "plot.png"))
    assert victim.read_text() == "keep me\n" and not os.path.islink(tmp_path / "plot.png")
