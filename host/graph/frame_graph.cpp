// frame_graph.cpp — see frame_graph.h.
#include "graph/frame_graph.h"

#include <algorithm>
#include <set>
#include <sstream>

#include "cl/buffers.h"
#include "cl/dispatch.h"

namespace clhair {

std::size_t BufferPool::acquire(std::size_t bytes, const std::vector<bool>& busy,
                                const std::string& what) {
  std::size_t best = entries_.size();
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if ((i < busy.size() && busy[i]) || entries_[i].bytes < bytes) continue;
    if (best == entries_.size() || entries_[i].bytes < entries_[best].bytes) best = i;
  }
  if (best == entries_.size()) {
    Entry e;
    e.buffer = makeBuffer<std::uint8_t>(dev_, what, bytes);
    e.bytes = std::max<std::size_t>(bytes, 1);
    entries_.push_back(std::move(e));
  }
  entries_[best].used = true;
  entries_[best].idle = 0;
  return best;
}

void BufferPool::endFrame(int frames) {
  for (Entry& e : entries_) {
    e.idle = e.used ? 0 : e.idle + 1;
    e.used = false;
  }
  // released only from the end, so the indices of the buffers kept stay valid
  while (!entries_.empty() && entries_.back().idle >= frames) entries_.pop_back();
}

std::uint64_t BufferPool::bytes() const {
  std::uint64_t sum = 0;
  for (const Entry& e : entries_) sum += e.bytes;
  return sum;
}

FrameGraph::Handle FrameGraph::import(std::string name, std::vector<const cl::Buffer*> buffers,
                                      bool contents, bool keep) {
  Resource r;
  r.name = std::move(name);
  r.imported = std::move(buffers);
  r.contents = contents;
  r.keep = keep;
  resources_.push_back(std::move(r));
  return Handle{static_cast<std::uint32_t>(resources_.size() - 1)};
}

FrameGraph::Handle FrameGraph::create(std::string name, std::size_t bytes) {
  Resource r;
  r.name = std::move(name);
  r.bytes = bytes;
  r.created = true;
  resources_.push_back(std::move(r));
  return Handle{static_cast<std::uint32_t>(resources_.size() - 1)};
}

cl::Buffer& FrameGraph::buffer(Handle h) {
  Resource& r = resources_.at(h.id);
  if (r.created) {
    if (!compiled_) throw Error("frame graph: buffer \"" + r.name + "\" asked for before compile");
    return pool_.buffer(r.poolSlot);
  }
  if (r.imported.empty() || !r.imported[0])
    throw Error("frame graph: resource \"" + r.name + "\" has no buffer");
  return const_cast<cl::Buffer&>(*r.imported[0]);
}

FrameGraph::Handle FrameGraph::Setup::read(Handle h) {
  if (!h) throw Error("frame graph: pass \"" + g_.passes_[pass_].name + "\" reads no resource");
  g_.passes_[pass_].reads.push_back(h.id);
  return h;
}

FrameGraph::Handle FrameGraph::Setup::write(Handle h) {
  if (!h) throw Error("frame graph: pass \"" + g_.passes_[pass_].name + "\" writes no resource");
  g_.passes_[pass_].writes.push_back(h.id);
  return h;
}

FrameGraph::Handle FrameGraph::Setup::readWrite(Handle h) {
  read(h);
  return write(h);
}

FrameGraph::Setup& FrameGraph::Setup::reads(std::initializer_list<Handle> hs) {
  for (const Handle h : hs) read(h);
  return *this;
}

FrameGraph::Setup& FrameGraph::Setup::writes(std::initializer_list<Handle> hs) {
  for (const Handle h : hs) write(h);
  return *this;
}

FrameGraph::Setup& FrameGraph::Setup::readsWrites(std::initializer_list<Handle> hs) {
  for (const Handle h : hs) readWrite(h);
  return *this;
}

bool FrameGraph::Resources::declared(Handle h) const {
  const Pass& p = g_.passes_.at(pass_);
  const auto in = [&](const std::vector<std::uint32_t>& ids) {
    return std::find(ids.begin(), ids.end(), h.id) != ids.end();
  };
  return h && (in(p.reads) || in(p.writes));
}

cl::Buffer& FrameGraph::Resources::operator[](Handle h) const {
  if (!declared(h))
    throw Error("frame graph: pass \"" + g_.passes_.at(pass_).name + "\" asks for " +
                (h ? "\"" + g_.name(h) + "\", which it did not declare" : "no resource"));
  return g_.buffer(h);
}

