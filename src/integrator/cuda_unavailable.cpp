// In a build configured without CUDA, asking for the GPU backend is a clear error (exit 3 in
// the app), never a crash or a silent fallback.
#include "src/denoise/denoiser.h"
#include "src/integrator/render_session.h"

#if !defined(PT_HAVE_CUDA)
namespace pt {

std::unique_ptr<RenderSession> MakeCudaSession(const Scene&, const RenderOptions&,
                                               const RenderCallbacks&) {
  throw BackendUnavailable(
      "this build has no CUDA backend (configured without a CUDA compiler); use --backend cpu");
}
RenderResult RenderCuda(const Scene& scene, const RenderOptions& options,
                        const RenderCallbacks& callbacks) {
  return MakeCudaSession(scene, options, callbacks)->Render();
}
std::unique_ptr<Denoiser> MakeCudaDenoiser(int, const DenoiseSettings&) {
  throw BackendUnavailable(
      "this build has no CUDA backend (configured without a CUDA compiler); use --backend cpu");
}
bool CudaBackendBuilt() { return false; }
int CudaDeviceCount() { return 0; }
int CudaStartDevice(int) { return 0; }
std::string CudaDeviceName() { return ""; }

}  // namespace pt
#endif
