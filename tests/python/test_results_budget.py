"""The repository stays light (docs/measurements.md, "What results/ keeps"): its tracked files
under TREE_BUDGET, and each committed full run, with the rows it added to results/history.csv,
under RUN_BUDGET. A run over it is a failure naming its largest files: keep its large files
compressed (the suite writes them so), or keep the run elsewhere."""
import csv
import io
import os
import subprocess

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
RESULTS = os.path.join(ROOT, "results")
TREE_BUDGET = 30_000_000  # bytes of the tracked files
RUN_BUDGET = 5_000_000  # bytes a full run adds: its directory and its history rows


def tracked_sizes(root):
    """{path: bytes} of the files git tracks in root (a link counts as itself)."""
    try:
        listed = subprocess.run(["git", "-C", root, "ls-files", "-z"], check=True, capture_output=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        pytest.skip("not a git checkout (%s): the budget is of the tracked tree" % e)
    paths = [p.decode() for p in listed.split(b"\0") if p]
    return {p: os.lstat(os.path.join(root, p)).st_size for p in paths if os.path.lexists(os.path.join(root, p))}


def largest(sizes, n=5):
    return ", ".join("%s %.2f MB" % (p, b / 1e6) for p, b in sorted(sizes.items(), key=lambda x: -x[1])[:n])


def over_budget(sizes, budget):
    """None within the budget, else a line naming the total and the largest files."""
    total = sum(sizes.values())
    return None if total <= budget else "%.2f MB, over %.2f MB: %s" % (total / 1e6, budget / 1e6, largest(sizes))


def full_runs(sizes):
    """{run directory: {path: bytes}} of the committed runs with a report page (the suite's runs)."""
    runs = {}
    for path, size in sizes.items():
        parts = path.split("/")
        if parts[0] == "results" and len(parts) > 2:
            runs.setdefault(parts[1], {})[path] = size
    return {d: files for d, files in runs.items() if "results/%s/report.html" % d in files}


def history_bytes(run_dir):
    """The bytes of results/history.csv's rows of the run in run_dir (its commit and date)."""
    from heightmarch_tools.measurements import load_run
    provenance = load_run(run_dir).provenance
    path = os.path.join(RESULTS, "history.csv")
    if not os.path.exists(path):
        return 0
    with open(path, newline="") as f:
        rows = csv.reader(f)
        header = next(rows)
        date, commit = header.index("date"), header.index("commit")
        mine = [row for row in rows if row[date] == provenance.get("date") and row[commit] == provenance.get("commit")]
    text = io.StringIO()
    csv.writer(text, lineterminator="\n").writerows(mine)  # as the history writes them
    return len(text.getvalue().encode())


def test_the_tree_is_within_its_budget():
    problem = over_budget(tracked_sizes(ROOT), TREE_BUDGET)
    assert problem is None, "the repository's tracked files: " + problem


def test_each_committed_full_run_with_its_history_rows_is_within_its_budget():
    sizes = tracked_sizes(ROOT)
    runs = full_runs(sizes)
    latest = os.path.realpath(os.path.join(RESULTS, "latest"))
    assert os.path.basename(latest) in runs, "results/latest (%s) is no committed full run" % latest
    for name, files in runs.items():
        files = dict(files, **{"results/history.csv (its rows)": history_bytes(os.path.join(RESULTS, name))})
        problem = over_budget(files, RUN_BUDGET)
        assert problem is None, "results/%s: %s" % (name, problem)


def test_the_budget_fails_a_run_over_it():
    """The check itself: a run of today's files uncompressed (measurements.json 19.8 MB) is refused."""
    files = {"results/r/report.html": 1_200_000, "results/r/measurements.json": 19_751_096}
    assert over_budget(files, RUN_BUDGET).startswith("20.95 MB, over 5.00 MB: results/r/measurements.json 19.75 MB")
    assert over_budget({"results/r/report.html": 1_200_000}, RUN_BUDGET) is None
    assert list(full_runs(files)) == ["r"] and full_runs({"results/r/bench.json": 1}) == {}
