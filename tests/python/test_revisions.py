"""revisions and processes: the build cache of regress and bisect, and children that end with them."""
import hashlib
import json
import os
import subprocess
import sys
import time

import pytest

from heightmarch_tools import processes, revisions
from heightmarch_tools.errors import Unusable
from heightmarch_tools.speed_check import Verdict, verdict


def test_settings_come_from_the_current_build(tmp_path):
    (tmp_path / "CMakeCache.txt").write_text("# comment\nCMAKE_BUILD_TYPE:STRING=Debug\nCMAKE_CXX_FLAGS:STRING=-O1\n"
                                             "OTHER:BOOL=ON\n")
    assert revisions.build_settings(str(tmp_path)) == {"CMAKE_BUILD_TYPE": "Debug", "CMAKE_CXX_FLAGS": "-O1"}
    assert revisions.build_settings(str(tmp_path / "none")) == {"CMAKE_BUILD_TYPE": "Release"}


def built(tmp_path, commit, name="build"):
    """A build directory holding a heightmarch-bench and a worker built from commit."""
    build = tmp_path / name
    build.mkdir()
    (build / "heightmarch-bench").write_bytes(b"\x7fELF...kBuildCommit=" + commit[:12].encode() + b"\0...")
    (build / "heightmarch-glsl-worker").write_bytes(b"worker " + commit[:12].encode())
    return str(build / "heightmarch-bench")


def stored(cache, tmp_path, commit, monkeypatch):
    """commit stored in cache as a build of it is stored (build_in, with the build itself faked)."""
    binary = built(tmp_path, commit, "build-" + commit[:6])
    monkeypatch.setattr(revisions, "build", lambda tree, build_dir, log, settings: binary)
    return cache.build_in(str(tmp_path), os.path.dirname(binary), commit, lambda line: None)


def test_the_cache_is_keyed_by_commit_and_settings(tmp_path, monkeypatch):
    release = revisions.BuildCache(str(tmp_path), {"CMAKE_BUILD_TYPE": "Release"})
    debug = revisions.BuildCache(str(tmp_path), {"CMAKE_BUILD_TYPE": "Debug"})
    commit = "a" * 40
    assert release.entry(commit) != debug.entry(commit) != debug.entry("b" * 40)
    assert release.lookup(commit) is None
    assert stored(release, tmp_path, commit, monkeypatch) == os.path.join(release.entry(commit), "heightmarch-bench")
    assert release.lookup(commit) == os.path.join(release.entry(commit), "heightmarch-bench")
    assert debug.lookup(commit) is None
    record = json.loads((tmp_path / revisions.CACHE / os.path.basename(release.entry(commit)) / "build.json").read_text())
    assert record["commit"] == commit and set(record["checksums"]) == {"heightmarch-bench", "heightmarch-glsl-worker"}


def planted(cache, commit, files):
    """An entry of commit holding files ({name: bytes or text}), as someone might plant it."""
    os.makedirs(cache.entry(commit))
    for name, content in files.items():
        path = os.path.join(cache.entry(commit), name)
        with open(path, "wb") as f:
            f.write(content if isinstance(content, bytes) else content.encode())


@pytest.mark.parametrize("forgery, why", [
    ("no record", "no build.json"),
    ("another commit", "its build.json names another commit"),
    ("other settings", "its build.json names other settings"),
    ("no checksums", "its build.json holds no checksums"),
    ("binary replaced", "heightmarch-bench is not the file its build.json names"),
    ("extra file", "it holds planted.so, which its build.json does not name"),
    ("another commit's binary", "its heightmarch-bench was not built from aaaaaaaaaaaa"),
])
def test_an_entry_that_does_not_prove_what_it_holds_is_never_trusted(tmp_path, monkeypatch, forgery, why):
    cache = revisions.BuildCache(str(tmp_path), {"CMAKE_BUILD_TYPE": "Release"})
    commit, other = "a" * 40, "b" * 40
    binary = b"kBuildCommit=" + (other if forgery == "another commit's binary" else commit)[:12].encode()
    checksum = hashlib.sha256(binary).hexdigest()
    record = {"commit": other if forgery == "another commit" else commit,
              "settings": {"CMAKE_BUILD_TYPE": "Debug"} if forgery == "other settings" else cache.settings,
              "checksums": {"heightmarch-bench": checksum}}
    if forgery == "no checksums":
        del record["checksums"]
    files = {"heightmarch-bench": b"#!/bin/sh\necho planted" if forgery == "binary replaced" else binary}
    if forgery != "no record":
        files["build.json"] = json.dumps(record)
    if forgery == "extra file":
        files["planted.so"] = b"x"
    planted(cache, commit, files)
    said = []
    assert cache.trusted(commit) == why
    assert cache.lookup(commit, said.append) is None
    assert not os.path.lexists(cache.entry(commit)) and why in said[0]  # removed, to be built again


