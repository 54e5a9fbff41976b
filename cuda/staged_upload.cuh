// Big uploads from pageable host memory through pinned buffers, the host's copies into them
// on several threads while the copy engine moves the previous buffer (cuda/staged_upload.cu).
//
// A pageable cudaMemcpy stages through the driver's own pinned memory with one thread: on the
// H100 host 155-163 ms per GiB; three pinned 16 MiB buffers filled by 8 threads take 48-56 ms,
// plus 26-38 ms once to allocate them (benchmarks/results/upload_probe_2026-11-27). So the
// buffers are made ahead, beside the scene's preparation, for a big scene (CudaPrepareUploads,
// render_api.h), or by an upload big enough to pay for them; small scenes never make them.
#pragma once

#include <cuda_runtime.h>

#include <cstddef>

namespace pt {

// Arrays below this size always take the plain pageable copy.
constexpr size_t kStagedUploadMinBytes = size_t(32) << 20;

// dst (device) <- src (pageable host) through the pinned buffers, done when it returns; false
// when it did not copy (bytes below kStagedUploadMinBytes, or no buffers yet and the upload
// too small to make them for): the caller copies as usual. Thread-safe.
bool StagedUploadCopy(void* dst, const void* src, size_t bytes, cudaStream_t stream);

}  // namespace pt
