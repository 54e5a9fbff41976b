// The text --help prints: every option of src/app/cli.cpp, grouped.
#include "src/app/cli.h"

namespace pt {

std::string CliUsage() {
  return R"(usage: pathtracer SCENE -o OUT [options]
       pathtracer SCENE --serve [PORT] [options]

Renders SCENE to OUT (.png sRGB; .exr or .pfm linear). SCENE is a JSON scene, or a .gltf,
.glb or .obj file rendered as a whole scene (docs/scene-format.md; options: docs/cli.md).
Options take `--flag V` or `--flag=V`; they override the scene's values.

Outputs
  -o FILE                  the image (required)
  --hdr FILE               also a linear .exr (with variance, sample-count, albedo, normal
                           and depth channels) or .pfm
  --spp-map FILE           samples per pixel: a heat map (.png) or raw counts (.exr/.pfm)
  --stats-json FILE        write render statistics as JSON
  --reference FILE         log relMSE against this .exr/.pfm image into the stats
  --denoise                denoise -o (NL-means on the two half films, guided by albedo,
                           normal and depth; docs/denoise.md); an --hdr EXR keeps the raw
                           image and gains denoised.R/G/B
  --denoise-outliers on|off  scale fireflies down to their neighbourhood before denoising
                           (Cycles' outlier detection; default on)
  --denoise-radius N       the denoiser's search window, (2N + 1)^2 pixels (1..20; default
                           5; 7 takes about 1.6x the time for 6-10% less error)
  --denoise-variance calibrated|sample  the noise the denoiser assumes: the sample variance
                           scaled to the two half films' difference (what --sampler sobol
                           needs, its default), or the sample variance as it is (the
                           default for independent samples)
  --denoise-emission keep|filter  the emission camera rays see directly: kept out of the
                           filter and added back (an emissive texture keeps its detail), or
                           filtered with the rest (default)

Image and sampling
  --spp N                  samples per pixel
  --width W, --height H    image size in pixels (one alone keeps a glTF scene's aspect ratio)
  --crop X0 Y0 X1 Y1       render only this pixel window [X0,X1) x [Y0,Y1)
  --max-depth D            most bounces a path may take
  --rr-depth N|off         Russian roulette from bounce N, or never
  --seed S                 random seed (0..4294967295)
  --integrator mis|bsdf|nee  light transport estimator (default mis)
  --adaptive on|off        adaptive sampling (default: the scene's render.adaptive)
  --light-paths all|direct|indirect  which light paths count (default all)
  --clamp L                firefly clamp: scale each sample down to luminance L at most
                           (off by default; biased, and marked so in the stats)
  --energy-compensation off|on  rough metals return the energy single-scattering GGX loses
                           (Kulla-Conty; default off: the glTF specification's and Blender
                           3.4's single scattering)

Camera and environment
  --camera N|NAME          the glTF camera to render through, by index or name (default: the
                           file's first perspective camera, else an automatic one)
  --time SECONDS           pose glTF files at this time of an animation: node motion, skins,
                           morph targets, cameras (default: the file's static pose)
  --animation N|NAME|all   the glTF animation --time poses, by index or name, or all at once
                           (default 0; alone: posed at its start)
  --variant NAME           the glTF file's KHR_materials_variants variant to render (default:
                           the materials the file assigns)
  --env FILE               environment map (.exr, .hdr, .pfm; 2:1 equirectangular) replacing
                           the scene's environment or background
  --env none               no environment: only the scene's lights and emitters light it
  --env-strength S         scale of the environment's radiance (default: the scene's, or 1)
  --env-sampling importance|uniform  how next-event estimation samples the map (default
                           importance: by luminance x solid angle)
  --light-sampler uniform|power|bvh|auto  how next-event estimation chooses a light (default
                           auto: bvh with 16 or more finite lights, else power)
  --sampler independent|sobol  the random numbers: independent (pcg4d, default) or
                           Owen-scrambled Sobol, stratified over each pixel's samples
  --fog SIGMA_S            fill the space around the camera with a homogeneous, white,
                           isotropic medium scattering SIGMA_S per unit length (replaces the
                           scene's "medium"; docs/media.md)
  --transmittance ratio|delta  how shadow rays estimate transmittance through grid media
                           (default ratio tracking; delta: the binary estimator, a study)

Backend and performance
  --backend auto|cpu|cuda  auto = CUDA when built and a GPU is present (default auto)
  --threads N              CPU threads, 0 = all cores (default 0)
  --max-paths N            paths in flight at once (default: the backend's); lower it when
                           the GPU runs out of memory
  --compact on|off|auto    stream compaction of finished paths (default auto)
  --ray-order on|off|auto  sort each bounce's rays by direction and origin before tracing
                           (default auto)
  --prim-pool on|off|auto  GPU, wide BVH: the lanes of a warp test their leaves' primitives
                           together (default auto: on for scenes of 131,072+ primitives)
  --warm-up on|off|auto    trace a short discarded wave before the render so that kernels
                           load outside its time (default auto: on the GPU when kernels load
                           lazily, CUDA's default)
  --sort off|material|queues|auto
                           shading order: as queued; ordered by material (one kernel); or
                           ordered and one kernel per material type and texturing (queues);
                           auto picks from the scene's materials (docs/sorting.md)
  --sort-method auto|counting|radix|radix32
                           how paths are ordered: counting sort, radix sort over the key
                           bits, or over all 32 (default auto: counting)
  --bvh binary|wide|auto   BVH node layout: binary, or 8-wide compressed; auto = the faster
                           one measured (wide, on the CPU and the GPU; default auto)
  --bvh-build sah|sbvh|gpu|auto
                           binned SAH, SAH with spatial splits (slower build), or the linear
                           BVH built on the GPU (on the CPU without one; faster build, slower
                           rays); default auto: gpu for meshes of 2^20+ primitives rendered on
                           a GPU, else sah
  --specialize on|off      shade-stage variant compiled for the scene's effects (default on)
  --film float|double      film accumulation precision (default float)
  --tri-test watertight|box-clamped|mt
                           triangle test; box-clamped: watertight, and the closest of
                           coincident surfaces never depends on the BVH (default watertight)
  --ray-offset robust|EPS  ray origin offsets from error bounds, or a fixed epsilon

Long renders
  --time-limit SECONDS     stop after this much render time, write what has accumulated
  --preview-every SECONDS  rewrite the outputs as samples accumulate
  --checkpoint-every SECONDS  rewrite the --hdr EXR as a resumable state this often
  --resume FILE.exr        continue the render an interrupted or checkpointed run left in
                           its --hdr EXR (same scene, size, crop, seed and settings)
  --progress-every SECONDS progress line interval when stderr is not a terminal (default 10)
  --quiet                  no progress bar or progress lines

Live preview
  --serve [PORT]           render progressively for a browser at http://127.0.0.1:PORT/
                           (default port 8765; see docs/serve.md); -o and --hdr are
                           written when Ctrl-C stops it
  --bind ADDR              with --serve: listen on ADDR instead of 127.0.0.1
  --env-dir DIR            with --serve: the environment maps the page offers (default:
                           the scene's folder)
  --exposure STOPS         the PNG's (and the preview's) exposure, in [-20, 20] (default 0)
  --tonemap clip|agx       the PNG's (and the preview's) tone mapping: plain sRGB clipping
                           (default) or an AgX-style filmic curve (docs/cli.md)

  --help, --version

Several GPUs or hosts (a build with MPI; see docs/distributed.md)
  mpirun -np N pathtracer SCENE.json -o OUT [options] splits the samples over N processes,
  each on its own GPU (local rank mod GPUs) or CPU threads; rank 0 writes every output.
  --chunks N               cut the samples into N chunks merged along a fixed tree: the
                           image of `mpirun -np K pathtracer ... --chunks N` for any K
                           (default 1; under mpirun 32, at most spp)
  --rank-timeout SECONDS   under mpirun: give up on a rank silent this long (default 60)
  --lanes N                under mpirun: render lanes (sessions) per rank; 2 on a GPU overlap
                           one lane's film download with the other's rendering (default 2 on
                           a GPU, 1 on the CPU)

SIGINT, SIGTERM and SIGHUP stop the render after the current wave and write the image so far
(an --hdr EXR then holds a resumable state); a second signal quits at once.

Exit status: 0 success, 1 bad command line, 2 bad scene or input file (nothing written),
3 runtime failure (no GPU, out of memory, unwritable output), 128+N stopped by signal N
(130 SIGINT, 143 SIGTERM, 129 SIGHUP; the image is written).
)";
}

}  // namespace pt
