"""denoise=True is the CLI's --denoise: the same denoised image bit for bit on the CPU, beside
the raw film, in save()'s files and in each step of render_progressive."""
import numpy as np
import pytest

import pathtracer
from conftest import SCENES, SMALL, assert_identical, read_pfm, run_cli


def test_denoised_equals_the_cli(tmp_path, cornell):
    result = pathtracer.render(cornell, denoise=True, **SMALL)
    raw = pathtracer.render(cornell, **SMALL)
    assert "denoised" not in raw.aovs
    assert_identical(result.image, raw.image)  # the film is the raw one
    denoised = result.aovs["denoised"]
    assert denoised.shape == result.image.shape and np.all(np.isfinite(denoised))
    assert np.any(denoised != result.image)
    assert_identical(denoised, run_cli(SCENES / "cornell_box.json", tmp_path, SMALL, ["--denoise"]))
    assert result.stats["time_ms"]["denoise"] > 0
    result.save(tmp_path / "mine.pfm")
    assert_identical(read_pfm(tmp_path / "mine.pfm"), denoised)


def test_progressive_denoises_each_step(cornell):
    steps = list(pathtracer.render_progressive(cornell, steps=[2], denoise=True, **SMALL))
    assert len(steps) == 2
    for step in steps:
        assert step.aovs["denoised"].shape == step.image.shape
    final = pathtracer.render(cornell, denoise=True, **SMALL)
    assert_identical(steps[-1].aovs["denoised"], final.aovs["denoised"])


def test_denoise_takes_a_bool(cornell):
    with pytest.raises(ValueError, match="denoise takes True or False"):
        pathtracer.render(cornell, denoise="maybe", **SMALL)
