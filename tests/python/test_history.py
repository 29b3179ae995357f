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
