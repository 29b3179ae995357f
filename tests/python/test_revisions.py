"""revisions and processes: the build cache of regress and bisect, and children that end with them."""
import os
import subprocess
import sys
import time

from heightmarch_tools import processes, revisions
from heightmarch_tools.speed_check import Verdict, verdict


def test_settings_come_from_the_current_build(tmp_path):
    (tmp_path / "CMakeCache.txt").write_text("# comment\nCMAKE_BUILD_TYPE:STRING=Debug\nCMAKE_CXX_FLAGS:STRING=-O1\n"
                                             "OTHER:BOOL=ON\n")
    assert revisions.build_settings(str(tmp_path)) == {"CMAKE_BUILD_TYPE": "Debug", "CMAKE_CXX_FLAGS": "-O1"}
    assert revisions.build_settings(str(tmp_path / "none")) == {"CMAKE_BUILD_TYPE": "Release"}


def test_the_cache_is_keyed_by_commit_and_settings(tmp_path):
    release = revisions.BuildCache(str(tmp_path), {"CMAKE_BUILD_TYPE": "Release"})
    debug = revisions.BuildCache(str(tmp_path), {"CMAKE_BUILD_TYPE": "Debug"})
    commit = "a" * 40
    assert release.entry(commit) != debug.entry(commit) != debug.entry("b" * 40)
    assert release.lookup(commit) is None
    os.makedirs(release.entry(commit))
    for name in ("heightmarch-bench", "build.json"):
        (tmp_path / revisions.CACHE / os.path.basename(release.entry(commit)) / name).write_text("x")
    assert release.lookup(commit) == os.path.join(release.entry(commit), "heightmarch-bench")
    assert debug.lookup(commit) is None


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
