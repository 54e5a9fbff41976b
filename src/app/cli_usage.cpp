// The text --help prints: every option of src/app/cli.cpp, grouped.
#include "src/app/cli.h"

namespace pt {

std::string CliUsage() {
  return R"(usage: pathtracer SCENE.json -o OUT [options]

Renders SCENE.json (see scene-format.md) to OUT (.png sRGB; .exr or .pfm linear).
Options take `--flag V` or `--flag=V`; they override the scene's values.

Outputs
  -o FILE                  the image (required)
  --hdr FILE               also a linear .exr (with variance, sample-count, albedo, normal
                           and depth channels) or .pfm
  --spp-map FILE           samples per pixel: a heat map (.png) or raw counts (.exr/.pfm)
  --stats-json FILE        write render statistics as JSON
  --reference FILE         log relMSE against this .exr/.pfm image into the stats

Image and sampling
  --spp N                  samples per pixel
  --width W, --height H    image size in pixels
  --crop X0 Y0 X1 Y1       render only this pixel window [X0,X1) x [Y0,Y1)
  --max-depth D            most bounces a path may take
  --rr-depth N|off         Russian roulette from bounce N, or never
  --seed S                 random seed (0..4294967295)
  --integrator mis|bsdf|nee  light transport estimator (default mis)
  --adaptive on|off        adaptive sampling (default: the scene's render.adaptive)
  --light-paths all|direct|indirect  which light paths count (default all)
  --clamp L                firefly clamp: scale each sample down to luminance L at most
                           (off by default; biased, and marked so in the stats)

Backend and performance
  --backend auto|cpu|cuda  auto = CUDA when built and a GPU is present (default auto)
  --threads N              CPU threads, 0 = all cores (default 0)
  --max-paths N            paths in flight at once (default: the backend's); lower it when
                           the GPU runs out of memory
  --compact on|off|auto    stream compaction of finished paths (default auto)
  --sort off|material|queues|auto
                           shading order: as queued; ordered by material (one kernel); or
                           ordered and one kernel per material type and texturing (queues);
                           auto picks from the scene's materials (docs/sorting.md)
  --sort-method auto|counting|radix|radix32
                           how paths are ordered: counting sort, radix sort over the key
                           bits, or over all 32 (default auto: counting)
  --specialize on|off      shade-stage variant compiled for the scene's effects (default on)
  --film float|double      film accumulation precision (default float)
  --tri-test watertight|mt triangle test (default watertight)
  --ray-offset robust|EPS  ray origin offsets from error bounds, or a fixed epsilon

Long renders
  --time-limit SECONDS     stop after this much render time, write what has accumulated
  --preview-every SECONDS  rewrite the outputs as samples accumulate
  --checkpoint-every SECONDS  rewrite the --hdr EXR as a resumable state this often
  --resume FILE.exr        continue the render an interrupted or checkpointed run left in
                           its --hdr EXR (same scene, size, crop, seed and settings)
  --progress-every SECONDS progress line interval when stderr is not a terminal (default 10)
  --quiet                  no progress bar or progress lines
  --help, --version

SIGINT, SIGTERM and SIGHUP stop the render after the current wave and write the image so far
(an --hdr EXR then holds a resumable state); a second signal quits at once.

Exit status: 0 success, 1 bad command line, 2 bad scene or input file (nothing written),
3 runtime failure (no GPU, out of memory, unwritable output), 128+N stopped by signal N
(130 SIGINT, 143 SIGTERM, 129 SIGHUP; the image is written).
)";
}

}  // namespace pt
