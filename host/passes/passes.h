// passes.h — the passes a frame is built from, one file per feature. Each function adds
// its pass (or one pass per groom) to the frame's graph: a setup that declares what it reads
// and writes and the kernels it launches, and an execute callback that enqueues the work
// with the renderer's stages. The handles of what a pass produces go into the FramePlan for
// the passes after it. renderer.cpp calls these in frame order, for a frame of one view or
// of several: a pass of one view (a ViewPlan argument) is added once per view it draws.
#pragma once

#include "frame/frame_plan.h"
#include "frame/pending_frame.h"
#include "graph/frame_graph.h"
#include "renderer_impl.h"

namespace clhair {

// A view's target as the stages take it: its record (the buffer of a pass's handle) and the
// frame's size.
inline ViewTarget viewTarget(const FramePlan& plan, const cl::Buffer& record) {
  return {&record, plan.scene.width, plan.scene.height};
}

// What a pass over groom `gp` in view `vp` reads of both: the view's record, the groom's
// record and the view's G-buffer (declared by readGroomInView, fetched by Resources).
struct GroomInView {
  FrameGraph::Handle view, groom, gbuffer;
};
inline GroomInView readGroomInView(FrameGraph::Setup& s, const ViewPlan& vp, const GroomPlan& gp) {
  return {s.read(vp.record), s.read(gp.params), s.read(vp.gbuffer)};
}

// scene_passes.cpp: the frame's shared resources, every view's and every groom's own,
// imported into the graph (the view and scene records are uploaded here, before any pass);
// the deep opacity maps when they must be built again; a view's opaque scene (and, for a
// given G-buffer, its depth read back to the source).
void importFrame(FrameGraph& g, Renderer::Impl& r, FramePlan& plan);
// The deep opacity maps when they are rebuilt: a first pass (totals, the camera's LOD caps),
// a pass per mapped light, a last pass for the slots' records (frame/shadow_maps.h).
void addShadowPasses(FrameGraph& g, Renderer::Impl& r, FramePlan& plan);
void addOpaquePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, ViewPlan& vp);

// lod_passes.cpp: each drawn groom's LOD pre-pass from the camera, then the segment budget
// over all of them.
void addLodPasses(FrameGraph& g, Renderer::Impl& r, FramePlan& plan);

// strand_passes.cpp: a groom's G-buffer clear and strand raster (or its given centre layer),
// and the capture of its raster inputs and layers (RenderOptions::captureGBuffer).
void addStrandPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp);
// The raster of groom `gp` into view `vp` (its record, depth and G-buffer and the raster
// counters from the pass's resources), sized as the plan's mode says: read-back mode reads
// the strand total here.
StrandRaster cameraRaster(Renderer::Impl& r, const FramePlan& plan, const GroomPlan& gp,
                          const ViewPlan& vp, const FrameGraph::Resources& res);
void addCapturePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp,
                    PendingFrame& out);

// view_strand_passes.cpp (a frame of several views): the groom's record in each view, its
// LOD from its first view in front, and its strands assembled once and drawn into every
// view's G-buffer (strands_raster_views; a strand file draws each view on its own, before
// that view's shading); after its last view, the record of its LOD view handed back to the
// instance.
void addViewsStrandPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp);
void addViewsRecordPass(FrameGraph& g, GroomPlan& gp);
// Before groom `gp` is shaded in view `vp`: its record for the view, or (when its strands
// could not be drawn into every view at once) its LOD and strands drawn in this view alone.
void declareViewDraw(FrameGraph::Setup& s, const FramePlan& plan, const GroomPlan& gp,
                     const ViewPlan& vp);
void drawInView(Renderer::Impl& r, const FramePlan& plan, GroomPlan& gp, const ViewPlan& vp,
                const FrameGraph::Resources& res);

// link_passes.cpp: Huang's hair linking over the groom's G-buffer (select, the sources'
// curve pass, propagate, merge).
void addLinkPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp);
// The linking stage's inputs for groom `gp` in the camera's view (a pass that declared the
// view's record and G-buffer and the groom's record).
LinkStage::Params linkParams(const FramePlan& plan, const GroomPlan& gp,
                             const FrameGraph::Resources& res);

// motion_pass.cpp: a deforming groom's strands at the previous frame, into its motion plane.
void addMotionPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp);

// shade_passes.cpp: deferred shading of the groom's centre layer in view `vp`, its filter
// (Lipp's, or Huang's alpha fix and anisotropic filter), and its composite over the view.
void addShadePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp, ViewPlan& vp);
// The shading pass's inputs for groom `gp`: the view's record, the groom's record, the
// G-buffer and the shaded hair are buffers of the pass's resources; the lights and maps, the
// groom's strand scan and its baked inputs come from their owners.
ShadeStage::Params shadeParams(Renderer::Impl& r, const FramePlan& plan, const GroomPlan& gp,
                               const cl::Buffer& view, const cl::Buffer& groom,
                               const cl::Buffer& gbuffer, cl::Buffer& hair);
void addFilterPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp, ViewPlan& vp);
void addCompositePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp,
                      ViewPlan& vp);

// point_passes.cpp: the groom shaded once per visible strand point (GroomPlan::points), in
// place of addShadePass: the points marked and ranked, their inputs written by the strand
// kernels' point pass, each shaded once, every sample resolved along its segment.
void addPointShadePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp);

// The AOV planes (AovStage::Planes in the same order), on the graph's blackboard under
// kAovPlanes once the AOV begin pass has created them.
struct AovHandles {
  FrameGraph::Handle lastDepth, owner, ownerMotion, alpha, hair, centreZ, tangent, strand;
  std::vector<FrameGraph::Handle> all() const {
    return {lastDepth, owner, ownerMotion, alpha, hair, centreZ, tangent, strand};
  }
};
inline constexpr const char* kAovPlanes = "AOV planes";

// aov_passes.cpp: the layers for compositing, started after the opaque scene and folded in
// after each groom's composite, on the device.
void addAovBeginPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, PendingFrame& out);
void addAovGroomPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp);

// cryptomatte_pass.cpp: the groom's hair folded into the Cryptomatte layers after its
// composite (RenderOptions::cryptomatte); the last groom drawn reads them back into `out`.
void addCryptomattePass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp,
                        PendingFrame& out);

// readback_pass.cpp: every view's result, the frame's statistics and AOV planes read back
// without blocking into `out`, which completes with the marker after them.
void addReadBackPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, PendingFrame& out);

}  // namespace clhair
