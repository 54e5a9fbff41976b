"""render_progressive yields the film after each step of samples, ends at the whole render's
image, and saves and reads images."""
import numpy as np
import pytest

import pathtracer
from conftest import SCENES, SMALL, assert_identical


def test_steps_increase_and_end_at_the_full_image(cornell):
    options = dict(SMALL, spp=8)
    partials = list(pathtracer.render_progressive(cornell, **options))
    assert [p.spp for p in partials] == [1, 2, 4, 8]
    assert [p.stats["spp_mean"] for p in partials] == [1, 2, 4, 8]
    assert [p.stats["stop_reason"] for p in partials] == ["in_progress"] * 3 + ["completed"]
    assert all(np.all(p.aovs["samples"] == p.spp) for p in partials)
    assert_identical(partials[-1].image, pathtracer.render(cornell, **options).image)
    # Each partial is its own copy: later steps do not change an earlier one.
    assert not np.array_equal(partials[0].image, partials[-1].image)


def test_custom_steps(cornell):
    options = dict(SMALL, spp=6)
    spps = [p.spp for p in pathtracer.render_progressive(cornell, steps=[3, 5], **options)]
    assert spps == [3, 5, 6]
    with pytest.raises(ValueError, match="steps must increase"):
        pathtracer.render_progressive(cornell, steps=[4, 2], **options)
    with pytest.raises(ValueError, match="adaptive"):
        pathtracer.render_progressive(cornell, adaptive=True, **options)


def test_an_edit_during_progressive_stops_it(cornell):
    steps = pathtracer.render_progressive(cornell, **dict(SMALL, spp=4))
    next(steps)
    cornell.set_material("red", albedo=[0.5, 0.5, 0.5])
    with pytest.raises(RuntimeError, match="edited"):
        next(steps)


def test_save_and_read_back(tmp_path, cornell):
    result = pathtracer.render(cornell, **SMALL)
    for name in ("x.exr", "x.pfm"):
        result.save(tmp_path / name)
        assert_identical(pathtracer.read_image(tmp_path / name), result.image)
    result.save(str(tmp_path / "x.png"))
    assert (tmp_path / "x.png").read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(ValueError, match="unknown image format"):
        result.save(tmp_path / "x.jpg")
    with pytest.raises(OSError):
        result.save(tmp_path / "no" / "such" / "folder.exr")
