# H100 (nvidia-h100-x1), 16 host cores. NEW: this tree at 228b6cd + the PNG change of the next
# commit (lazy module loading with the warm-up wave, the render module loaded on the start-up
# thread, --compress-mode=speed, the film resolved on the device, OpenVDB as a module); EAGER:
# the same binary under CUDA_MODULE_LOADING=EAGER (no warm-up); BASE: bc3982d. Packed with
# tools/pack_device.sh (base beside it, see benchmarks/issue28_gpu_check.sh).
BASE=.device/base NEW=.device/bin SHARED=$PWD/.device/shared OUT=$OUT/i28 REPEATS=5 BIG_REPEATS=3 \
  WALL_VARIANTS="BASE NEW EAGER" STEPS="wall bvh" bash benchmarks/issue28_gpu_check.sh
# The denoiser's times in the same call (a merge of branch dnspeed, reverted after this):
OUT=$OUT/dn STEPS="info time" bash benchmarks/denoise_check.sh
