"""history: the machine key speed is compared within, and rows as the history records them."""
from heightmarch_tools import history


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


def row(**changes):
    """A timed measurements.json row as history reads it."""
    return dict({"kind": "trace", "backend": "avx2", "threads": 1, "heightfield": {"label": "bricks", "width": 512, "height": 512},
                 "technique": "pom", "layers": "32", "view": {"kind": "default", "width": 64, "height": 64},
                 "filter": "bilinear"}, **changes)


def test_the_filter_is_part_of_a_series():
    bilinear, trilinear = history.series_fields(row()), history.series_fields(row(filter="trilinear"))
    assert bilinear != trilinear
    assert history.series_name(tuple(trilinear[k] for k in history.SERIES_FIELDS)).endswith(", trilinear")
    # a run before filters read level 0; the exact reference is every filter's, one series
    assert history.series_fields({k: v for k, v in row().items() if k != "filter"}) == bilinear
    assert history.series_fields(row(kind="exact", technique=None, filter=None))["filter"] == ""


def test_a_history_written_before_filters_reads_as_bilinear(tmp_path):
    earlier = [c for c in history.COLUMNS if c != "filter"]
    path = tmp_path / "history.csv"
    history.write(str(path), [{c: "x" for c in earlier}], earlier)
    rows = history.read(str(path))
    assert [r["filter"] for r in rows] == ["bilinear"]
