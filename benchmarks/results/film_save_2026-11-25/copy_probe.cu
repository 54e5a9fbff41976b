#include <cuda_runtime.h>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <vector>
#include <thread>
using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point a) { return std::chrono::duration<double, std::milli>(Clock::now() - a).count(); }
__global__ void Spin(float* p, int n, int iters) { int i = blockIdx.x * blockDim.x + threadIdx.x; if (i < n) { float v = p[i]; for (int k = 0; k < iters; ++k) v = v * 1.0000001f + 1e-7f; p[i] = v; } }
int main() {
  size_t bytes = 72u << 20;
  void* d; cudaMalloc(&d, bytes); cudaMemset(d, 1, bytes); cudaDeviceSynchronize();
  for (int rep = 0; rep < 3; ++rep) {
    auto t = Clock::now(); std::vector<char> fresh(bytes); double alloc = Ms(t);
    t = Clock::now(); cudaMemcpy(fresh.data(), d, bytes, cudaMemcpyDeviceToHost); double fr = Ms(t);
    t = Clock::now(); cudaMemcpy(fresh.data(), d, bytes, cudaMemcpyDeviceToHost); double warm = Ms(t);
    char* pinned; t = Clock::now(); cudaMallocHost(&pinned, bytes); double palloc = Ms(t);
    t = Clock::now(); cudaMemcpy(pinned, d, bytes, cudaMemcpyDeviceToHost); double p1 = Ms(t);
    t = Clock::now(); cudaMemcpy(pinned, d, bytes, cudaMemcpyDeviceToHost); double p2 = Ms(t);
    t = Clock::now(); std::memcpy(fresh.data(), pinned, bytes); double mc = Ms(t);
    t = Clock::now(); cudaHostRegister(fresh.data(), bytes, 0); double reg = Ms(t);
    t = Clock::now(); cudaMemcpy(fresh.data(), d, bytes, cudaMemcpyDeviceToHost); double r1 = Ms(t);
    t = Clock::now(); cudaHostUnregister(fresh.data()); double unreg = Ms(t);
    t = Clock::now(); cudaFreeHost(pinned); double pfree = Ms(t);
    printf("72MB: vector alloc+zero %.1f | pageable fresh %.1f warm %.1f | mallocHost %.1f pinned %.1f %.1f | memcpy %.1f | register %.1f regcopy %.1f unreg %.1f | freeHost %.1f\n", alloc, fr, warm, palloc, p1, p2, mc, reg, r1, unreg, pfree);
  }
  {
    size_t n = 2073600; std::vector<float> src(n * 3, 1.5f); std::vector<double> dst(n * 3, 0.0);
    for (int threads : {1, 2, 4, 8}) {
      for (int rep = 0; rep < 2; ++rep) {
        auto t = Clock::now(); std::vector<std::thread> ws;
        for (int k = 0; k < threads; ++k) ws.emplace_back([&, k] { size_t lo = n * 3 * k / threads, hi = n * 3 * (k + 1) / threads; for (size_t i = lo; i < hi; ++i) dst[i] = src[i]; });
        for (auto& w : ws) w.join();
        printf("widen 2M vec3 -> dvec3, %d threads: %.2f ms\n", threads, Ms(t));
      }
    }
  }
  // Interference: kernels on a non-blocking stream from thread A while thread B does pageable copies.
  float* work; int n = 1 << 24; cudaMalloc(&work, n * 4); cudaMemset(work, 0, n * 4);
  for (int mode = 0; mode < 5; ++mode) {
    cudaStream_t s; cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking);
    std::vector<char> host(bytes); char* pinned; cudaMallocHost(&pinned, bytes);
    cudaDeviceSynchronize();
    bool stop = false; int copies = 0;
    std::thread copier([&] { cudaSetDevice(0); cudaStream_t cs; cudaStreamCreateWithFlags(&cs, cudaStreamNonBlocking); while (!stop && mode > 0) { char* dst = (mode == 1 || mode == 3) ? host.data() : pinned; if (mode <= 2) cudaMemcpy(dst, d, bytes, cudaMemcpyDeviceToHost); else { cudaMemcpyAsync(dst, d, bytes, cudaMemcpyDeviceToHost, cs); cudaStreamSynchronize(cs); } ++copies; } cudaStreamDestroy(cs); });
    auto t = Clock::now();
    for (int k = 0; k < 400; ++k) { Spin<<<n / 256, 256, 0, s>>>(work, n, 20); if (k % 4 == 3) cudaStreamSynchronize(s); }
    cudaStreamSynchronize(s); double ms = Ms(t); stop = true; copier.join();
    printf("400 kernels (sync every 4) with %s copies beside: %.1f ms (%d copies)\n", (const char*[]){"no", "pageable", "pinned", "pageable async own stream", "pinned async own stream"}[mode], ms, copies);
    cudaFreeHost(pinned); cudaStreamDestroy(s);
  }
}
