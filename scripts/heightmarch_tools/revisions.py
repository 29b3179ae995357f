"""A revision's heightmarch-bench, built once and kept: a detached worktree of the commit, a build
of its benchmark binary and GLSL worker with the current build's settings, and a cache under the
build directory keyed by the commit and those settings (ccache, where installed, speeds up the
first build of a commit near one built before). scripts/regress and scripts/bisect use it.

Every child runs through processes.run: a signal ends it with its whole process group, and the
worktree is removed on the way out.
"""
import hashlib
import json
import os
import shutil
import stat
import subprocess
import tempfile
import time

from . import processes
from .errors import Unusable
from .escape import terminal
from .readers import is_number, read_json, read_text
from .writers import atomic_write

CACHE = "regress-cache"  # under the build directory
BINARIES = ("heightmarch-bench", "heightmarch-glsl-worker")  # the bench finds its worker beside it (built with GLSL)
MAX_ENTRIES = 10  # builds kept; the least recently used goes first
INCOMING = ".incoming-"  # a build being stored: .incoming-PID-...
# The current build's settings that a revision's build takes on, so both sides are built alike.
SETTINGS = ("CMAKE_BUILD_TYPE", "CMAKE_CXX_COMPILER", "CMAKE_C_COMPILER", "CMAKE_CXX_FLAGS", "CMAKE_C_FLAGS",
            "CMAKE_EXE_LINKER_FLAGS")
DEFAULT_SETTINGS = {"CMAKE_BUILD_TYPE": "Release"}


