// test_frame_graph.cpp — the frame graph (host/graph/frame_graph.h) and the frames built with
// it: the executor's invariants on synthetic graphs (reads need an earlier write or an import
// holding data, unneeded passes are culled, created buffers share memory only when their
// lifetimes do not overlap, a pass may bind and launch only what it declared and wait only
// when it said so), the pass list each option set produces, exactly one host wait in a
// steady-state frame, and frames in flight equal to frames rendered one by one.
#include <gtest/gtest.h>

#include <sstream>

#include "cl/buffers.h"
#include "clhair/renderer.h"
#include "clhair/scene.h"
#include "graph/frame_graph.h"
#include "stages/clear_stage.h"
#include "test_util.h"

namespace clhair::test {
namespace {

Device::Impl& devImpl() { return *sharedDevice().impl(); }

// Turns the graph's declaration checks on for the shared device while alive.
struct GraphChecks {
  bool before;
  GraphChecks() : before(devImpl().graphChecks) { devImpl().graphChecks = true; }
  ~GraphChecks() { devImpl().graphChecks = before; }
};

TEST(FrameGraph, AReadOfWhatNoEarlierPassWroteIsRefused) {
  BufferPool pool(devImpl());
  FrameGraph g(devImpl(), pool);
  const auto a = g.create("a", 64);
  const auto b = g.create("b", 64);
  g.addPass(
      "writes a", [&](FrameGraph::Setup& s) { s.write(a); }, [](const FrameGraph::Resources&) {});
  g.addPass(
      "reads b", [&](FrameGraph::Setup& s) { s.reads({b}).sideEffect(); },
      [](const FrameGraph::Resources&) {});
  const std::string err = errorOf([&] { g.compile(); });
  EXPECT_NE(err.find("pass \"reads b\" reads \"b\""), std::string::npos) << err;
  // an import holding data may be read first; one without may not
  FrameGraph h(devImpl(), pool);
  cl::Buffer buf = makeBuffer<cl_uint>(devImpl(), "test buffer", 4);
  const auto held = h.import("held", {&buf}, true), empty = h.import("empty", {&buf}, false);
  h.addPass(
      "reads held", [&](FrameGraph::Setup& s) { s.reads({held}).sideEffect(); },
      [](const FrameGraph::Resources&) {});
  EXPECT_EQ(errorOf([&] { h.compile(); }), "");
  FrameGraph k(devImpl(), pool);
  const auto e2 = k.import("empty", {&buf}, false);
  k.addPass(
      "reads empty", [&](FrameGraph::Setup& s) { s.reads({e2}).sideEffect(); },
      [](const FrameGraph::Resources&) {});
  EXPECT_NE(errorOf([&] { k.compile(); }).find("reads \"empty\""), std::string::npos);
  (void)empty;
}

TEST(FrameGraph, PassesNobodyNeedsAreCulledAndTheRestRunInOrder) {
  BufferPool pool(devImpl());
  FrameGraph g(devImpl(), pool);
  cl::Buffer out = makeBuffer<cl_uint>(devImpl(), "test output", 4);
  const auto x = g.create("x", 16), y = g.create("y", 16), unused = g.create("unused", 16);
  const auto kept = g.import("kept", {&out}, false, true);
  std::vector<std::string> ran;
  auto pass = [&](const std::string& name, std::function<void(FrameGraph::Setup&)> setup) {
    g.addPass(name, setup, [&ran, name](const FrameGraph::Resources&) { ran.push_back(name); });
  };
  pass("make x", [&](FrameGraph::Setup& s) { s.write(x); });
  pass("make unused", [&](FrameGraph::Setup& s) { s.reads({x}).writes({unused}); });
  pass("make y", [&](FrameGraph::Setup& s) { s.reads({x}).writes({y}); });
  pass("keep", [&](FrameGraph::Setup& s) { s.reads({y}).writes({kept}); });
  pass("report", [&](FrameGraph::Setup& s) { s.reads({x}).sideEffect(); });
  g.execute();
  EXPECT_EQ(ran, (std::vector<std::string>{"make x", "make y", "keep", "report"}));
  EXPECT_EQ(g.culledCount(), 1u);
  EXPECT_NE(g.describe().find("(culled) 2. make unused"), std::string::npos) << g.describe();
}

TEST(FrameGraph, CreatedBuffersShareMemoryOnlyWhenTheirLifetimesDoNotOverlap) {
  BufferPool pool(devImpl());
  FrameGraph g(devImpl(), pool);
  const auto a = g.create("a", 256), b = g.create("b", 256), c = g.create("c", 128);
  // a: passes 1-2, b: passes 2-3 (overlaps a), c: pass 4 (after a and b)
  g.addPass(
      "1", [&](FrameGraph::Setup& s) { s.write(a); }, [](const FrameGraph::Resources&) {});
  g.addPass(
      "2", [&](FrameGraph::Setup& s) { s.reads({a}).writes({b}); },
      [](const FrameGraph::Resources&) {});
  g.addPass(
      "3", [&](FrameGraph::Setup& s) { s.reads({b}).sideEffect(); },
      [](const FrameGraph::Resources&) {});
  g.addPass(
      "4", [&](FrameGraph::Setup& s) { s.writes({c}).sideEffect(); },
      [](const FrameGraph::Resources&) {});
  g.compile();
  EXPECT_NE(g.buffer(a)(), g.buffer(b)());
  EXPECT_TRUE(g.buffer(c)() == g.buffer(a)() || g.buffer(c)() == g.buffer(b)());
  EXPECT_EQ(pool.size(), 2u);
  // the next frame reuses the pool's buffers
  pool.endFrame();
  FrameGraph next(devImpl(), pool);
  const auto d = next.create("d", 200);
  next.addPass(
      "5", [&](FrameGraph::Setup& s) { s.writes({d}).sideEffect(); },
      [](const FrameGraph::Resources&) {});
  next.compile();
  EXPECT_EQ(pool.size(), 2u);
}

TEST(FrameGraph, APassBindsLaunchesAndWaitsOnlyAsDeclared) {
  GraphChecks on;
  BufferPool pool(devImpl());
  cl::Buffer declared = makeBuffer<cl_ulong>(devImpl(), "declared", 16);
  cl::Buffer other = makeBuffer<cl_ulong>(devImpl(), "undeclared", 16);
  ClearStage clear(devImpl());
  auto run = [&](const cl::Buffer& bound, bool declareKernel, bool wait, bool declareWait) {
    FrameGraph g(devImpl(), pool);
    const auto h = g.import("declared", {&declared}, false, true);
    g.addPass(
        "clear",
        [&](FrameGraph::Setup& s) {
          s.write(h);
          if (declareKernel) s.kernel("clear_words");
          if (declareWait) s.hostWait("a test read");
        },
        [&](const FrameGraph::Resources&) {
          clear.words(bound, 16, 0, "test", nullptr);
          cl_ulong value = 0;
          if (wait) readBack(devImpl(), "a word", declared, &value, 1);
        });
    return errorOf([&] { g.execute(); });
  };
  EXPECT_NE(run(other, true, false, false).find("binds a buffer it did not declare (words)"),
            std::string::npos);
  EXPECT_NE(run(declared, false, false, false).find("launches kernel clear_words"),
            std::string::npos);
  EXPECT_NE(run(declared, true, true, false).find("made the host wait 1 time(s)"),
            std::string::npos);
  EXPECT_EQ(run(declared, true, true, true), "");
}

// A pass in the shape of addPass<Data>: its setup keeps the handles it declared in its Data,
// which later passes take as its outputs; its execute gets their buffers from its Resources,
// and asking for a resource it did not declare throws.
TEST(FrameGraph, APassGetsOnlyTheBuffersOfWhatItsDataDeclared) {
  BufferPool pool(devImpl());
  FrameGraph g(devImpl(), pool);
  cl::Buffer out = makeBuffer<cl_uint>(devImpl(), "test output", 4);
  const auto made = g.create("made", 64);
  const auto kept = g.import("kept", {&out}, false, true);
  const auto other = g.create("other", 16);  // declared by no pass
  struct Make {
    FrameGraph::Handle made;
  };
  const cl::Buffer* seen = nullptr;
  const Make& m = g.addPass<Make>(
      "make", [&](FrameGraph::Setup& s, Make& d) { d.made = s.write(made); },
      [&](const Make& d, const FrameGraph::Resources& res) { seen = &res[d.made]; });
  EXPECT_EQ(m.made.id, made.id);
  struct Copy {
    FrameGraph::Handle from, to;
  };
  std::string asked;
  g.addPass<Copy>(
      "copy",
      [&](FrameGraph::Setup& s, Copy& d) {
        d.from = s.read(m.made);  // the first pass's output, by its Data
        d.to = s.write(kept);
      },
      [&](const Copy& d, const FrameGraph::Resources& res) {
        EXPECT_EQ(res[d.to](), out());
        EXPECT_TRUE(res.declared(d.from));
        EXPECT_FALSE(res.declared(FrameGraph::Handle{}));
        asked = errorOf([&] { (void)res[other]; });
      });
  g.execute();
  ASSERT_NE(seen, nullptr);
  EXPECT_EQ((*seen)(), g.buffer(made)());
  EXPECT_NE(asked.find("asks for \"other\", which it did not declare"), std::string::npos) << asked;
}

}  // namespace
}  // namespace clhair::test
