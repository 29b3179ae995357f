"""history and record_run: the machine key speed is compared within, rows as the history records
and checks them, its repair, recordings that overlap or come from an incomplete run."""
import csv
import multiprocessing
import os
import signal
import time

import pytest

from heightmarch_tools import cli, history, record_run
from heightmarch_tools.errors import Unusable


def parts(**changes):
    return dict({"cpu": "AMD EPYC (family 25, model 17)", "cores": "2", "best_isa": "avx512", "compiler": "GNU 12.2.0",
                 "build_type": "Release"}, **changes)


def test_machine_key_names_family_and_model():
    assert history.machine_key(parts()) == "amd-epyc-f25m17-2c-avx512-gnu-12.2.0-release"
    assert history.is_known(history.machine_key(parts()))


def test_a_machine_without_family_model_or_a_part_is_unknown():
    assert history.machine_key(parts(cpu="AMD EPYC")) == "unknown-amd-epyc-2c-avx512-gnu-12.2.0-release"
    assert history.machine_key(parts(build_type="")) == "unknown-amd-epyc-f25m17-2c-avx512-gnu-12.2.0-?"
    assert not history.is_known(history.machine_key(parts(cores="")))


# ---------------------------------------------------------------------------------------------
# The file: rows checked with their line numbers, repair, recordings that overlap

@pytest.fixture(autouse=True)
def no_plot(monkeypatch):
    """The history plot is test_history.sh's; here it would only cost time."""
    monkeypatch.setattr(record_run.history_plot, "draw", lambda *_: False)


def run_data(commit, label="bricks"):
    """A recorded run's measurements.json as record_run reads it: one timed POM-32 row."""
    view = {"kind": "default", "width": 64, "height": 64, "theta": None, "phi": None}
    return {"provenance": {"date": "2026-12-01T10:00:%02dZ" % int(commit[1:]), "commit": commit,
                           "cpu": "AMD EPYC (family 25, model 17)", "cores": 2, "best_isa": "avx2",
                           "compiler": "GNU 12.2.0", "build_type": "Release"},
            "backends": ["scalar", "avx2"],
            "rows": [{"kind": "trace", "purposes": ["isa"], "technique": "pom", "layers": "32", "backend": "avx2",
                      "threads": 1, "heightfield": {"label": label, "width": 32, "height": 32}, "view": view,
                      "samples_known": True, "samples_per_ray": 12.5,
                      "errors": {"uv_error_mean": 0.25, "uv_error_p95": 1.5, "wrong_surface_rate": 0.01},
                      "speed": {"rays_per_second": {"rounds": [2e7, 2.1e7, 1.9e7]}}}]}


def recorded(tmp_path, commit, label="bricks", hold=0.0):
    run_dir = tmp_path / commit
    run_dir.mkdir()
    return record_run.record(run_data(commit, label), str(run_dir), str(tmp_path / "history.csv"),
                             lambda *_: time.sleep(hold))


def test_a_recorded_run_is_read_back(tmp_path):
    recorded(tmp_path, "c01", label="=HYPERLINK(\"x\")")
    rows = history.read(str(tmp_path / "history.csv"))
    assert len(rows) == 1 and rows[0]["heightfield"] == "'=HYPERLINK(\"x\")" and rows[0]["threads"] == "1"


@pytest.mark.parametrize("bad, why", [
    (lambda line: "<<<<<<< HEAD", "line 3: 1 cells, not 24 (a merge conflict's marker)"),
    (lambda line: line.replace(",2e+07,", ",fast,"), "line 3: rays_per_second_median: is \"fast\", not a number"),
    (lambda line: line.replace(",12.5,", ",nan,"), "line 3: samples_per_ray: is NaN, not a finite number"),
    (lambda line: line.replace(",1,bricks,", ",0.5,bricks,"), "line 3: threads: is 0.5, not in [1, inf]"),
    (lambda line: line.replace(",1,bricks,", ",2.5,bricks,"), "line 3: threads: is 2.5, not an integer")])
