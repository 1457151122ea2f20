// The backends by kind. Each is defined in its own file (backend.h lists them).
#include "backends/backend.h"

#include "core/check.h"

namespace mcpose::backends {

std::unique_ptr<Backend> MakeScalarReference();
std::unique_ptr<Backend> MakeFloatSimd();
std::unique_ptr<Backend> MakeFixedPoint();
std::unique_ptr<Backend> MakeFixedPointSimd();
std::unique_ptr<Backend> MakeHardware();
#if MCPOSE_HAVE_RTL
std::unique_ptr<Backend> MakeRtl();
#endif

std::unique_ptr<Backend> MakeBackend(RasterBackend kind) {
  std::unique_ptr<Backend> backend;
  switch (kind) {
    case RasterBackend::kScalar: backend = MakeScalarReference(); break;
    case RasterBackend::kFloatSimd: backend = MakeFloatSimd(); break;
    case RasterBackend::kFixedPoint: backend = MakeFixedPoint(); break;
    case RasterBackend::kSimd: backend = MakeFixedPointSimd(); break;
    case RasterBackend::kHardware: backend = MakeHardware(); break;
    case RasterBackend::kRtl:
#if MCPOSE_HAVE_RTL
      backend = MakeRtl();
#endif
      break;  // without Verilator the options refuse it (RtlBackendAvailable)
  }
  MCPOSE_CHECK(backend != nullptr);
  MCPOSE_CHECK(backend->kind() == kind);
  return backend;
}

}  // namespace mcpose::backends
