"""The module renders what the command line renders: the same scene, seed and options give the
same image bit for bit on the CPU, and the same statistics document."""
import json
import subprocess

import numpy as np
import pytest

import pathtracer
from conftest import SCENES, SMALL, assert_identical, cli_path, run_cli, scene_dict


@pytest.mark.parametrize("scene_file, options", [
    ("cornell_box.json", SMALL),
    ("cornell_box.json", dict(SMALL, sort="queues", compact="off", integrator="nee", threads=1)),
    ("cornell_glass_mirror.json", dict(SMALL, max_depth=6, bvh="binary", rr_depth=1)),
    ("depth_of_field.json", dict(SMALL, sampler="sobol")),
    ("instanced_shapes.json", dict(SMALL, crop="4,2,20,17", sort="material")),
    ("meshes/smooth_shapes.glb", dict(SMALL, width=30, height=None, seed=3)),
])
def test_image_equals_the_cli(tmp_path, scene_file, options):
    options = {k: v for k, v in options.items() if v is not None}
    scene = pathtracer.Scene(SCENES / scene_file)
    result = pathtracer.render(scene, **options)
    expected = run_cli(SCENES / scene_file, tmp_path, options, ["--hdr", str(tmp_path / "out.exr")])
    assert_identical(result.image, expected)
    # The CLI's EXR (its --hdr, with variance and the AOVs) too, read back by the module.
    assert_identical(result.image, pathtracer.read_image(tmp_path / "out.exr"))
    # save() writes the --hdr file the CLI writes, byte for byte.
    result.save(tmp_path / "mine.exr")
    assert (tmp_path / "mine.exr").read_bytes() == (tmp_path / "out.exr").read_bytes()


def test_aovs_off_gives_the_same_image_as_the_cli_without_hdr(tmp_path, cornell):
    result = pathtracer.render(cornell, aovs=False, **SMALL)
    assert "albedo" not in result.aovs and result.aovs["variance"].shape == (20, 24, 3)
    assert_identical(result.image, run_cli(SCENES / "cornell_box.json", tmp_path, SMALL))


def test_aovs_are_the_film_buffers(cornell):
    result = pathtracer.render(cornell, **SMALL)
    assert result.image.dtype == np.float32 and result.image.shape == (20, 24, 3)
    aovs = result.aovs
    assert aovs["albedo"].shape == (20, 24, 3) and aovs["normal"].shape == (20, 24, 3)
    assert aovs["depth"].shape == (20, 24) and aovs["samples"].shape == (20, 24)
    assert np.all(aovs["samples"] == 4) and result.spp == 4.0
    # The camera sees the back wall (z = -1) from z = 3.9 in the middle of the image.
    assert 4.0 < aovs["depth"][10, 12] < 5.5
    assert np.all(aovs["variance"] >= 0) and np.all(np.isfinite(result.image))


def test_stats_are_the_cli_stats_document(tmp_path, cornell):
    result = pathtracer.render(cornell, **SMALL)
    stats_file = tmp_path / "stats.json"
    run_cli(SCENES / "cornell_box.json", tmp_path, SMALL, ["--stats-json", str(stats_file)])
    cli = json.loads(stats_file.read_text())

    def keys(d, prefix=""):
        out = set()
        for k, v in d.items():
            out.add(prefix + k)
            if isinstance(v, dict) and k != "shade_queues":
                out |= keys(v, prefix + k + ".")
        return out

    # The CLI's time_ms also cuts the process's wall time into parts (time_ms.parts): a
    # process the module does not have. Every other key is shared.
    process_only = {"time_ms." + k for k in cli["time_ms"]["parts"] + ["parts", "first_pixel", "background"]}
    process_only -= {"time_ms." + k for k in ("load", "bvh_build", "upload", "render")}
    assert process_only and keys(result.stats) == keys(cli) - process_only
    for key in ("samples", "spp_mean", "rays", "scene", "sort", "compact", "paths_in_flight"):
        assert result.stats[key] == cli[key], key
    assert result.stats["bvh"]["nodes"] == cli["bvh"]["nodes"]
    assert result.stats["stop_reason"] == "completed"
    assert result.stats["command_line"][0] == "pathtracer.render"
