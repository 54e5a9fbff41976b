// The linear BVH's stages (src/geometry/lbvh.h) as kernels on the current GPU, with CUB's radix
// sort for the keys: what --bvh-build gpu runs when the CUDA backend is built and a GPU is
// present. The host driver (src/geometry/lbvh_build.cpp) runs the same bodies in loops and
// gives the same tree (both sorts are stable on distinct-index ties).
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include "cuda/device_buffer.cuh"
#include "src/core/prefault.h"
#include "src/geometry/lbvh_build.h"
#include "src/geometry/lbvh_collapse.h"

namespace pt {
namespace {

template <typename F>
__global__ void LbvhKernel(uint32_t n, F body) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) body(i);
}

template <typename F>
void Launch(cudaStream_t stream, uint32_t n, F body) {
  if (n == 0) return;
  constexpr uint32_t kBlock = 256;
  LbvhKernel<<<(n + kBlock - 1) / kBlock, kBlock, 0, stream>>>(n, body);
  CudaCheck(cudaGetLastError(), "LBVH kernel");
}

}  // namespace

// The linear BVH's arrays on the current GPU, through the refit (lbvh.h's stages 1-4). In a
// named namespace, with the stages in a function of their own: nvcc takes extended lambdas in
// neither a constructor nor a function of internal linkage.
namespace lbvh_cuda {

struct DeviceLbvh {
  DeviceBuffer<Aabb> bounds;
  DeviceBuffer<uint64_t> keys, keysSorted;
  DeviceBuffer<uint32_t> values, valuesSorted, parent, left, right, rangeLo, rangeHi, visits;
  DeviceBuffer<float> box;
  DeviceBuffer<unsigned char> scratch;
  lbvh::Arrays a;
};

void RunStages(DeviceLbvh& d, const std::vector<Aabb>& host, cudaStream_t stream) {
  const uint32_t n = uint32_t(host.size()), nodes = lbvh::NodeCount(n);
  d.bounds.Upload(host);
  d.keys.Resize(n), d.keysSorted.Resize(n), d.values.Resize(n), d.valuesSorted.Resize(n);
  d.parent.Resize(nodes), d.left.Resize(n - 1), d.right.Resize(n - 1);
  d.rangeLo.Resize(n - 1), d.rangeHi.Resize(n - 1), d.visits.Resize(n - 1);
  d.box.Resize(6 * size_t(nodes));
  d.visits.Zero();
  lbvh::Arrays& a = d.a;
  a.n = n;
  a.bounds = d.bounds.Data();
  a.keys = d.keys.Data();
  a.values = d.values.Data();
  a.parent = d.parent.Data();
  a.left = d.left.Data();
  a.right = d.right.Data();
  a.rangeLo = d.rangeLo.Data();
  a.rangeHi = d.rangeHi.Data();
  a.visits = d.visits.Data();
  a.box = d.box.Data();
  vec3 lo, cells;
  LbvhGrid(host, &lo, &cells);
  const lbvh::Arrays arrays = a;
  Launch(stream, n, [arrays, lo, cells] __device__(uint32_t i) {
    lbvh::MortonCode(arrays, i, lo, cells);
  });
  size_t bytes = 0;
  CudaCheck(cub::DeviceRadixSort::SortPairs(nullptr, bytes, d.keys.Data(), d.keysSorted.Data(),
                                            d.values.Data(), d.valuesSorted.Data(), int(n), 0,
                                            63, stream),
            "LBVH sort");
  d.scratch.Resize(bytes);
  CudaCheck(cub::DeviceRadixSort::SortPairs(d.scratch.Data(), bytes, d.keys.Data(),
                                            d.keysSorted.Data(), d.values.Data(),
                                            d.valuesSorted.Data(), int(n), 0, 63, stream),
            "LBVH sort");
  a.keys = d.keysSorted.Data();
  a.values = d.valuesSorted.Data();
  const lbvh::Arrays sorted = a;
  Launch(stream, n - 1, [sorted] __device__(uint32_t i) { lbvh::EmitInterior(sorted, i); });
  Launch(stream, n, [sorted] __device__(uint32_t i) { lbvh::Refit(sorted, i); });
}

}  // namespace lbvh_cuda