def test_a_cache_that_links_elsewhere_is_refused_and_never_written_through(tmp_path, monkeypatch):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (tmp_path / "build").mkdir()
    os.symlink(elsewhere, tmp_path / "build" / revisions.CACHE)
    cache = revisions.BuildCache(str(tmp_path / "build"), {})
    for use in (cache.checked_dir, lambda: cache.lookup("a" * 40), lambda: cache.record(build_seconds=1.0),
                cache.current_build_log, lambda: stored(cache, tmp_path, "a" * 40, monkeypatch)):
        with pytest.raises(Unusable, match="regress-cache: is a link, not a directory"):
            use()
    assert os.listdir(elsewhere) == []


def test_a_link_planted_at_a_build_log_is_not_written_through(tmp_path):
    cache = revisions.BuildCache(str(tmp_path), {})
    target = tmp_path / "target"
    target.write_text("kept")
    cache.checked_dir()
    os.symlink(target, os.path.join(cache.dir, "current-build.log"))
    with pytest.raises(Unusable, match="cannot write the build log"):
        cache.current_build_log()
    assert target.read_text() == "kept"


def test_the_cache_keeps_the_latest_builds_and_drops_what_a_killed_run_left(tmp_path):
    cache = revisions.BuildCache(str(tmp_path), {})
    def commit(i):
        return "%02d" % i + "0" * 38

    for i in range(revisions.MAX_ENTRIES + 2):
        os.makedirs(cache.entry(commit(i)))
        stamp = os.path.join(cache.entry(commit(i)), "build.json")
        open(stamp, "w").close()
        os.utime(stamp, (1000 + i, 1000 + i))
    dead = os.path.join(cache.dir, "%s999999999-x" % revisions.INCOMING)  # no such process
    os.makedirs(dead)
    cache.evict()
    kept = sorted(os.listdir(cache.dir))
    assert len(kept) == revisions.MAX_ENTRIES and not os.path.exists(dead)
    assert not any(k.startswith((commit(0)[:12], commit(1)[:12])) for k in kept)  # the oldest went


def test_timings_are_kept_for_estimates(tmp_path):
    cache = revisions.BuildCache(str(tmp_path), {})
    assert cache.timings() == {}
    cache.record(build_seconds=300.0)
    cache.record(round_seconds=4.5)
    assert cache.timings() == {"build_seconds": 300.0, "round_seconds": 4.5}
    (tmp_path / revisions.CACHE / "timings.json").write_text("NaN")
    assert cache.timings() == {}  # only estimates: a bad file is no figure, never an error


def test_a_broken_wait_ends_the_childs_whole_group(tmp_path):
    pids = tmp_path / "pids"
    child = subprocess.Popen(["sh", "-c", "sleep 60 & echo $$ $! > %s; wait" % pids], process_group=0)
    for _ in range(200):
        if pids.exists() and pids.read_text().strip():
            break
        time.sleep(0.05)
    processes.end_group(child)
    time.sleep(0.1)
    for pid in map(int, pids.read_text().split()):
        try:
            os.kill(pid, 0)
            alive = subprocess.run(["ps", "-o", "stat=", "-p", str(pid)], capture_output=True, text=True).stdout
            assert alive.strip().startswith("Z") or not alive.strip(), "process %d outlived its group's end" % pid
        except ProcessLookupError:
            pass
    assert processes.run([sys.executable, "-c", "print(2)"], stdout=subprocess.PIPE, text=True).stdout == "2\n"


def test_the_verdict_line():
    def v(name, speed, improved=False, regressed=False):
        return Verdict((name, name), speed, 0.01, (speed, speed, speed), improved, regressed)

    assert verdict([v("a", 0.99), v("b", 1.0)], 0.01) == ("no regression: none of 2 benchmarks slower by more than 1%", 0)
    line, code = verdict([v("a", 0.9, regressed=True), v("b", 0.8, regressed=True), v("c", 1.2, improved=True)], 0.01)
    assert code == 1 and line.startswith("REGRESSION: 2 of 3 benchmarks slower by more than 1% (slowest: b at 0.800")
    line, code = verdict([v("a", 1.1, improved=True), v("b", 1.0)], 0.01)
    assert code == 0 and line.startswith("improvement: 1 of 2 benchmarks faster by more than 1%, none slower")
