#!/usr/bin/env python3
"""Cost model of the MPI sample split (docs/distributed.md): expected render time and
efficiency T1 / (N * TN) on N GPUs, from one GPU's per-sample time, the film's bytes, and
the bandwidths of host memory, of the path between ranks of a host, and of InfiniBand.

    python3 benchmarks/mpi_cost_model.py                 # the tables of docs/distributed.md
    python3 benchmarks/mpi_cost_model.py --check         # against the measured 2-GPU runs
    python3 benchmarks/mpi_cost_model.py --rate 489e6 --width 1920 --height 1080 --spp 4096

The model follows src/distributed/: the samples are cut into C chunks (leaves); each GPU runs
L lanes, each rendering one leaf at a time into a fresh film, downloading it (t_save per
leaf) and handing it to the rank, which merges it along the fixed tree (t_merge per merge,
multi-threaded, memory-bound). With two lanes one lane's download overlaps the other's
rendering, so a leaf costs the GPU max(t_leaf, (t_leaf + t_save) / L). Not overlapped, at the
end: the last leaf's download, the merges up the rank's own subtree (log2 of its leaves), then
ceil(log2 N) levels of the binomial tree of ranks, each one film transfer plus one merge (the
first log2(GPUs per host) levels inside a host, the rest over InfiniBand). Start-up (mpirun,
MPI_Init, scene load, BVH, CUDA contexts, upload, and writing the image) happens on every
rank at once and does not shrink with N.

Constants marked "measured" come from the 2 x H200 runs of 2026-11-25 (benchmarks/RESULTS.md);
the InfiniBand bandwidth and the extra launch time over many hosts are assumptions.
"""
import argparse
import math

FILM_BYTES = 60          # a pixel of a film on the wire and in host memory (88 with features)
MERGE_BYTES = 3 * FILM_BYTES  # a merge reads two films and writes one

# Measured, 2 x H200 host (2026-11-25, benchmarks/results/mpi_h200x2_2026-11-25_filmsave):
# per pixel of a leaf's film, its download and conversion to the double-precision host film
# into a recycled film (SaveFilmInto: ~11 ms a leaf at 1920x1080; 49-63 ms into fresh memory
# before the film pool);
SAVE_NS_PER_PIXEL = 5.5
# a merge with the rank's spare cores (4.4 ms for 2,073,600 pixels: ~85 GB/s of traffic);
MERGE_NS_PER_PIXEL = 2.1
# one 124 MB film from rank 1 to rank 0 in Open MPI's shared memory, its merge included (the
# bunny's reduction: 20-23 ms once the root no longer made an empty film first);
HOST_LINK = 6e9
# start-up and output: a whole run's wall time minus its render time (1 GPU 1.2 s, 2 GPUs
# 1.5 s at 1920x1080).
STARTUP_ONE, STARTUP_MPI = 1.2, 1.5
# Rates of one H200 (measured the same day): plain one-process renders, 1024 spp (bunny
# 1920x1080 in 2.669 s, Breakfast Room 1280x720 in 5.335 s).
BUNNY_RATE, BREAKFAST_RATE = 794.5e6, 176.9e6


def model(a, n, pixels, spp, rate, chunks):
    """Seconds: (one GPU's render, N GPUs' render phase, the tail within it)."""
    t1 = pixels * spp / rate
    if n == 1:
        return t1, t1, 0.0
    t_leaf = pixels * (spp / chunks) / rate
    t_save = pixels * a.save_ns * 1e-9
    t_merge = pixels * a.merge_ns * 1e-9
    leaves = chunks / n
    per_leaf = max(t_leaf, (t_leaf + t_save) / a.lanes)
    # Leaves go to lanes one at a time: an uneven last round leaves GPUs idle.
    rounds = math.ceil(chunks / (n * a.lanes)) * a.lanes
    render = max(leaves, rounds if chunks % (n * a.lanes) else leaves) * per_leaf
    film = pixels * FILM_BYTES
    levels_host = math.ceil(math.log2(min(n, a.gpus_per_host)))
    levels_ib = math.ceil(math.log2(n / a.gpus_per_host)) if n > a.gpus_per_host else 0
    cascade = math.ceil(math.log2(max(1.0, leaves))) * t_merge
    transfer = levels_host * (film / a.host_link + t_merge) + levels_ib * (film / a.ib + t_merge)
    tail = t_save + cascade + transfer
    return t1, render + tail, tail


