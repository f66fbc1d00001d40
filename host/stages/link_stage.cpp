// link_stage.cpp — see link_stage.h.
#include "stages/link_stage.h"

#include <algorithm>
#include <vector>

#include "cl/buffers.h"

namespace clhair {

LinkStage::LinkStage(Device::Impl& dev)
    : dev_(dev),
      clear_(dev),
      params_(makeBuffer<gpu::ClhLinkGpu>(dev, "hair linking parameters", 1)),
      counters_(makeBuffer<cl_uint>(dev, "hair linking counters", CLH_LINK_COUNTERS)) {}

// Each kernel is built on its first use: a frame that does not link (Lipp's filter, or no
// filter) builds no link program.
cl::Kernel& LinkStage::built(cl::Kernel& kernel, const char* name) {
  if (!kernel()) kernel = dev_.kernel("link.cl", name);
  return kernel;
}

namespace {
std::uint64_t gbufferBytes(const LinkStage::Params& p) {
  return std::uint64_t(p.target.pixels()) * std::uint64_t(p.layers) * sizeof(cl_ulong);
}

// The groom's screen box grown by `margin` pixels, within the target.
PixelRect boxOf(const LinkStage::Params& p, int margin) {
  return p.box.grown(margin).clipped(p.target.width, p.target.height);
}
}  // namespace

void LinkStage::select(const FilterParams& f, const Params& p, Profiler* profiler) {
  const std::size_t pixels = p.target.pixels();
  words_ = (p.strandIds + 31u) / 32u + 1u;
  words_ += words_ & 1u;  // whole 64-bit words for the clear
  const std::uint64_t wanted =
      f.linkTable > 0 ? std::uint64_t(f.linkTable) : std::uint64_t(p.strandIds) * 2u + 16u;
  tableSize_ = static_cast<std::uint32_t>(std::min<std::uint64_t>(wanted, 1u << 26));
  if (!choice_() || choiceCap_ < pixels) {
    // link_select writes every pixel's entry before link_propagate reads it. The host fills
    // it once anyway, for checkers that track initialised memory from host writes:
    // Oclgrind 21.10's --uninitialized creates a global buffer's shadow only when the host
    // writes it (and as large as that write), so kernel stores into a buffer the host never
    // wrote go untracked and link_propagate's reads of them were reported (DESIGN.md, "The
    // default filter")
    const std::vector<cl_uint> none(pixels, CLH_LINK_NONE);
    choice_ = makeBuffer<cl_uint>(dev_, "hair linking sources", pixels, none.data());
    choiceCap_ = pixels;
  }
  ensureCapacity<cl_uint>(dev_, flags_, flagsCap_, "hair linking strand bitmap", words_);
  ensureCapacity<cl_uint>(dev_, table_, tableCap_, "alpha fix hash table",
                          std::size_t(tableSize_) * 4u);
  gpu::ClhLinkGpu g{};
  g.align_threshold = f.linkThreshold;
  g.sigma_px = f.linkSigma;
  g.max_steps = static_cast<gpu::clh_u32>(std::max(f.link ? f.linkMaxSteps : 0, 0));
  g.table_size = tableSize_;
  g.alpha_fix = f.alphaFix ? 1u : 0u;
  g.aniso = f.aniso ? 1u : 0u;
  g.sigma_d = f.sigmaD;
  g.sigma_theta = f.sigmaTheta;
  g.sigma_c = f.sigmaCAniso;
  g.kernel_k = f.kernelK;
  g.strand_words = words_;
  uploadChanged(dev_, params_, paramsSent_, &g, 1);
  const cl_uint init[CLH_LINK_COUNTERS] = {0, 0, 0, 0, 0xFFFFFFFFu, 0xFFFFFFFFu, 0, 0};
  upload(dev_, counters_, init, CLH_LINK_COUNTERS);
  // cleared on the device (the table is 16 bytes per strand, too much to send every frame),
  // by kernels: checkers (Oclgrind) do not count clEnqueueFillBuffer as a write
  clear_.uints(flags_, words_, 0u, "link", profiler);
  clear_.uints(table_, std::size_t(tableSize_) * 4u, 0u, "link", profiler);
  if (!f.link) return;
  if (p.layers < int(CLH_LAYER_LINKED) + 1)
    throw Error("hair linking needs " + std::to_string(CLH_LAYER_LINKED + 1) +
                " G-buffer layers, not " + std::to_string(p.layers));
  const PixelRect box = boxOf(p, 1);  // an empty pixel's 3x3 neighbourhood
  KernelArgs(built(select_, "link_select"), "link")
      .buffer("groom", *p.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("link parameters", params_, sizeof(gpu::ClhLinkGpu))
      .buffer("G-buffer", *p.gbuffer, gbufferBytes(p))
      .buffer("sources", choice_, pixels * sizeof(cl_uint))
      .buffer("source strands", flags_, std::uint64_t(words_) * sizeof(cl_uint))
      .buffer("link counters", counters_, CLH_LINK_COUNTERS * sizeof(cl_uint))
      .value("box", box.arg());
  dispatchBox(dev_, select_, "link", box, profiler);
}

void LinkStage::propagate(const Params& p, Profiler* profiler) {
  const PixelRect box = boxOf(p, 1);  // the pixels select may have given a source
  KernelArgs(built(propagate_, "link_propagate"), "link")
      .buffer("groom", *p.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("link parameters", params_, sizeof(gpu::ClhLinkGpu))
      .buffer("G-buffer", *p.gbuffer, gbufferBytes(p))
      .buffer("sources", choice_, p.target.pixels() * sizeof(cl_uint))
      .value("box", box.arg());
  dispatchBox(dev_, propagate_, "link", box, profiler);
}

void LinkStage::merge(const Params& p, bool linking, Profiler* profiler) {
  const PixelRect box = boxOf(p, 0);
  KernelArgs(built(merge_, "link_merge"), "link")
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("link parameters", params_, sizeof(gpu::ClhLinkGpu))
      .buffer("G-buffer", *p.gbuffer, gbufferBytes(p))
      .buffer("source strands", flags_, std::uint64_t(words_) * sizeof(cl_uint))
      .buffer("hash table", table_, std::uint64_t(tableSize_) * 4 * sizeof(cl_uint))
      .buffer("link counters", counters_, CLH_LINK_COUNTERS * sizeof(cl_uint))
      .value("linking", static_cast<cl_uint>(linking ? 1 : 0))
      .value("box", box.arg());
  dispatchBox(dev_, merge_, "link", box, profiler);
}

cl::Buffer* LinkStage::finish(const Params& p, bool aniso, cl::Buffer& hair, cl::Buffer& out,
                              Profiler* profiler) {
  const std::uint64_t colourBytes = std::uint64_t(p.target.pixels()) * 4 * sizeof(float);
  // the alpha fix's output as far as the anisotropic filter reads it; the filter the box
  const PixelRect alphaBox = boxOf(p, CLH_LINK_MAX_RADIUS), box = boxOf(p, 0);
  KernelArgs(built(alpha_, "link_alpha"), "filter")
      .buffer("groom", *p.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("link parameters", params_, sizeof(gpu::ClhLinkGpu))
      .buffer("G-buffer", *p.gbuffer, gbufferBytes(p))
      .buffer("source strands", flags_, std::uint64_t(words_) * sizeof(cl_uint))
      .buffer("hash table", table_, std::uint64_t(tableSize_) * 4 * sizeof(cl_uint))
      .buffer("hair colour", hair, colourBytes)
      .buffer("alpha-fixed colour", out, colourBytes)
      .value("box", alphaBox.arg());
  dispatchBox(dev_, alpha_, "filter", alphaBox, profiler);
  if (!aniso) return &out;
  KernelArgs(built(aniso_, "link_aniso"), "filter")
      .buffer("groom", *p.groom, sizeof(gpu::ClhGroomGpu))
      .buffer("view", *p.target.view, sizeof(gpu::ClhViewGpu))
      .buffer("link parameters", params_, sizeof(gpu::ClhLinkGpu))
      .buffer("G-buffer", *p.gbuffer, gbufferBytes(p))
      .buffer("link counters", counters_, CLH_LINK_COUNTERS * sizeof(cl_uint))
      .buffer("alpha-fixed colour", out, colourBytes)
      .buffer("filtered colour", hair, colourBytes)
      .value("box", box.arg());
  dispatchBox(dev_, aniso_, "filter", box, profiler);
  return &hair;
}

LinkCounters LinkStage::counters() {
  cl_uint c[CLH_LINK_COUNTERS];
  readBack(dev_, "hair linking counters", counters_, c, CLH_LINK_COUNTERS);
  LinkCounters r;
  r.selecting = c[0];
  r.filled = c[1];
  r.strands = c[2];
  r.turnedAway = c[3];
  for (int k = 0; k < 4; ++k) r.bounds[k] = c[4 + k];
  return r;
}

}  // namespace clhair
