// The media stages (src/integrator/media_pass_impl.h) on the CPU backend.
#include "cpu_backend/cpu_backend.h"
#include "src/integrator/media_pass_impl.h"

namespace pt {

template class MediaPass<CpuBackend>;

}  // namespace pt
