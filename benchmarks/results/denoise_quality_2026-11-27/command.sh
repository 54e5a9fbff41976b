# H100 (nvidia-h100-x1), main 76365c0's binary packed with its libraries (tools/pack_device.sh);
# the scenes at their own size (Breakfast Room sun and sky 1280x720, DamagedHelmet 1920x1080).
OUT=$OUT/dn STEPS=quality SCENES="breakfast helmet" REF_SPP=4096 bash benchmarks/denoise_check.sh
# The 2-core CPU time of --denoise at 1080p (main 189b407):
OUT=$OUT/dn STEPS=time bash benchmarks/denoise_check.sh
