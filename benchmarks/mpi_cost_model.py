#!/usr/bin/env python3
"""Cost model of the MPI sample split (docs/distributed.md): expected render time and
efficiency T1 / (N * TN) on N GPUs, from the per-sample time of one GPU, the film's bytes,
and the bandwidths of host memory, the links within a host and InfiniBand between hosts.

    python3 benchmarks/mpi_cost_model.py              # the tables of docs/distributed.md
    python3 benchmarks/mpi_cost_model.py --rate 480e6 --width 1920 --height 1080 --spp 1024

What it models (src/distributed/): the samples are cut into C chunks (leaves); each GPU runs
L lanes that render one leaf at a time into a fresh film, download it (t_save) and merge it
along the fixed tree on the host (t_merge per merge, multi-threaded, memory-bound). With two
lanes, one lane's download overlaps the other's rendering, so a leaf costs the GPU
max(t_leaf, (t_leaf + t_save) / L). At the end, the last leaf's download, the merges up the
rank's own subtree (log2 of its leaves), then ceil(log2 N) levels of the binomial tree of
ranks, each one film transfer plus one merge, are not overlapped: that is the reduction tail.
Start-up (mpirun, MPI_Init, scene load, BVH, CUDA context, upload) happens on every rank at
once and does not shrink with N.
"""
import argparse
import math

# A film on the wire and in host memory: mean and M2 as 2 x 3 doubles, luminance mean and M2
# (2 floats), a count: 60 bytes a pixel (88 with the EXR feature channels).
FILM_BYTES = 60
# The film on the GPU (float): mean and M2 3 floats each, 2 luminance floats, a count.
DEVICE_FILM_BYTES = 36
# A merge reads two films and writes one.
MERGE_BYTES = 3 * FILM_BYTES


def leaf_costs(a, pixels):
    t_save = pixels * DEVICE_FILM_BYTES / a.d2h + pixels * 2 * 24 / a.hostwrite
    t_merge = pixels * MERGE_BYTES / a.membw
    return t_save, t_merge


def model(a, n, pixels, spp, rate, chunks):
    """Seconds: (one GPU's render, N GPUs' render phase, the tail within it)."""
    t1 = pixels * spp / rate
    t_leaf = pixels * (spp / chunks) / rate
    t_save, t_merge = leaf_costs(a, pixels)
    leaves = chunks / n
    per_leaf = max(t_leaf, (t_leaf + t_save) / a.lanes)
    render = math.ceil(leaves) * per_leaf if chunks % (n * a.lanes) else leaves * per_leaf
    film = pixels * FILM_BYTES
    levels_host = math.ceil(math.log2(min(n, a.gpus_per_host))) if n > 1 else 0
    levels_ib = math.ceil(math.log2(n / a.gpus_per_host)) if n > a.gpus_per_host else 0
    cascade = math.ceil(math.log2(max(1.0, leaves))) * t_merge
    transfer = levels_host * (film / a.host_link + t_merge) + levels_ib * (film / a.ib + t_merge)
    tail = (t_save + cascade + transfer) if n > 1 else 0.0
    return t1, (render + tail) if n > 1 else t1, tail


def table(a, title, width, height, spp, rate, counts):
    pixels = width * height
    startup1 = a.startup
    print(f"\n### {title}: {width}x{height}, {spp} spp, {rate / 1e6:.0f} M samples/s per GPU\n")
    print("| GPUs | chunks | render s | tail ms | efficiency (render) | efficiency (with start-up) |")
    print("|---|---|---|---|---|---|")
    for n in counts:
        chunks = min(spp, max(a.chunks, 4 * n * a.lanes)) if n > 1 else 1
        t1, tn, tail = model(a, n, pixels, spp, rate, chunks)
        startup = startup1 + (a.startup_hosts if n > a.gpus_per_host else 0.0)
        eff = t1 / (n * tn)
        eff_all = (startup1 + t1) / (n * (startup + tn))
        label = f"{n // a.gpus_per_host} x {a.gpus_per_host}" if n > a.gpus_per_host else f"{n}"
        print(f"| {label} | {chunks} | {tn:.3f} | {tail * 1e3:.0f} | {eff:.3f} | {eff_all:.3f} |")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--lanes", type=int, default=2)
    p.add_argument("--chunks", type=int, default=32, help="default chunk count under mpirun")
    p.add_argument("--gpus-per-host", type=int, default=8)
    # Host side, per rank (assumptions; docs/distributed.md states them and the measured values).
    p.add_argument("--d2h", type=float, default=12e9, help="GPU to pageable host memory, B/s")
    p.add_argument("--hostwrite", type=float, default=10e9, help="fresh host memory writes, B/s")
    p.add_argument("--membw", type=float, default=40e9, help="merge threads' memory bandwidth, B/s")
    p.add_argument("--host-link", type=float, default=8e9,
                   help="one film between ranks of a host (shared memory, single copy), B/s")
    p.add_argument("--ib", type=float, default=25e9, help="InfiniBand HDR 200 Gb/s, B/s")
    p.add_argument("--startup", type=float, default=2.0, help="seconds, every rank at once")
    p.add_argument("--startup-hosts", type=float, default=1.0,
                   help="extra seconds to launch over 16 hosts")
    p.add_argument("--rate", type=float, help="samples/s of one GPU (custom table)")
    p.add_argument("--width", type=int, default=3840)
    p.add_argument("--height", type=int, default=2160)
    p.add_argument("--spp", type=int, default=1024)
    a = p.parse_args()
    counts = [1, 2, 4, 8, 128]
    if a.rate:
        table(a, "Custom", a.width, a.height, a.spp, a.rate, counts)
        return
    # Rates measured on an H100 (benchmarks/RESULTS.md, issue 3).
    bunny, breakfast = 480e6, 70.6e6
    table(a, "Bunny-class scene (bunny in the Cornell box)", 1920, 1080, 1024, bunny, counts)
    table(a, "4K frame, bunny-class scene", 3840, 2160, 1024, bunny, counts)
    table(a, "4K frame, Breakfast-Room-class scene", 3840, 2160, 1024, breakfast, counts)
    table(a, "4K frame, bunny-class scene, 16k spp", 3840, 2160, 16384, bunny, counts)


if __name__ == "__main__":
    main()
