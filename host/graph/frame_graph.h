// frame_graph.h — a frame as a list of passes over named device buffers, and the small
// executor that runs it (after Filament's FrameGraph and Frostbite's frame graph).
//
// A pass is added with a name, a setup that declares the resources it reads and writes,
// the kernels it launches and the host waits it needs, and an execute callback that
// enqueues its work. Resources are either imported (buffers that live beyond the frame:
// the render target, a groom's tables, the shadow maps) or created by size, which the
// executor allocates from a pool that outlives frames and shares one buffer between
// created resources whose lifetimes in the frame do not overlap.
//
// compile() checks that every read follows a write of this frame or an import that holds
// contents, culls the passes whose writes nobody needs (a pass is needed when it has a side
// effect, writes a kept import or writes what a needed later pass reads), and allocates the
// created resources. execute() runs the passes in order and counts the host waits of each
// (Transfers::countWait); with checks on (Device::Impl::graphChecks) a pass that binds a
// buffer it did not declare, launches an undeclared kernel or waits on the host without
// declaring it throws. describe() prints the graph for `clhair render --passes`.
// Invariant: passes run in the order they were added (the queue is in order), which is a
// valid order by construction: a pass can only name resources that already exist.
#pragma once

#include <any>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cl/device_impl.h"

namespace clhair {

// Buffers for created resources, kept between frames and reused by size.
class BufferPool {
 public:
  explicit BufferPool(Device::Impl& dev) : dev_(dev) {}
  // Index of a pooled buffer of at least `bytes` not in `busy` (allocated when none fits).
  std::size_t acquire(std::size_t bytes, const std::vector<bool>& busy, const std::string& what);
  cl::Buffer& buffer(std::size_t i) { return entries_[i].buffer; }
  std::size_t size() const { return entries_.size(); }
  // After a frame: buffers no frame used for `frames` frames are released.
  void endFrame(int frames = 8);
  std::uint64_t bytes() const;

 private:
  struct Entry {
    cl::Buffer buffer;
    std::size_t bytes = 0;
    int idle = 0;
    bool used = false;
  };
  Device::Impl& dev_;
  std::vector<Entry> entries_;
};

// What passes leave by name for the passes after them (Filament's Blackboard): a feature's
// handles travel here, so that the frame's plan does not have to know the feature.
class Blackboard {
 public:
  template <class T>
  void put(const std::string& name, T value) {
    entries_[name] = std::move(value);
  }
  // The entry `name` as a T; null when there is none (or it is not a T).
  template <class T>
  T* get(const std::string& name) {
    auto it = entries_.find(name);
    return it == entries_.end() ? nullptr : std::any_cast<T>(&it->second);
  }

 private:
  std::map<std::string, std::any> entries_;
};

class FrameGraph {
 public:
  struct Handle {
    std::uint32_t id = ~0u;
    explicit operator bool() const { return id != ~0u; }
  };

  FrameGraph(Device::Impl& dev, BufferPool& pool) : dev_(dev), pool_(pool) {}
  FrameGraph(const FrameGraph&) = delete;
  FrameGraph& operator=(const FrameGraph&) = delete;

  // Buffers owned elsewhere, as one resource (for example a groom instance's LOD records,
  // counts and scan). `contents`: they hold data the frame may read before writing it (an
  // upload, an earlier frame). `keep`: their contents matter after the frame (the frame's
  // result, maps kept for later frames), so a pass writing them is never culled. The
  // pointers are dereferenced when passes run, so a buffer may be (re)made until then.
  Handle import(std::string name, std::vector<const cl::Buffer*> buffers, bool contents,
                bool keep = false);
  // A buffer of `bytes` bytes the executor allocates; no contents until a pass writes it.
  Handle create(std::string name, std::size_t bytes);
  // The buffer of a created resource (after compile()) or the first of an imported one (a
  // pass's execute asks its Resources instead, which check that the pass declared it).
  cl::Buffer& buffer(Handle h);
  const std::string& name(Handle h) const { return resources_.at(h.id).name; }