def git(root, *args):
    result = processes.run(["git", "-C", root] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if result.returncode != 0:
        raise subprocess.CalledProcessError(result.returncode, result.args, result.stdout, result.stderr)
    return result.stdout.strip()


def repository(path):
    """The top of the git repository holding path, or Unusable."""
    try:
        return git(path, "rev-parse", "--show-toplevel")
    except subprocess.CalledProcessError:
        raise Unusable("%s is not in a git repository" % path)


def resolve(root, rev):
    """The full commit id of rev, or Unusable."""
    try:
        return git(root, "rev-parse", "--verify", "--quiet", rev + "^{commit}")
    except subprocess.CalledProcessError:
        raise Unusable("unknown revision %s" % terminal(rev))


def describe(root, commit):
    """'1a2b3c4d5e6f subject' of a commit, for progress lines."""
    return git(root, "log", "-1", "--format=%h %s", commit)[:100]


def cmake_cache(build_dir):
    """{KEY: VALUE} of build_dir/CMakeCache.txt ({} without one)."""
    path = os.path.join(build_dir, "CMakeCache.txt")
    if not os.path.lexists(path):
        return {}
    out = {}
    for line in read_text(path).splitlines():
        if line[:1] not in ("#", "/", "") and "=" in line and ":" in line.split("=", 1)[0]:
            key, value = line.split("=", 1)
            out[key.split(":", 1)[0]] = value
    return out


def compiler_version(path):
    """The first line of `path --version` (a compiler updated in place is another setting)."""
    try:
        result = processes.run([path, "--version"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    except OSError:
        return "?"
    return (result.stdout.splitlines() or ["?"])[0]


def build_settings(build_dir):
    """The settings a revision is built with: the current build's (build type, compilers and their
    versions, flags) where it has them, else a Release build with the default compilers."""
    cache = cmake_cache(build_dir)
    settings = {k: cache[k] for k in SETTINGS if cache.get(k)} or dict(DEFAULT_SETTINGS)
    settings.setdefault("CMAKE_BUILD_TYPE", "Release")
    for key in ("CMAKE_CXX_COMPILER", "CMAKE_C_COMPILER"):
        if key in settings:
            settings[key + "_VERSION"] = compiler_version(settings[key])
    return settings


class Worktree:
    """A detached worktree of commit under a temporary directory, removed on exit, whatever ends
    the block (an error, Interrupted)."""

    def __init__(self, root, commit):
        self.root, self.commit = root, commit

    def __enter__(self):
        self.work = tempfile.mkdtemp(prefix="heightmarch-speed-")
        self.tree = os.path.join(self.work, "tree")
        try:
            git(self.root, "worktree", "add", "--detach", self.tree, self.commit)
        except BaseException:
            self.__exit__()
            raise
        return self

    def __exit__(self, *exc):
        with processes.signals_held():
            subprocess.run(["git", "-C", self.root, "worktree", "remove", "--force", self.tree], capture_output=True)
            shutil.rmtree(self.work, ignore_errors=True)
            subprocess.run(["git", "-C", self.root, "worktree", "prune"], capture_output=True)


def build(source, build_dir, log, settings=None):
    """Builds heightmarch-bench (and its GLSL worker) of the tree at source into build_dir, first
    configured with settings unless settings is None (a build directory of the user's, brought up
    to date as it is). Output goes to log; its path."""
    commands, env = [], None
    if settings is not None:
        configure = ["cmake", "-S", source, "-B", build_dir, "-DHEIGHTMARCH_BUILD_TESTS=OFF"]
        configure += ["-D%s=%s" % (k, v) for k, v in sorted(settings.items()) if not k.endswith("_VERSION")]
        if shutil.which("ccache"):
            configure += ["-DCMAKE_CXX_COMPILER_LAUNCHER=ccache", "-DCMAKE_C_COMPILER_LAUNCHER=ccache"]
        commands.append(configure)
        # ccache finds a compile of the same file in another worktree when the paths of the sources
        # and of the build's generated files are taken relative to the directory holding both
        env = dict(os.environ, CCACHE_BASEDIR=os.path.commonpath([os.path.realpath(source), os.path.realpath(build_dir)]))
    commands.append(["cmake", "--build", build_dir, "-j", str(os.cpu_count() or 1), "--target", "heightmarch-bench"])
    for command in commands:
        if processes.run(command, stdout=log, stderr=subprocess.STDOUT, env=env).returncode != 0:
            raise Unusable("building %s failed: its log is %s" % (source, log.name))
    return os.path.join(build_dir, "heightmarch-bench")


def checksum(path):
    """The SHA-256 of a file, hex."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def real_file(path):
    """Whether path is a regular file itself, not a link to one."""
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def embeds_commit(path, commit):
    """Whether the binary at path carries commit's id as its own (build_info.hpp's kBuildCommit,
    the first 12 digits, compiled into every heightmarch binary)."""
    with open(path, "rb") as f:
        return commit[:12].encode() in f.read()


class BuildCache:
    """Built revisions under BUILD/regress-cache/COMMIT12-KEY/ (the binaries and build.json with the
    commit, the settings, the binaries' SHA-256 and the build's seconds), KEY a hash of the commit
    and the settings; entries appear whole (renamed into place) and at most MAX_ENTRIES are kept.
    Beside them: the last build log of each commit (build-COMMIT12.log) and timings.json, the last
    build's and round's seconds for the next run's estimates.

    Nothing is trusted by its name: the cache is a directory of its own inside the build directory
    (a link there is refused, never followed), and an entry's binary runs only when the entry proves
    it (trusted()): its build.json names the commit and the settings asked for and the checksums of
    the files beside it, and the binary carries that commit as its own. An entry that does not is
    removed and built again."""

    def __init__(self, build_dir, settings):
        self.build_dir = os.path.abspath(build_dir)
        self.dir = os.path.join(self.build_dir, CACHE)
        self.settings = settings

    def checked_dir(self):
        """self.dir, made where missing; Unusable where it is a link or anything but a directory."""
        try:
            os.makedirs(self.build_dir, exist_ok=True)  # bisect's default build/ may not be built yet
            try:
                os.mkdir(self.dir)
            except FileExistsError:
                pass
            mode = os.lstat(self.dir).st_mode
        except OSError as e:
            raise Unusable("%s: cannot make the build cache: %s" % (terminal(self.dir), e.strerror))
        if stat.S_ISLNK(mode) or not stat.S_ISDIR(mode):
            raise Unusable("%s: is %s, not a directory: the build cache is a directory of its own inside %s "
                           "(remove it)" % (terminal(self.dir), "a link" if stat.S_ISLNK(mode) else "a file",
                                            terminal(self.build_dir)))
        return self.dir

    def entry(self, commit):
        key = hashlib.sha256(json.dumps([commit, self.settings], sort_keys=True).encode()).hexdigest()[:12]
        return os.path.join(self.dir, "%s-%s" % (commit[:12], key))

    def trusted(self, commit):
        """Why the entry of commit cannot be trusted, or None when it proves what it holds."""
        entry = self.entry(commit)
        if not stat.S_ISDIR(os.lstat(entry).st_mode):
            return "it is not a directory"
        stamp = os.path.join(entry, "build.json")
        if not real_file(stamp):
            return "no build.json"
        try:
            record = read_json(stamp)
        except Unusable as e:
            return str(e)
        if not isinstance(record, dict) or record.get("commit") != commit:
            return "its build.json names another commit"
        if record.get("settings") != self.settings:
            return "its build.json names other settings"
        sums = record.get("checksums")
        if not isinstance(sums, dict) or BINARIES[0] not in sums:
            return "its build.json holds no checksums"
        for name in os.listdir(entry):
            if name != "build.json" and name not in sums:
                return "it holds %s, which its build.json does not name" % terminal(name)
        for name, digest in sums.items():
            path = os.path.join(entry, name)
            if name not in BINARIES or not real_file(path) or checksum(path) != digest:
                return "%s is not the file its build.json names" % terminal(name)
        if not embeds_commit(os.path.join(entry, BINARIES[0]), commit):
            return "its %s was not built from %s" % (BINARIES[0], commit[:12])
        return None

    def lookup(self, commit, progress=None):
        """The cached heightmarch-bench of commit, or None; an entry that does not prove what it
        holds is removed (progress says why), so it is built again."""
        entry = self.entry(commit)
        if not os.path.lexists(os.path.join(self.checked_dir(), os.path.basename(entry))):
            return None
        why = self.trusted(commit)
        if why:
            if progress:
                progress("the cached build in %s is not trusted (%s): it is removed and built again"
                         % (entry, why))
            remove_entry(entry)
            return None
        os.utime(os.path.join(entry, "build.json"))  # recently used
        return os.path.join(entry, BINARIES[0])

    def build(self, root, commit, progress):
        """commit's heightmarch-bench from the cache, or built in a worktree of its own and stored;
        its path."""
        cached = self.lookup(commit, progress)
        if cached:
            progress("cached build of %s in %s" % (describe(root, commit), os.path.dirname(cached)))
            return cached
        progress("building %s in a worktree (%s; log: %s)" % (describe(root, commit), self.estimate(), self.log(commit)))
        with Worktree(root, commit) as tree:
            return self.build_in(tree.tree, os.path.join(tree.work, "build"), commit, progress)

    def build_in(self, tree, build_dir, commit, progress):
        """Builds the checkout of commit at tree into build_dir (incrementally where it holds an
        earlier build) and stores it; its cached heightmarch-bench. The build's log is
        self.log(commit), kept; an interrupted build stores nothing."""
        self.checked_dir()
        start = time.monotonic()
        with open_log(self.log(commit)) as log:
            binary = build(tree, build_dir, log, self.settings)
        seconds = time.monotonic() - start
        self.record(build_seconds=seconds)
        if not embeds_commit(binary, commit):  # a build system that did not rebuild its commit's id
            raise Unusable("the build of %s in %s does not carry its commit: not stored" % (commit[:12], build_dir))
        incoming = tempfile.mkdtemp(prefix="%s%d-" % (INCOMING, os.getpid()), dir=self.dir)
        try:
            sums = {}
            for b in BINARIES:
                if os.path.exists(os.path.join(os.path.dirname(binary), b)):
                    shutil.copy2(os.path.join(os.path.dirname(binary), b), incoming)
                    sums[b] = checksum(os.path.join(incoming, b))
            atomic_write(os.path.join(incoming, "build.json"), json.dumps(
                {"commit": commit, "settings": self.settings, "checksums": sums, "build_seconds": seconds},
                sort_keys=True) + "\n")
            if os.path.lexists(self.entry(commit)) and self.trusted(commit):
                remove_entry(self.entry(commit))  # what lookup() removed came back meanwhile
            try:
                os.rename(incoming, self.entry(commit))
            except OSError:  # another run stored the same build meanwhile
                pass
        finally:
            shutil.rmtree(incoming, ignore_errors=True)
        progress("built %s in %s" % (commit[:12], duration(seconds)))
        self.evict()
        return os.path.join(self.entry(commit), BINARIES[0])

    def log(self, commit):
        """Where the build of commit logs (kept: the last build of each commit)."""
        return os.path.join(self.dir, "build-%s.log" % commit[:12])

    def current_build_log(self):
        """The log of bringing the current build up to date, opened for writing (open_log)."""
        return open_log(os.path.join(self.checked_dir(), "current-build.log"))

    def estimate(self):
        seconds = self.timings().get("build_seconds")
        return ("the last build took %s" % duration(seconds) if seconds else
                "several minutes on 2 cores, less where ccache holds a build of a commit near it")

    def evict(self):
        """Keeps the MAX_ENTRIES most recently used builds; removes what a killed run left."""
        entries = []
        for name in os.listdir(self.dir):
            path = os.path.join(self.dir, name)
            stamp = os.path.join(path, "build.json")
            if os.path.isfile(stamp):
                entries.append((os.path.getmtime(stamp), path))
            elif name.startswith(INCOMING) and not alive(name[len(INCOMING):].split("-")[0]):
                shutil.rmtree(path, ignore_errors=True)
        for _, path in sorted(entries, reverse=True)[MAX_ENTRIES:]:
            shutil.rmtree(path, ignore_errors=True)
        logs = [os.path.join(self.dir, n) for n in os.listdir(self.dir) if n.startswith("build-") and n.endswith(".log")]
        for path in sorted(logs, key=os.path.getmtime, reverse=True)[2 * MAX_ENTRIES:]:
            os.unlink(path)

    def timings(self):
        """The last figures record() kept ({} where there are none, or they are not readable: they
        only make estimates)."""
        path = os.path.join(self.dir, "timings.json")
        try:
            data = read_json(path) if os.path.lexists(path) else {}
        except Unusable:
            return {}
        if not isinstance(data, dict):
            return {}
        return {k: v for k, v in data.items() if is_number(v) and 0 < v < 1e6}

    def record(self, **seconds):
        """Keeps figures (seconds) for the next run's estimates."""
        self.checked_dir()
        atomic_write(os.path.join(self.dir, "timings.json"), json.dumps(dict(self.timings(), **seconds)) + "\n")


def remove_entry(path):
    """Removes a cache entry: a link or a file as itself (never what it points to), a directory
    with what it holds."""
    if os.path.islink(path) or not os.path.isdir(path):
        os.unlink(path)
    else:
        shutil.rmtree(path)


def open_log(path):
    """A build log opened for writing from its start, never through a link planted at its name."""
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644)
    except OSError as e:
        raise Unusable("%s: cannot write the build log: %s" % (terminal(path), e.strerror))
    return os.fdopen(fd, "w")


def alive(pid):
    """Whether the process of pid (text) runs."""
    if not pid.isdigit() or int(pid) <= 0:
        return False
    try:
        os.kill(int(pid), 0)
        return True
    except ProcessLookupError:
        return False
    except PermissionError:
        return True


def duration(seconds):
    """'45 s', '3.5 min'."""
    return "%.0f s" % seconds if seconds < 90 else "%.1f min" % (seconds / 60)