FrameGraph::Setup& FrameGraph::Setup::kernel(const std::string& name) {
  auto& k = g_.passes_[pass_].kernels;
  if (std::find(k.begin(), k.end(), name) == k.end()) k.push_back(name);
  return *this;
}

FrameGraph::Setup& FrameGraph::Setup::hostWait(const std::string& why) {
  g_.passes_[pass_].waits.push_back(why);
  return *this;
}

FrameGraph::Setup& FrameGraph::Setup::sideEffect() {
  g_.passes_[pass_].sideEffect = true;
  return *this;
}

void FrameGraph::addPass(const std::string& name, const std::function<void(Setup&)>& setup,
                         std::function<void(const Resources&)> run) {
  if (compiled_) throw Error("frame graph: pass \"" + name + "\" added after compile");
  Pass p;
  p.name = name;
  p.run = std::move(run);
  passes_.push_back(std::move(p));
  Setup s(*this, passes_.size() - 1);
  setup(s);
}

void FrameGraph::check(bool ok, const std::string& what) const {
  if (!ok) throw Error("frame graph: " + what);
}

void FrameGraph::compile() {
  const std::size_t R = resources_.size(), P = passes_.size();
  // every read follows a write of this frame or an import holding contents
  std::vector<bool> written(R, false);
  for (std::size_t r = 0; r < R; ++r) written[r] = resources_[r].contents;
  for (const Pass& p : passes_) {
    for (std::uint32_t r : p.reads)
      check(written[r], "pass \"" + p.name + "\" reads \"" + resources_[r].name +
                            "\", which no earlier pass wrote and the host did not provide");
    for (std::uint32_t r : p.writes) written[r] = true;
  }
  // culling, from the last pass back
  std::vector<bool> needed(R, false);
  for (std::size_t r = 0; r < R; ++r) needed[r] = resources_[r].keep;
  for (std::size_t i = P; i-- > 0;) {
    Pass& p = passes_[i];
    bool live = p.sideEffect;
    for (std::uint32_t r : p.writes) live = live || needed[r];
    p.culled = !live;
    if (live)
      for (std::uint32_t r : p.reads) needed[r] = true;
  }
  // lifetimes of created resources over the passes that run, then pool slots: a slot is
  // shared by resources whose lifetimes do not overlap
  std::vector<std::size_t> first(R, P), last(R, 0);
  for (std::size_t i = 0; i < P; ++i) {
    if (passes_[i].culled) continue;
    for (const auto* list : {&passes_[i].reads, &passes_[i].writes})
      for (std::uint32_t r : *list) {
        first[r] = std::min(first[r], i);
        last[r] = std::max(last[r], i);
      }
  }
  std::vector<std::uint32_t> order;
  for (std::uint32_t r = 0; r < R; ++r)
    if (resources_[r].created && first[r] < P) order.push_back(r);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return first[a] != first[b] ? first[a] < first[b] : a < b;
  });
  std::vector<std::size_t> slotFreeAfter;  // per pool slot: last pass of its current holder
  for (std::uint32_t r : order) {
    std::vector<bool> busy(pool_.size(), false);
    for (std::size_t s = 0; s < slotFreeAfter.size(); ++s)
      busy[s] = slotFreeAfter[s] != ~std::size_t(0) && slotFreeAfter[s] >= first[r];
    const std::size_t slot = pool_.acquire(resources_[r].bytes, busy, resources_[r].name);
    if (slotFreeAfter.size() <= slot) slotFreeAfter.resize(slot + 1, ~std::size_t(0));
    slotFreeAfter[slot] = last[r];
    resources_[r].poolSlot = slot;
  }
  compiled_ = true;
}

// Checks the buffers and kernels of one pass against its declarations.
class FrameGraph::Audit : public LaunchAudit {
 public:
  Audit(FrameGraph& g, const Pass& p) : g_(g), p_(p) { scan(); }
  void bound(const cl::Buffer& b, const char* argument) override {
    if (covered(b)) return;
    scan();  // the pass may have made a declared buffer since it started (grow-only buffers)
    if (covered(b)) return;
    throw Error("frame graph: pass \"" + p_.name + "\" binds a buffer it did not declare (" +
                argument + ")");
  }
  void launched(const std::string& kernel) override {
    if (std::find(p_.kernels.begin(), p_.kernels.end(), kernel) == p_.kernels.end())
      throw Error("frame graph: pass \"" + p_.name + "\" launches kernel " + kernel +
                  ", which it did not declare");
  }

