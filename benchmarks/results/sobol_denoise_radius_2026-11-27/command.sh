# H100 (nvidia-h100-x1), three device calls on one machine's lease, main df8d155 + sampler merge
# (the build of 20:34, default denoise radius still 7; `--denoise-radius` picks the others).
# 1. GPU tests (pt_tests alone; its CLI cases fail without the pathtracer binary): gpu_tests.log
pt_tests --gtest_brief=1 --gtest_filter='*Gpu*:Denoise*:HalfFilms*:Specialization*:AxisRays*:Sobol*:Sampler*:Lbvh*:Light*'
# 2. render rates, 5 interleaved rounds, independent vs --sampler sobol (rates_stats.tgz)
for i in 1 2 3 4 5; do for s in independent sobol; do
  pathtracer ../shared/peer-scenes/pbrt_cornell.json --spp 1024 --sampler $s --stats-json pbrt_$s_$i.json -o p.png
  pathtracer scenes/cornell_box.json --width 512 --height 512 --spp 64 --sampler $s --stats-json cb_$s_$i.json -o p.png
done; done
# CPU (--threads 16) against GPU, 128^2, 64 spp, each sampler: max and mean |difference|
# 3. the denoiser's time: STEPS=time bash benchmarks/denoise_check.sh, then 3 interleaved runs of
for r in 7 6 5; do taskset -c 0,1 pathtracer benchmarks/scenes/bunny_cornell.json --spp 1 --denoise --denoise-radius $r --backend cpu --threads 2 -o t.png; done  # and taskset -c 0,2
# 4. the denoiser's error at radius 7, 6 and 5 (denoise_curve.csv/.md)
python3 benchmarks/denoise_curve.py --binary pathtracer --out dq \
  --scenes benchmarks/scenes/bunny_cornell.json:1920x1080,benchmarks/scenes/breakfast_room_sunsky.json:1280x720,benchmarks/scenes/damaged_helmet.json:1920x1080 \
  --spps 16,256 --seeds 4 --ref-spp 4096 --variant "radius 6=--denoise-radius 6" --variant "radius 5=--denoise-radius 5"
# 5. light samplers with each sampler (accuracy_lights_*.md/.csv/.png)
for s in independent sobol; do
  python3 benchmarks/accuracy_lights.py --binary pathtracer --backend cuda --size 960x540 --spps 16,64,256 --seeds 2 \
    --ref-spp 8192 --methods bvh,power --scenes benchmarks/scenes/damaged_helmet_emissive.json,benchmarks/scenes/many_lights_breakfast.json \
    --extra "--sampler $s" --out al_$s
done
