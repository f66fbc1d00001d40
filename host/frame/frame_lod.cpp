// frame_lod.cpp — see frame_lod.h.
#include "frame/frame_lod.h"

#include <algorithm>
#include <cstring>

#include "cl/buffers.h"

namespace clhair {

namespace {
std::size_t alignUp(std::size_t n, std::size_t a) { return (n + a - 1) / a * a; }
}  // namespace

BudgetRuleParams budgetRuleParams(const RenderOptions& options, const gpu::ClhViewGpu& view) {
  BudgetRuleParams r;
  r.screen = options.budgetRule != BudgetRule::Uniform;
  r.keepLow = options.budgetKeepLow;
  r.keepHigh = options.budgetKeepHigh;
  r.widenCap = options.budgetWidenCap;
  r.imageArea = static_cast<float>(view.width) * static_cast<float>(view.height);
  return r;
}

FrameLod::FrameLod(Device::Impl& dev) : dev_(dev), stage_(dev) {
  const cl_uint bits = clCall("querying the sub-buffer alignment",
                              [&] { return dev.device.getInfo<CL_DEVICE_MEM_BASE_ADDR_ALIGN>(); });
  align_ = std::max<std::size_t>(bits / 8, 64);
}

void FrameLod::bind(const std::vector<GroomDraw>& draws) {
  layout_.assign(draws.size(), gpu::ClhBudgetDraw{});
  std::vector<std::size_t> at(draws.size());
  std::size_t bytes = 0;
  for (std::size_t k = 0; k < draws.size(); ++k) {
    const std::uint32_t n = draws[k].state->records;
    gpu::ClhBudgetDraw& d = layout_[k];
    at[k] = bytes;
    d.records = n;
    d.records_at = static_cast<gpu::clh_u32>(bytes / sizeof(gpu::ClhLodRecord));
    bytes = alignUp(bytes + std::max<std::size_t>(n, 1) * sizeof(gpu::ClhLodRecord), align_);
    d.counts_at = static_cast<gpu::clh_u32>(bytes / sizeof(cl_uint));
    bytes = alignUp(bytes + gpu::clh_lod_counts_length(std::max<std::uint32_t>(n, 1)) * 4, align_);
    d.offsets_at = static_cast<gpu::clh_u32>(bytes / sizeof(cl_uint));
    bytes = alignUp(bytes + gpu::clh_lod_offsets_length(n) * 4, align_);
    d.kind = draws[k].groom->storedStrands() ? 1u : 0u;
    d.min_points = 3u;
  }
  if (bytes >= (std::size_t(1) << 32))
    throw Error("the LOD records of " + std::to_string(draws.size()) + " groom instances need " +
                std::to_string(bytes >> 20) + " MiB in one buffer; at most 4 GiB are supported");
  if (bytes > arenaBytes_ || !arena_()) {
    arenaBytes_ = std::max(bytes + bytes / 2, align_);
    arena_ = makeBuffer<std::uint8_t>(dev_, "LOD records of all grooms", arenaBytes_);
    ++generation_;
  }
  for (std::size_t k = 0; k < draws.size(); ++k) {
    GroomInstanceGpu& inst = *draws[k].state;
    if (inst.arenaGeneration == generation_ && inst.arenaAt == at[k]) continue;
    const gpu::ClhBudgetDraw& d = layout_[k];
    const std::uint32_t n = d.records;
    auto view = [&](std::size_t origin, std::size_t size) {
      cl_buffer_region region{origin, size};
      return clCall("creating a view of the LOD records", [&] {
        return arena_.createSubBuffer(CL_MEM_READ_WRITE, CL_BUFFER_CREATE_TYPE_REGION, &region);
      });
    };
    inst.lod = view(std::size_t(d.records_at) * sizeof(gpu::ClhLodRecord),
                    std::max<std::size_t>(n, 1) * sizeof(gpu::ClhLodRecord));
    inst.counts = view(std::size_t(d.counts_at) * 4,
                       gpu::clh_lod_counts_length(std::max<std::uint32_t>(n, 1)) * 4);
    inst.offsets = view(std::size_t(d.offsets_at) * 4, gpu::clh_lod_offsets_length(n) * 4);
    inst.arenaGeneration = generation_;
    inst.arenaAt = at[k];
  }
}

void FrameLod::enqueue(const std::vector<GroomDraw>& draws, const std::vector<char>& active,
                       const std::vector<char>& far, std::uint64_t budget, Profiler* profiler,
                       const BudgetRuleParams& rule) {
  const std::size_t D = draws.size();
  if (D == 0) return;
  for (std::size_t k = 0; k < D; ++k) {
    layout_[k].active = static_cast<gpu::clh_u32>(active[k]);
    layout_[k].far = far[k] ? 1u : 0u;
  }
  const cl_mem before = table_();
  ensureCapacity<gpu::ClhBudgetDraw>(dev_, table_, tableCap_, "groom draw table", D);
  if (table_() != before) tableSent_.clear();
  uploadChanged(dev_, table_, tableSent_, layout_.data(), D);
  gpu::ClhBudgetRule r{};
  r.rule = rule.screen ? CLH_BUDGET_RULE_SCREEN : CLH_BUDGET_RULE_UNIFORM;
  r.image_area = rule.imageArea;
  r.keep_lo = rule.keepLow;
  r.keep_hi = rule.keepHigh;
  r.room_lo = rule.roomLow;
  r.widen_cap = rule.widenCap;
  if (!rule_()) {
    rule_ = makeBuffer<gpu::ClhBudgetRule>(dev_, "segment budget rule", 1);
    ruleSent_.clear();
  }
  uploadChanged(dev_, rule_, ruleSent_, &r, 1);
  const std::size_t words = stateWords(D);
  ensureCapacity<cl_uint>(dev_, state_, stateCap_, "segment budget state", words);
  BudgetStage::Params p;
  p.table = &table_;
  p.draws = static_cast<std::uint32_t>(D);
  p.arena = &arena_;
  p.arenaBytes = arenaBytes_;
  p.budget = budget;
  p.rule = &rule_;
  p.state = &state_;
  p.stateWords = words;
  stage_.enqueue(p, profiler);
}

std::size_t FrameLod::stateWords(std::size_t draws) {
  return draws == 0 ? 0 : CLH_BUDGET_HEADER + CLH_BUDGET_DRAW_WORDS * draws;
}

FrameLod::Result FrameLod::read(std::size_t draws) {
  std::vector<std::uint32_t> s(stateWords(draws));
  readBack(dev_, "the segment budget's outcome", state_, s.data(), s.size());
  return decode(s, draws);
}

FrameLod::Result FrameLod::decode(const std::vector<std::uint32_t>& s, std::size_t draws) {
  Result r;
  if (draws == 0 || s.size() < stateWords(draws)) return r;
  auto f32 = [](std::uint32_t u) {
    float f;
    std::memcpy(&f, &u, 4);
    return f;
  };
  r.scale = f32(s[0]);
  r.over = s[1] != 0;
  r.lodSegments = std::uint64_t(s[3]) | (std::uint64_t(s[4]) << 32);
  r.level = f32(s[5]);
  r.claims = f32(s[6]);
  r.draw.resize(4 * draws);
  r.plan.resize(draws);
  for (std::size_t k = 0; k < draws; ++k) {
    const std::uint32_t* w = &s[CLH_BUDGET_HEADER + CLH_BUDGET_DRAW_WORDS * k];
    std::copy(w, w + 4, r.draw.begin() + 4 * static_cast<std::ptrdiff_t>(k));
    const bool halved = (w[3] & CLH_BUDGET_HALVED) != 0;
    DrawPlan& p = r.plan[k];
    p.request = halved ? w[5] : w[4];
    p.floor = halved ? w[7] : w[6];
    p.area = f32(w[8]);
    p.share = w[10];
    p.factor = f32(w[11]);
    p.claim = f32(w[12]);
  }
  return r;
}

}  // namespace clhair
