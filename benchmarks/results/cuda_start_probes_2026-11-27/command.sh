# H100 (nvidia-h100-x1). What a GPU run's start-up and exit cost outside the renderer.
# 1. exit: a process that makes the context, allocates and touches N GiB, optionally frees,
#    prints a CLOCK_REALTIME stamp and returns from main or calls _Exit; exit_ms = the shell's
#    stamp after the process ended - the printed one (nvcc -O2 exit_probe.cu):
for mode in "0 keep normal" "4 keep normal" "4 free normal" "4 keep quick" "4 free quick" "0 keep quick"; do
  for r in 1 2 3; do out=$(/tmp/exit_probe $mode); end=$(date +%s%N); echo "$mode: $out exit_ms $(( (end - ${out##*END }) / 1000000 ))"; done
done
# 2. process start: `pathtracer --version` wall ms, bc3982d (base, OpenVDB linked) and this tree
#    (bin, OpenVDB in libpt_vdb.so loaded on demand).
# 3. module loads: cuobjdump -xelf all pathtracer; fatbinary -64 --create=r_MODE.fatbin
#    --image3=kind=elf,sm=90,file=render_cuda.sm_90.cubin --compress-all --compress-mode=MODE;
#    then module_probe FILES... (cuInit, primary context, cuModuleLoad, cuModuleEnumerateFunctions,
#    cuFuncLoad each) under CUDA_MODULE_LOADING=LAZY and EAGER.
