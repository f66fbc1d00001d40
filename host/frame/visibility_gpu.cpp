// visibility_gpu.cpp — see visibility_gpu.h.
#include "frame/visibility_gpu.h"

#include <glm/matrix.hpp>

#include "cl/buffers.h"
#include "clhair/gpu_types.h"
#include "clhair/visibility_sh.h"

namespace clhair {

VisibilityGpu::VisibilityGpu(Device::Impl& dev) : dev_(dev) {
  const cl_float4 zero{};
  none_ = makeBuffer<cl_float4>(dev, "no baked visibility", 1, &zero);
}

void VisibilityGpu::prepare(std::size_t k, const GroomInstance& gi, bool enabled, bool lodAggregate,
                            bool multipleScattering, const AoField* ao) {
  while (records_.size() <= k) {
    records_.push_back(makeBuffer<gpu::ClhVisibilityGpu>(dev_, "baked visibility record", 1));
    fields_.push_back(none_);
    sent_.emplace_back();
  }
  if (inputs_.size() <= k) inputs_.resize(k + 1);
  gpu::ClhVisibilityGpu v{};
  v.shade_flags = (lodAggregate ? CLH_SHADE_AGGREGATE : 0u) |
                  (multipleScattering ? 0u : CLH_SHADE_SINGLE_SCATTER);
  Inputs in{&records_[k], &none_, 1u, &none_, 1u};
  const glm::mat4 inv = glm::inverse(gi.transform);
  fields_[k] = none_;
  if (ao) {
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) v.world_to_obj[4 * row + col] = inv[col][row];
    for (int i = 0; i < 4; ++i) {
      v.ao_lo[i] = ao->lo.s[i];
      v.ao_dims[i] = i < 3 ? ao->dims.s[i] : ao->flags;
    }
    fields_[k] = ao->values;
    in.aoField = &fields_[k];
    in.aoFieldVoxels = ao->floats();
  }
  if (enabled && gi.visibility) {
    auto it = tables_.find(gi.visibility.get());
    if (it == tables_.end()) {
      const std::vector<float>& sh = gi.visibility->sh;
      if (sh.size() != std::size_t(CLH_VIS_CELLS) * CLH_VIS_COEFFS)
        throw Error("groom \"" + gi.name + "\": its baked visibility holds " +
                    std::to_string(sh.size()) + " coefficients, need " +
                    std::to_string(std::size_t(CLH_VIS_CELLS) * CLH_VIS_COEFFS));
      cl::Buffer b = makeBuffer<cl_float4>(dev_, "baked visibility", CLH_VIS_CELLS,
                                           reinterpret_cast<const cl_float4*>(sh.data()));
      it = tables_.emplace(gi.visibility.get(), std::make_pair(gi.visibility, b)).first;
    }
    in.table = &it->second.second;
    in.cells = static_cast<std::uint32_t>(CLH_VIS_CELLS);
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 4; ++col) v.world_to_obj[4 * row + col] = inv[col][row];
    v.absorption = gi.visibilityAbsorption;
    v.cells = CLH_VIS_CELLS;
    v.enabled = 1;
  }
  uploadChanged(dev_, records_[k], sent_[k], &v, 1);
  inputs_[k] = in;
}

std::vector<const cl::Buffer*> VisibilityGpu::buffers() const {
  std::vector<const cl::Buffer*> b = {&none_};
  for (const cl::Buffer& r : records_) b.push_back(&r);
  for (std::size_t k = 0; k < fields_.size(); ++k) {  // each field once
    bool seen = fields_[k]() == none_();
    for (std::size_t j = 0; j < k && !seen; ++j) seen = fields_[j]() == fields_[k]();
    if (!seen) b.push_back(&fields_[k]);
  }
  for (const auto& [bake, table] : tables_) b.push_back(&table.second);
  return b;
}

}  // namespace clhair
