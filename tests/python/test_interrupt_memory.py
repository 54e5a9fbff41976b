"""Ctrl-C (SIGINT) during a render raises KeyboardInterrupt between waves and leaves the module
usable; a hundred renders do not grow the process."""
import os
import signal
import threading
import time

import numpy as np
import pytest

import pathtracer
from conftest import SCENES, SMALL, assert_identical

# Many small waves (max_paths), so a stop is seen soon: ~5 s of rendering if not stopped.
LONG = dict(width=96, height=96, spp=4096, max_depth=8, max_paths=2048, backend="cpu", threads=1)


def sigint_after(seconds):
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


@pytest.mark.parametrize("progressive", [False, True])
def test_keyboard_interrupt_stops_the_render_and_the_module_stays_usable(cornell, progressive):
    expected = pathtracer.render(cornell, **SMALL).image
    start = time.monotonic()
    timer = sigint_after(0.3)
    try:
        with pytest.raises(KeyboardInterrupt):
            if progressive:
                for _ in pathtracer.render_progressive(cornell, steps=[4096], **LONG):
                    pass
            else:
                pathtracer.render(cornell, **LONG)
    finally:
        timer.cancel()
    assert time.monotonic() - start < 3.0  # stopped at the next wave, not at the end
    assert_identical(pathtracer.render(cornell, **SMALL).image, expected)


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_memory_does_not_grow_over_100_renders(cornell):
    # Each render's film is ~0.23 MB (64x64: image, variance, AOVs, counts): a leak of the film,
    # the arrays or a session (far larger) would grow the process by 22 MB or more (it grows
    # by ~1.5 MB, once).
    options = dict(SMALL, width=64, height=64, spp=1, max_depth=1, threads=1)
    kept = []
    for _ in range(5):  # warm up: allocator arenas
        pathtracer.render(cornell, **options)
    before = rss_bytes()
    for i in range(100):
        result = pathtracer.render(cornell, **options)
        assert result.image.shape == (64, 64, 3)
        if os.environ.get("PT_TEST_KEEP_RESULTS"):  # proves the bound catches a leak
            kept.append(result)
    grown = rss_bytes() - before
    assert grown < 8 << 20, f"RSS grew by {grown / 2**20:.1f} MiB over 100 renders"
