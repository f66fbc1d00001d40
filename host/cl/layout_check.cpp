// layout_check.cpp — compile-time pins of the host/device struct layouts of gpu_types.h.
// The device side reports the same sizes through selftest_layout (tests/test_layout.cpp).
#include <cstddef>

#include "clhair/gpu_types.h"

namespace clhair::gpu {

static_assert(sizeof(ClhMeshVertex) == 64, "ClhMeshVertex layout");
static_assert(sizeof(ClhBundle) == 64, "ClhBundle layout");
static_assert(offsetof(ClhBundle, uv) == 32, "ClhBundle uv offset");
static_assert(sizeof(ClhGroomGpu) == 304, "ClhGroomGpu layout");
static_assert(sizeof(ClhChildrenGpu) == 32, "ClhChildrenGpu layout");
static_assert(offsetof(ClhGroomGpu, bundle_count) == 96, "ClhGroomGpu counts offset");
static_assert(offsetof(ClhGroomGpu, clump_strength) == 160, "ClhGroomGpu styling offset");
static_assert(offsetof(ClhGroomGpu, root_color) == 208, "ClhGroomGpu colour offset");
static_assert(sizeof(ClhViewGpu) == 144, "ClhViewGpu layout");
static_assert(sizeof(ClhMotionGpu) == 80, "ClhMotionGpu layout");
static_assert(sizeof(ClhLightGpu) == 32, "ClhLightGpu layout");
static_assert(sizeof(ClhSphereGpu) == 32, "ClhSphereGpu layout");
static_assert(sizeof(ClhPlaneGpu) == 32, "ClhPlaneGpu layout");
static_assert(sizeof(ClhSceneGpu) == 64, "ClhSceneGpu layout");
static_assert(sizeof(ClhFilterGpu) == 32, "ClhFilterGpu layout");
static_assert(sizeof(ClhLinkGpu) == 48, "ClhLinkGpu layout");
static_assert(sizeof(ClhShadowGpu) == 160, "ClhShadowGpu layout");
static_assert(sizeof(ClhLodRecord) == 16, "ClhLodRecord layout");
static_assert(sizeof(ClhVisibilityGpu) == 96, "ClhVisibilityGpu layout");
static_assert(offsetof(ClhLodRecord, strands) == 0 && offsetof(ClhLodRecord, control_points) == 4 &&
                  offsetof(ClhLodRecord, coverage) == 8 && offsetof(ClhLodRecord, gamma) == 12,
              "ClhLodRecord member offsets (the bit table in gpu_types.h)");
static_assert(sizeof(ClhBudgetDraw) == 32, "ClhBudgetDraw layout");
static_assert(sizeof(ClhBudgetRule) == 32, "ClhBudgetRule layout");

}  // namespace clhair::gpu