 private:
  static cl_mem parentOf(const cl::Buffer& b) {
    return clCall("reading a buffer's parent",
                  [&] { return b.getInfo<CL_MEM_ASSOCIATED_MEMOBJECT>(); })();
  }
  // The declared buffers as they are now.
  void scan() {
    mems_.clear();
    parents_.clear();
    for (const auto* list : {&p_.reads, &p_.writes})
      for (std::uint32_t r : *list) {
        const Resource& res = g_.resources_[r];
        if (res.created) {
          add(g_.pool_.buffer(res.poolSlot));
          continue;
        }
        for (const cl::Buffer* b : res.imported)
          if (b && (*b)()) add(*b);
      }
  }
  bool covered(const cl::Buffer& b) const {
    if (mems_.count(b())) return true;
    const cl_mem parent = parentOf(b);
    if (parent && mems_.count(parent)) return true;  // a part of a declared buffer
    return parents_.count(b()) > 0;                  // the whole of declared parts
  }
  void add(const cl::Buffer& b) {
    mems_.insert(b());
    cl::Memory parent = clCall("reading a buffer's parent",
                               [&] { return b.getInfo<CL_MEM_ASSOCIATED_MEMOBJECT>(); });
    if (parent()) parents_.insert(parent());
  }
  FrameGraph& g_;
  const Pass& p_;
  std::set<cl_mem> mems_, parents_;
};

void FrameGraph::execute() {
  if (!compiled_) compile();
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    Pass& p = passes_[i];
    if (p.culled) continue;
    const std::uint64_t before = dev_.transfers.hostWaits();
    if (dev_.graphChecks) {
      Audit audit(*this, p);
      LaunchAudit*& current = LaunchAudit::current();
      LaunchAudit* outer = current;
      current = &audit;
      try {
        p.run(Resources(*this, i));
      } catch (...) {
        current = outer;
        throw;
      }
      current = outer;
    } else {
      p.run(Resources(*this, i));
    }
    p.waitsMade = dev_.transfers.hostWaits() - before;
    waits_ += p.waitsMade;
    if (dev_.graphChecks && p.waitsMade > 0 && p.waits.empty())
      throw Error("frame graph: pass \"" + p.name + "\" made the host wait " +
                  std::to_string(p.waitsMade) + " time(s) without declaring it");
  }
}

std::vector<std::string> FrameGraph::executedPasses() const {
  std::vector<std::string> out;
  for (const Pass& p : passes_)
    if (!p.culled) out.push_back(p.name);
  return out;
}

std::size_t FrameGraph::culledCount() const {
  return static_cast<std::size_t>(
      std::count_if(passes_.begin(), passes_.end(), [](const Pass& p) { return p.culled; }));
}

std::string FrameGraph::describe() const {
  std::ostringstream o;
  auto names = [&](const std::vector<std::uint32_t>& ids) {
    std::string s;
    for (std::uint32_t r : ids) s += (s.empty() ? "" : ", ") + resources_[r].name;
    return s.empty() ? std::string("-") : s;
  };
  std::size_t waits = 0;
  for (const Pass& p : passes_)
    if (!p.culled) waits += p.waits.size();
  o << "frame graph: " << passes_.size() - culledCount() << " passes (" << culledCount()
    << " culled), " << resources_.size() << " resources, " << waits
    << " declared host waits in passes + 1 at the frame's end\n";
  std::size_t n = 0;
  for (const Pass& p : passes_) {
    o << (p.culled ? "  (culled) " : "  ") << ++n << ". " << p.name << "\n";
    std::string k;
    for (const std::string& s : p.kernels) k += (k.empty() ? "" : ", ") + s;
    if (!k.empty()) o << "       kernels: " << k << "\n";
    o << "       reads:   " << names(p.reads) << "\n";
    o << "       writes:  " << names(p.writes) << "\n";
    for (const std::string& w : p.waits) o << "       host wait: " << w << "\n";
  }
  o << "buffers:\n";
  for (const Resource& r : resources_) {
    if (r.created) {
      o << "  " << r.name << ": created, " << r.bytes << " bytes";
      if (compiled_ && r.poolSlot != ~std::size_t(0)) o << ", pool buffer " << r.poolSlot;
      o << "\n";
    } else {
      o << "  " << r.name << ": imported" << (r.contents ? ", holds data" : "")
        << (r.keep ? ", kept after the frame" : "") << "\n";
    }
  }
  o << "host wait at the frame's end: the frame's read-back (Renderer::wait)\n";
  return o.str();
}

}  // namespace clhair
