"""Speed of two builds judged on a noisy machine: a revision's heightmarch-bench built in a
separate worktree, both binaries run alternately (A B A B ...), and the per-round ratios of
rays/s judged. scripts/regress and scripts/bisect use it.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

from benchmark_results import Unusable, canonical, load_benchmarks, spread

MAX_ROUNDS = 1000


def git(root, *args):
    return subprocess.run(["git", "-C", root] + list(args), check=True, capture_output=True, text=True).stdout.strip()


def resolve(root, rev):
    """The full commit id of rev, or Unusable."""
    try:
        return git(root, "rev-parse", "--verify", "--quiet", rev + "^{commit}")
    except subprocess.CalledProcessError:
        raise Unusable("unknown revision %s" % rev)


def check_filter(pattern):
    if not pattern:
        raise Unusable("--filter is empty")
    try:
        re.compile(pattern)
    except re.error as e:
        raise Unusable("--filter %s is not a regular expression: %s" % (pattern, e))


def build(source, build_dir, log, configure=True):
    """Builds heightmarch-bench of the tree at source into build_dir (configured first as Release
    without tests, unless it is a build directory of the user's); its path. Output goes to log."""
    commands = [["cmake", "-S", source, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DHEIGHTMARCH_BUILD_TESTS=OFF"]] if configure else []
    commands.append(["cmake", "--build", build_dir, "-j", str(os.cpu_count() or 1), "--target", "heightmarch-bench"])
    for cmd in commands:
        if subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT).returncode != 0:
            raise Unusable("building %s failed (%s)" % (source, log.name))
    return os.path.join(build_dir, "heightmarch-bench")


class Worktree:
    """A detached worktree of commit under a temporary directory, removed on exit."""

    def __init__(self, root, commit):
        self.root, self.commit = root, commit

    def __enter__(self):
        self.work = tempfile.mkdtemp(prefix="heightmarch-speed-")
        self.tree = os.path.join(self.work, "tree")
        git(self.root, "worktree", "add", "--detach", self.tree, self.commit)
        return self

    def __exit__(self, *exc):
        subprocess.run(["git", "-C", self.root, "worktree", "remove", "--force", self.tree], capture_output=True)
        shutil.rmtree(self.work, ignore_errors=True)


def list_benchmarks(binary, pattern, extra):
    """The names binary would run with this filter and these flags; Unusable when it refuses them."""
    result = subprocess.run([binary, "--benchmark_list_tests=true", "--benchmark_filter=" + pattern] + extra,
                            capture_output=True, text=True)
    if result.returncode != 0:
        raise Unusable("%s refuses the benchmark flags: %s" % (os.path.basename(binary),
                                                                (result.stderr.strip().splitlines() or ["exit %d" % result.returncode])[0]))
    return result.stdout.split()


def short(name):
    """A name as both builds share it: both ran at the same sizes, and older revisions name
    min_time: instead of view:/depth_map:."""
    return re.sub(r"/(view|depth_map):[^/]*", "", canonical(name))


def rays_per_second(path):
    data = load_benchmarks(path)
    return {short(b.get("run_name", b["name"])): b["rays_per_second"] for b in data["benchmarks"]
            if b.get("run_type", "iteration") == "iteration" and not b.get("error_occurred") and "rays_per_second" in b}


def interleaved_ratios(binaries, pattern, extra, rounds, work, progress=sys.stderr):
    """Runs binaries["old"] and binaries["new"] alternately for rounds rounds; per benchmark the
    per-round ratios NEW/OLD of rays/s."""
    ratios = {}
    for i in range(1, rounds + 1):
        speeds = {}
        for side in ("old", "new"):
            print("round %d/%d, %s" % (i, rounds, side), file=progress)
            out = os.path.join(work, "%s-%d.json" % (side, i))
            with open(out, "w") as f:
                subprocess.run([binaries[side], "--benchmark_filter=" + pattern, "--benchmark_format=json"] + extra,
                               stdout=f, stderr=subprocess.DEVNULL, check=True)
            speeds[side] = rays_per_second(out)
        for name in speeds["old"].keys() & speeds["new"].keys():
            ratios.setdefault(name, []).append(speeds["new"][name] / speeds["old"][name])
    return ratios


def judge(ratios, threshold):
    """[(name, (median, min, max) of the ratios, regressed)]: a regression is a median below
    1 - threshold with the whole spread below 1."""
    out = []
    for name in sorted(ratios):
        s = spread(ratios[name])
        out.append((name, s, s[0] < 1 - threshold and s[2] < 1))
    return out