namespace {

// Sets the device; false when there is none or it cannot be used.
bool UseDevice(int device) {
  int devices = 0;
  if (cudaGetDeviceCount(&devices) != cudaSuccess || device >= devices ||
      cudaSetDevice(device) != cudaSuccess) {
    cudaGetLastError();
    return false;
  }
  return true;
}

// An exclusive scan of n counts on the device; returns their total.
uint32_t ExclusiveScan(const uint32_t* in, uint32_t* out, uint32_t n,
                       DeviceBuffer<unsigned char>& scratch, cudaStream_t stream) {
  size_t bytes = 0;
  CudaCheck(cub::DeviceScan::ExclusiveSum(nullptr, bytes, in, out, int(n), stream), "scan");
  if (scratch.Size() < bytes) scratch.Resize(bytes);
  CudaCheck(cub::DeviceScan::ExclusiveSum(scratch.Data(), bytes, in, out, int(n), stream),
            "scan");
  uint32_t last[2] = {0, 0};
  CudaCheck(cudaMemcpyAsync(&last[0], out + n - 1, 4, cudaMemcpyDeviceToHost, stream), "scan");
  CudaCheck(cudaMemcpyAsync(&last[1], in + n - 1, 4, cudaMemcpyDeviceToHost, stream), "scan");
  CudaCheck(cudaStreamSynchronize(stream), "scan");
  return last[0] + last[1];
}

}  // namespace

bool BuildLbvhCuda(const std::vector<Aabb>& bounds, int device, BvhBuildResult* out) {
  const uint32_t n = uint32_t(bounds.size());
  if (n < 2 || !UseDevice(device)) return false;  // one primitive: the host's build
  const cudaStream_t stream = ThreadCopyStream();
  lbvh_cuda::DeviceLbvh d;
  lbvh_cuda::RunStages(d, bounds, stream);
  DeviceBuffer<BvhNode> nodes;
  DeviceBuffer<uint32_t> depth;
  nodes.Resize(lbvh::NodeCount(n));
  depth.Resize(n);
  lbvh::Arrays a = d.a;
  a.out = nodes.Data();
  a.depth = depth.Data();
  Launch(stream, n, [a] __device__(uint32_t i) { lbvh::EmitLayout(a, i); });
  Launch(stream, n, [a] __device__(uint32_t i) { lbvh::LeafDepth(a, i); });
  CudaCheck(cudaStreamSynchronize(stream), "LBVH build");
  std::vector<uint32_t> depths;
  // The host arrays paged in on every core first: a download into fresh pages takes their
  // faults one after another (tens of ms for a multi-million-triangle tree).
  ReserveOnThreads(out->nodes, nodes.Size());
  ReserveOnThreads(out->primOrder, n);
  ReserveOnThreads(depths, n);
  nodes.Download(out->nodes);
  d.valuesSorted.Download(out->primOrder);
  depth.Download(depths);
  return FinishLbvh(depths, out);
}