def test_a_malformed_row_is_refused_with_its_line_and_repaired(tmp_path, capsys, bad, why):
    recorded(tmp_path, "c01")
    recorded(tmp_path, "c02")
    path = tmp_path / "history.csv"
    lines = path.read_text().splitlines()
    lines[2] = bad(lines[2])
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(Unusable) as e:
        history.read(str(path))
    assert why in str(e.value) and "scripts/repair-history" in str(e.value)
    with pytest.raises(Unusable):
        recorded(tmp_path, "c03")  # a recording refuses it too, and adds nothing
    assert history.repair([str(path)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("drops line 3: ") and out[-1].endswith("1 rows kept, 1 dropped")
    assert [r["commit"] for r in history.read(str(path))] == ["c01"]


def test_two_recordings_at_once_keep_both_rows(tmp_path):
    recorded(tmp_path, "c01")
    workers = [multiprocessing.Process(target=recorded, args=(tmp_path, c, "bricks", 0.5)) for c in ("c02", "c03")]
    for w in workers:
        w.start()
    for w in workers:
        w.join(60)
    assert [w.exitcode for w in workers] == [0, 0]
    assert sorted(r["commit"] for r in history.read(str(tmp_path / "history.csv"))) == ["c01", "c02", "c03"]


def test_an_incomplete_run_is_not_recorded(tmp_path):
    (tmp_path / "c01").mkdir()
    (tmp_path / "c01" / "INCOMPLETE").write_text("This run did not complete.\n")
    with pytest.raises(Unusable) as e:
        record_run.record(run_data("c01"), str(tmp_path / "c01"), str(tmp_path / "history.csv"))
    assert "INCOMPLETE" in str(e.value) and not (tmp_path / "history.csv").exists()


@pytest.mark.parametrize("when", ["just after the row is written", "while the history is written"])
def test_a_signal_after_the_row_is_written_exits_0_saying_so(tmp_path, monkeypatch, capsys, when):
    """One truth after a signal: Ctrl-C at the moment the history's rename has put the row in (or
    during the write that does) leaves a recorded run and exit 0 with a line, never 130."""
    write = history.write

    def write_then_signal(path, rows, *table):
        history_csv = path.endswith("history.csv")  # not alerts.csv, which is written the same way
        if history_csv and when == "while the history is written":
            os.kill(os.getpid(), signal.SIGINT)
        write(path, rows, *table)
        if history_csv and when == "just after the row is written":
            os.kill(os.getpid(), signal.SIGINT)
    monkeypatch.setattr(record_run.history, "write", write_then_signal)
    try:
        assert cli.run("report", lambda: recorded(tmp_path, "c01") and 0) == 0
    finally:
        for s in cli.SIGNALS:
            signal.signal(s, signal.default_int_handler if s == signal.SIGINT else signal.SIG_DFL)
    assert [r["commit"] for r in history.read(str(tmp_path / "history.csv"))] == ["c01"]
    assert capsys.readouterr().err == ("report: SIGINT came after the run was recorded in %s: it is complete and "
                                       "recorded\n" % (tmp_path / "history.csv"))


def test_a_signal_before_the_row_is_written_adds_no_row(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(record_run.alerts, "keep", lambda *_: os.kill(os.getpid(), signal.SIGTERM))
    try:
        assert cli.run("report", lambda: recorded(tmp_path, "c01") and 0) == 128 + signal.SIGTERM
    finally:
        for s in cli.SIGNALS:
            signal.signal(s, signal.default_int_handler if s == signal.SIGINT else signal.SIG_DFL)
    assert not (tmp_path / "history.csv").exists() and capsys.readouterr().err == "report: interrupted (SIGTERM)\n"


def test_a_file_from_before_simd_use_reads_with_it_empty(tmp_path):
    recorded(tmp_path, "c01")
    path = tmp_path / "history.csv"
    lines = path.read_text().splitlines()
    assert lines[0].endswith(",simd_utilization")
    path.write_text("\n".join(line.rsplit(",", 1)[0] for line in lines) + "\n")  # as written before the column
    rows = history.read(str(path))
    assert len(rows) == 1 and rows[0]["simd_utilization"] == "" and rows[0]["samples_per_ray"] == "12.5"
    recorded(tmp_path, "c02")  # recording rewrites it with the column
    assert path.read_text().splitlines()[0].endswith(",simd_utilization")


def test_simd_use_is_recorded_for_the_rows_that_measure_it():
    assert history.measure({"simd_utilization": 0.5}, "simd_utilization") == "0.5"
    assert history.measure({"simd_utilization": None}, "simd_utilization") == ""


def test_a_malformed_alerts_csv_stops_the_recording_before_the_history_changes(tmp_path):
    recorded(tmp_path, "c01")
    before = (tmp_path / "history.csv").read_text()
    (tmp_path / "alerts.csv").write_text("<<<<<<< HEAD\n")
    with pytest.raises(Unusable) as e:
        recorded(tmp_path, "c02")
    assert "alerts.csv: line 1" in str(e.value) and (tmp_path / "history.csv").read_text() == before


def glsl_row(gl):
    return {"kind": "glsl", "backend": "glsl", "threads": 2, "heightfield": {"label": "bricks", "width": 512, "height": 512},
            "technique": "pom", "layers": "32", "view": {"kind": "default", "width": 256, "height": 256}, "gl": gl}


def test_glsl_series_are_kept_apart_by_their_renderer():
    def gl(renderer, path):
        return {"path": path.lower(), "device": "software", "renderer": renderer, "version": "4.5", "driver": "Mesa",
                "label": "glsl (%s; %s)" % (renderer, path)}
    llvmpipe = "llvmpipe, LLVM 15.0.6, 256 bits"
    osmesa, egl = glsl_row(gl(llvmpipe, "OSMesa")), glsl_row(gl(llvmpipe, "EGL"))
    gpu = glsl_row(gl("NVIDIA H100 80GB HBM3/PCIe/SSE2", "EGL"))
    keys = {history.series(history.series_fields(r)) for r in (osmesa, egl, gpu)}
    assert len(keys) == 3
    assert history.series_fields(gpu)["backend"] == "glsl (NVIDIA H100 80GB HBM3/PCIe/SSE2; EGL)"
    # a run from before rows recorded their renderer stays the series it was
    assert history.series_fields(glsl_row(None))["backend"] == "glsl"


def row(**changes):
    """A timed measurements.json row as history reads it."""
    return dict({"kind": "trace", "backend": "avx2", "threads": 1,
                 "heightfield": {"label": "bricks", "width": 512, "height": 512},
                 "technique": "pom", "layers": "32", "view": {"kind": "default", "width": 64, "height": 64},
                 "filter": "bilinear"}, **changes)


def test_the_filter_is_part_of_a_series():
    bilinear, trilinear = history.series_fields(row()), history.series_fields(row(filter="trilinear"))
    assert bilinear != trilinear
    assert history.series_name(tuple(trilinear[k] for k in history.SERIES_FIELDS)).endswith(", trilinear")
    # a run before filters read level 0; the exact reference is every filter's, one series
    assert history.series_fields({k: v for k, v in row().items() if k != "filter"}) == bilinear
    assert history.series_fields(row(kind="exact", technique=None, filter=None))["filter"] == ""


@pytest.mark.parametrize("earlier", [("filter",), ("filter", "simd_utilization")])
def test_a_history_written_before_filters_reads_as_bilinear(tmp_path, earlier):
    recorded(tmp_path, "c01")
    path = tmp_path / "history.csv"
    with open(path, newline="") as f:
        lines = list(csv.reader(f))
    gone = {lines[0].index(c) for c in earlier}
    with open(path, "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows([c for i, c in enumerate(line) if i not in gone] for line in lines)
    rows = history.read(str(path))
    assert [r["filter"] for r in rows] == ["bilinear"] and rows[0]["samples_per_ray"] == "12.5"
    assert set(rows[0]) == set(history.COLUMNS)
    if "simd_utilization" in earlier:
        assert rows[0]["simd_utilization"] == ""
