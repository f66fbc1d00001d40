// link_stage.h — binds and launches the kernels of kernels/link.cl (Huang et al. 2025 §4):
// hair linking (select, then propagate along the source strands' centre lines, which the
// groom's strand pass draws in between), the merge of linked pixels with the per-strand
// counts of the alpha fix, the alpha fix after shading and the orientation-aware
// anisotropic filter. The stage owns the parameter record, the per-pixel source choice,
// the source strands' bitmap, the hash table and the counters, all grow-only.
//
// The hash table holds one entry per source strand: at most the groom's strand count, so
// it is sized to twice that (load factor at most 1/2; Huang Eq. 14 sizes it from the hair's
// screen box, which bounds the same key count) unless FilterParams::linkTable says
// otherwise; a strand the full table cannot hold is counted and keeps alpha 1.
//
// The passes run over the groom's screen box (Params::box), each grown by the margin its
// kernel needs (link.cl has them and why): select and propagate box + 1, merge and the
// filter box, the alpha fix box + CLH_LINK_MAX_RADIUS. The result buffer finish() returns
// is then right inside the box only (outside it the whole-frame passes would leave 0):
// composite it over the box alone.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "clhair/scene.h"
#include "stages/clear_stage.h"
#include "stages/stage_inputs.h"

namespace clhair {

// What one groom's pass counted (LinkStage::counters).
struct LinkCounters {
  std::uint32_t selecting = 0;            // empty pixels that chose a source
  std::uint32_t filled = 0;               // pixels linking filled
  std::uint32_t strands = 0;              // strands in the hash table
  std::uint32_t turnedAway = 0;           // pixels whose strand found no room in the table
  std::array<std::uint32_t, 4> bounds{};  // hair pixels: min x, min y, max x, max y
};

class LinkStage {
 public:
  explicit LinkStage(Device::Impl& dev);
  struct Params {
    ViewTarget target;
    const cl::Buffer* groom = nullptr;  // ClhGroomGpu
    cl::Buffer* gbuffer = nullptr;      // `layers` layers, MSAA 1
    std::uint32_t strandIds = 0;        // identities run below this (the groom's strands)
    int layers = CLH_LAYER_LINKED + 1;  // CLH_LAYER_ID + 1 without linking
    // The groom's screen box: every pixel any of its G-buffer layers can hold (the default:
    // the whole target). Each kernel runs over it grown by what it reads (link.cl).
    PixelRect box;
  };
  // Uploads the settings, clears the bitmap, table and counters, and picks the sources.
  void select(const FilterParams& f, const Params& p, Profiler* profiler);
  const cl::Buffer& flags() const { return flags_; }
  std::uint32_t flagWords() const { return words_; }
  // After the curve pass: the walks, then the merge and the counts (also without linking,
  // for the bounds of the anisotropic filter: then only the merge's counting runs).
  void propagate(const Params& p, Profiler* profiler);
  void merge(const Params& p, bool linking, Profiler* profiler);
  // After shading: the alpha fix of `hair` into `out`, then (aniso) the filter of `out`
  // back into `hair`. Returns the buffer holding the result (premultiplied RGBA).
  cl::Buffer* finish(const Params& p, bool aniso, cl::Buffer& hair, cl::Buffer& out,
                     Profiler* profiler);
  LinkCounters counters();
  // The stage's own buffers (what a pass using it declares) and its counters
  // (CLH_LINK_COUNTERS uints: selecting, filled, strands, turned away, bounds).
  std::vector<const cl::Buffer*> buffers() const {
    return {&params_, &choice_, &flags_, &table_, &counters_};
  }
  const cl::Buffer& counterBuffer() const { return counters_; }

 private:
  Device::Impl& dev_;
  cl::Kernel& built(cl::Kernel& kernel, const char* name);  // `kernel`, built if not yet
  cl::Kernel select_, propagate_, merge_, alpha_, aniso_;
  ClearStage clear_;
  cl::Buffer params_, choice_, flags_, table_, counters_;
  std::size_t choiceCap_ = 0, flagsCap_ = 0, tableCap_ = 0;
  std::uint32_t words_ = 1, tableSize_ = 1;
  std::vector<unsigned char> paramsSent_;  // what params_ holds
};

}  // namespace clhair
