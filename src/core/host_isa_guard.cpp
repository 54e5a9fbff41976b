// A build for x86-64-v3 (CMake's PT_HOST_ISA; AVX2, FMA, BMI2) started on an older CPU would
// die of SIGILL somewhere in its first vector instruction. This file is compiled for baseline
// x86-64 and checks the CPU before any other static initialiser runs, so that start instead
// ends with a message saying what to rebuild. The linker is told to keep it (PT_HOST_ISA_GUARD
// is referenced from CMake), although nothing calls it.
#include <cstdio>
#include <cstdlib>

#if defined(PT_HOST_ISA_V3) && (defined(__x86_64__) || defined(__i386__))
extern "C" __attribute__((constructor(101))) void PtHostIsaGuard() {
  __builtin_cpu_init();
  // PT_TEST_PRETEND_OLD_CPU: the test suite's way to see this path (tests/cli_run_test.cpp).
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
      __builtin_cpu_supports("bmi2") && std::getenv("PT_TEST_PRETEND_OLD_CPU") == nullptr)
    return;
  std::fputs(
      "error: this build of pathtracer needs an x86-64-v3 CPU (AVX2, FMA, BMI2: Intel Haswell "
      "or AMD Zen and later), which this one is not; rebuild it here with "
      "cmake -DPT_HOST_ISA=baseline (see README.md)\n",
      stderr);
  std::_Exit(3);  // docs/cli.md: runtime failure
}
#else
extern "C" void PtHostIsaGuard() {}
#endif
