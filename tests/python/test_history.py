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


def glsl_row(gl):
    return {"kind": "glsl", "backend": "glsl", "threads": 2, "heightfield": {"label": "bricks", "width": 512, "height": 512},
            "technique": "pom", "layers": "32", "view": {"kind": "default", "width": 256, "height": 256}, "gl": gl}


def test_glsl_series_are_kept_apart_by_their_renderer():
    def gl(renderer, path):
        return {"path": path.lower(), "device": "software", "renderer": renderer, "version": "4.5", "driver": "Mesa",
                "label": "glsl (%s; %s)" % (renderer, path)}
    osmesa, egl = glsl_row(gl("llvmpipe, LLVM 15.0.6, 256 bits", "OSMesa")), glsl_row(gl("llvmpipe, LLVM 15.0.6, 256 bits", "EGL"))
    gpu = glsl_row(gl("NVIDIA H100 80GB HBM3/PCIe/SSE2", "EGL"))
    keys = {history.series(history.series_fields(r)) for r in (osmesa, egl, gpu)}
    assert len(keys) == 3
    assert history.series_fields(gpu)["backend"] == "glsl (NVIDIA H100 80GB HBM3/PCIe/SSE2; EGL)"
    # a run from before rows recorded their renderer stays the series it was
    assert history.series_fields(glsl_row(None))["backend"] == "glsl"