def chunks_for(a, n, spp):
    """The default (32) up to 8 GPUs; beyond, 2 leaves a lane (pass --chunks)."""
    return min(spp, max(a.chunks, 2 * a.lanes * n)) if n > 1 else 1


def table(a, title, width, height, spp, rate, counts):
    pixels = width * height
    print(f"\n### {title}: {width}x{height}, {spp} spp, {rate / 1e6:.1f} M samples/s a GPU\n")
    print("| GPUs | chunks | render s | tail ms | efficiency (render) | "
          "efficiency (whole run) |")
    print("|---|---|---|---|---|---|")
    for n in counts:
        chunks = chunks_for(a, n, spp)
        t1, tn, tail = model(a, n, pixels, spp, rate, chunks)
        startup = STARTUP_ONE if n == 1 else STARTUP_MPI + (a.launch_hosts if n > a.gpus_per_host else 0.0)
        eff = t1 / (n * tn)
        eff_all = (STARTUP_ONE + t1) / (n * (startup + tn))
        label = f"{n // a.gpus_per_host} x {a.gpus_per_host}" if n > a.gpus_per_host else f"{n}"
        print(f"| {label} | {chunks} | {tn:.3f} | {tail * 1e3:.0f} | {eff:.3f} | {eff_all:.3f} |")


def check(a):
    print("### The model against the measured 2 x H200 runs (medians of 3)\n")
    print("| scene | predicted 2-GPU render s | measured | predicted efficiency | measured |")
    print("|---|---|---|---|---|")
    for name, w, h, rate, t1m, t2m in (("bunny", 1920, 1080, BUNNY_RATE, 2.655, 1.381),
                                       ("Breakfast Room", 1280, 720, BREAKFAST_RATE, 5.318, 2.668)):
        t1, t2, _ = model(a, 2, w * h, 1024, rate, 32)
        print(f"| {name} | {t2:.3f} | {t2m:.3f} | {t1 / (2 * t2):.3f} | {t1m / (2 * t2m):.3f} |")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--lanes", type=int, default=2)
    p.add_argument("--chunks", type=int, default=32, help="the default chunk count under mpirun")
    p.add_argument("--gpus-per-host", type=int, default=8)
    p.add_argument("--save-ns", type=float, default=SAVE_NS_PER_PIXEL)
    p.add_argument("--merge-ns", type=float, default=MERGE_NS_PER_PIXEL)
    p.add_argument("--host-link", type=float, default=HOST_LINK, help="B/s between ranks of a host")
    p.add_argument("--ib", type=float, default=25e9,
                   help="B/s between hosts (assumed: InfiniBand HDR, 200 Gb/s; NDR 400 Gb/s is 50e9)")
    p.add_argument("--launch-hosts", type=float, default=1.0,
                   help="extra start-up seconds over 16 hosts (assumed)")
    p.add_argument("--check", action="store_true", help="compare with the measured 2-GPU runs")
    p.add_argument("--rate", type=float, help="one GPU's samples/s (a custom table)")
    p.add_argument("--width", type=int, default=3840)
    p.add_argument("--height", type=int, default=2160)
    p.add_argument("--spp", type=int, default=1024)
    a = p.parse_args()
    counts = [1, 2, 4, 8, 128]
    if a.check:
        check(a)
    elif a.rate:
        table(a, "Custom", a.width, a.height, a.spp, a.rate, counts)
    else:
        table(a, "4K frame, bunny-class scene", 3840, 2160, 1024, BUNNY_RATE, counts)
        table(a, "4K frame, Breakfast-Room-class scene", 3840, 2160, 1024, BREAKFAST_RATE, counts)
        table(a, "4K frame, bunny-class scene, 16k spp", 3840, 2160, 16384, BUNNY_RATE, counts)
        table(a, "Issue 15: the bunny at 1920x1080", 1920, 1080, 4096, BUNNY_RATE, counts[:4])
        table(a, "Issue 15: the Breakfast Room at 1280x720", 1280, 720, 4096, BREAKFAST_RATE,
              counts[:4])


if __name__ == "__main__":
    main()