bool BuildWideLbvhCuda(const std::vector<Aabb>& bounds, int device, WideBvhResult* out) {
  const uint32_t n = uint32_t(bounds.size());
  if (n < 2 || !UseDevice(device)) return false;
  const cudaStream_t stream = ThreadCopyStream();
  lbvh_cuda::DeviceLbvh d;
  lbvh_cuda::RunStages(d, bounds, stream);
  const uint32_t nodes = lbvh::NodeCount(n);
  DeviceBuffer<float> cost, sah;
  DeviceBuffer<int8_t> choice, split8;
  DeviceBuffer<uint8_t> asLeaf;
  DeviceBuffer<uint32_t> visits, primOrder;
  DeviceBuffer<WideBvhNode> wide;
  cost.Resize(size_t(nodes) * lbvh::kCollapseWidth), choice.Resize(cost.Size());
  split8.Resize(nodes), asLeaf.Resize(nodes), visits.Resize(n - 1), visits.Zero();
  wide.Resize(n), primOrder.Resize(n), sah.Resize(n), sah.Zero();
  lbvh::CollapseArrays c;
  c.cost = cost.Data();
  c.choice = choice.Data();
  c.split8 = split8.Data();
  c.asLeaf = asLeaf.Data();
  c.visits = visits.Data();
  c.wide = wide.Data();
  c.primOrder = primOrder.Data();
  c.sah = sah.Data();
  const lbvh::Arrays a = d.a;
  Launch(stream, n, [a, c] __device__(uint32_t i) { lbvh::CollapseCosts(a, c, i); });
  // A level's tasks and counts, for up to n wide nodes.
  DeviceBuffer<uint32_t> taskNode, taskWide, nextNode, nextWide, children, count, interior,
      prims, interiorOffset, primOffset;
  for (auto* b : {&taskNode, &taskWide, &nextNode, &nextWide, &count, &interior, &prims,
                  &interiorOffset, &primOffset})
    b->Resize(n);
  children.Resize(size_t(n) * lbvh::kCollapseWidth);
  uint32_t *curNode = taskNode.Data(), *curWide = taskWide.Data();
  uint32_t *nxtNode = nextNode.Data(), *nxtWide = nextWide.Data();
  CudaCheck(cudaMemsetAsync(curNode, 0, 4, stream), "LBVH collapse");  // the root's task
  CudaCheck(cudaMemsetAsync(curWide, 0, 4, stream), "LBVH collapse");
  uint32_t tasks = 1, nodeCount = 1, primCount = 0;
  int depth = 0;
  for (; tasks > 0; ++depth) {
    if (depth >= kWideStackSize) return false;
    c.taskNode = curNode;
    c.taskWide = curWide;
    c.taskChildren = children.Data();
    c.taskCount = count.Data();
    c.taskInterior = interior.Data();
    c.taskPrims = prims.Data();
    Launch(stream, tasks, [a, c] __device__(uint32_t t) { lbvh::CountLevel(a, c, t); });
    const uint32_t interiorTotal =
        ExclusiveScan(interior.Data(), interiorOffset.Data(), tasks, d.scratch, stream);
    const uint32_t primTotal =
        ExclusiveScan(prims.Data(), primOffset.Data(), tasks, d.scratch, stream);
    c.interiorOffset = interiorOffset.Data();
    c.primOffset = primOffset.Data();
    c.nodeBase = nodeCount;
    c.primBase = primCount;
    c.nextNode = nxtNode;
    c.nextWide = nxtWide;
    Launch(stream, tasks, [a, c] __device__(uint32_t t) { lbvh::EmitNode(a, c, t); });
    nodeCount += interiorTotal;
    primCount += primTotal;
    tasks = interiorTotal;
    std::swap(curNode, nxtNode);
    std::swap(curWide, nxtWide);
  }
  CudaCheck(cudaStreamSynchronize(stream), "LBVH collapse");
  if (primCount != n) return false;
  ReserveOnThreads(out->nodes, nodeCount);  // as BuildLbvhCuda's downloads
  ReserveOnThreads(out->primOrder, n);
  out->nodes.resize(nodeCount);
  CudaCheck(cudaMemcpyAsync(out->nodes.data(), wide.Data(), nodeCount * sizeof(WideBvhNode),
                            cudaMemcpyDeviceToHost, stream),
            "LBVH download");
  std::vector<float> parts(nodeCount);
  CudaCheck(cudaMemcpyAsync(parts.data(), sah.Data(), nodeCount * sizeof(float),
                            cudaMemcpyDeviceToHost, stream),
            "LBVH download");
  float rootBox[6];
  for (int k = 0; k < 6; ++k) {
    CudaCheck(cudaMemcpyAsync(&rootBox[k], d.box.Data() + size_t(k) * nodes, 4,
                              cudaMemcpyDeviceToHost, stream),
              "LBVH download");
  }
  primOrder.Download(out->primOrder);  // waits for the stream's copies
  CudaCheck(cudaStreamSynchronize(stream), "LBVH download");
  out->maxDepth = depth - 1;
  double total = 0.0;
  for (float p : parts) total += double(p);
  Aabb root;
  root.lo = vec3(rootBox[0], rootBox[1], rootBox[2]);
  root.hi = vec3(rootBox[3], rootBox[4], rootBox[5]);
  const float rootArea = lbvh::BoxArea(root);
  out->sahCost = rootArea > 0.0f ? total / rootArea : 0.0;
  return true;
}

}  // namespace pt