  class Setup {
   public:
    // The pass reads / writes / reads and writes `h`; returns it, for the pass's Data.
    Handle read(Handle h);
    Handle write(Handle h);
    Handle readWrite(Handle h);
    // The same for resources the pass's execute does not name (bound by their owners).
    Setup& reads(std::initializer_list<Handle> hs);
    Setup& writes(std::initializer_list<Handle> hs);
    Setup& readsWrites(std::initializer_list<Handle> hs);
    Setup& kernel(const std::string& name);
    // The pass makes the host wait for the device, and why (each wait it makes is counted).
    Setup& hostWait(const std::string& why);
    // Never culled: its effect is outside the graph (a read-back to the host).
    Setup& sideEffect();

   private:
    friend class FrameGraph;
    explicit Setup(FrameGraph& g, std::size_t pass) : g_(g), pass_(pass) {}
    FrameGraph& g_;
    std::size_t pass_;
  };

  // What a pass's execute reaches of the graph: the buffers of the resources its setup
  // declared.
  class Resources {
   public:
    // The buffer of `h` (a created resource's, or the first of an imported one's); throws
    // when the pass did not declare `h`.
    cl::Buffer& operator[](Handle h) const;
    // Whether the pass declared `h`.
    bool declared(Handle h) const;

   private:
    friend class FrameGraph;
    Resources(FrameGraph& g, std::size_t pass) : g_(g), pass_(pass) {}
    FrameGraph& g_;
    std::size_t pass_;
  };

  // A pass in the shape of Filament's addPass<Data>: `setup` declares what the pass reads,
  // writes, launches and waits for and keeps in its Data the handles its execute uses; `run`
  // enqueues the work with the buffers of those handles (Resources). Returns the Data, whose
  // handles later passes take as the pass's outputs; it lives as long as the graph.
  template <class Data>
  const Data& addPass(const std::string& name, const std::function<void(Setup&, Data&)>& setup,
                      std::function<void(const Data&, const Resources&)> run) {
    auto data = std::make_shared<Data>();
    addPass(
        name, [&](Setup& s) { setup(s, *data); },
        [data, run = std::move(run)](const Resources& res) { run(*data, res); });
    return *data;
  }
  // A pass whose execute uses no buffer of the graph by name.
  void addPass(const std::string& name, const std::function<void(Setup&)>& setup,
               std::function<void(const Resources&)> run);

  void compile();
  void execute();
  // The graph as text: passes in order (culled ones marked) with their kernels, reads and
  // writes and declared host waits, then the created buffers and what they share.
  std::string describe() const;

  Blackboard& blackboard() { return blackboard_; }

  // After execute(): the passes that ran, and the host waits they made.
  std::vector<std::string> executedPasses() const;
  std::uint64_t hostWaits() const { return waits_; }
  std::size_t passCount() const { return passes_.size(); }
  std::size_t culledCount() const;

 private:
  struct Resource {
    std::string name;
    std::vector<const cl::Buffer*> imported;
    std::size_t bytes = 0;
    bool created = false, contents = false, keep = false;
    std::size_t poolSlot = ~std::size_t(0);
  };
  struct Pass {
    std::string name;
    std::vector<std::uint32_t> reads, writes;
    std::vector<std::string> kernels, waits;
    bool sideEffect = false, culled = false;
    std::function<void(const Resources&)> run;
    std::uint64_t waitsMade = 0;
  };
  class Audit;
  void check(bool ok, const std::string& what) const;

  Device::Impl& dev_;
  BufferPool& pool_;
  std::vector<Resource> resources_;
  std::vector<Pass> passes_;
  bool compiled_ = false;
  std::uint64_t waits_ = 0;
  Blackboard blackboard_;
};

}  // namespace clhair
