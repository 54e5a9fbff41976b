# H100 (nvidia-h100-x1), main 835ef01 (the light BVH's box-bounded cosines merged), packed by
# tools/pack_device.sh (pt_tests carried in a second call: the GPU tests below).
OUT=$OUT/l30 bash benchmarks/light_bvh_check.sh
# (this run's sanitizer step failed to make its scene - fixed in light_bvh_check.sh since; run by
# hand in a later call: compute-sanitizer memcheck, the 2,000-lamp city, bvh, sort off and queues:
# 0 errors each)
# GPU tests of the same commit:
#   pt_tests --gtest_filter='AxisRays*:Lbvh*:*Gpu*:Light*:Denoise*:-LongRender*'  (87 passed, 1 skipped)
