// motion_pass.cpp — a deforming groom's motion (passes.h): its strands again at the previous
// frame, after hair linking (a linked pixel's motion is that of the strand linked into it)
// and before the composite changes the depth they were tested against; resolved on the word
// the composite takes the pixel's depth from, so Z and motion describe one fragment. The
// previous camera's intrinsics keep this frame's sub-pixel shift.
#include "cl/buffers.h"
#include "passes/passes.h"
#include "stages/view_math.h"

namespace clhair {

void addMotionPass(FrameGraph& g, Renderer::Impl& r, FramePlan& plan, GroomPlan& gp) {
  struct Data {
    FrameGraph::Handle params, plane;
  };
  g.addPass<Data>(
      "motion " + std::to_string(gp.index),
      [&](FrameGraph::Setup& s, Data& d) {
        const ViewPlan& camera = plan.camera();
        s.reads({camera.record, camera.depth, camera.gbuffer, gp.tables, gp.params, gp.lod});
        s.readsWrites({plan.rasterCounters});
        d.params = s.write(plan.motionParams);
        d.plane = s.write(gp.motionPlane);
        s.kernel("clear_words").kernel(gp.draw.groom->kernels().motion);
        if (plan.mode == DispatchMode::ReadBack)
          s.hostWait("the groom's strand total for the motion pass (--dispatch readback)");
      },
      [&](const Data& d, const FrameGraph::Resources& res) {
        const Scene& before = *plan.options.previous;
        const gpu::ClhViewGpu pv = makeView(before.camera, plan.scene.width, plan.scene.height);
        const gpu::ClhViewGpu still =
            makeView(plan.scene.camera, plan.scene.width, plan.scene.height);
        gpu::ClhMotionGpu m{};
        m.fx = pv.fx;
        m.fy = pv.fy;
        m.cx = pv.cx + (plan.camera().view.cx - still.cx);
        m.cy = pv.cy + (plan.camera().view.cy - still.cy);
        storeMat34(m.prev_obj_to_view,
                   worldToView(before.camera) * before.grooms[gp.index].transform);
        m.depth_layers = gp.depthLayers;
        cl::Buffer& params = res[d.params];
        upload(r.dev, params, &m, 1);
        cl::Buffer& plane = res[d.plane];
        r.target.clearWords(plane, plan.pixels, &r.profiler);
        MotionDraw mp;
        mp.params = &params;
        mp.motion = &plane;
        // a groom that cannot give its motion leaves the plane empty: rigid motion is kept
        gp.draw.groom->motion(*gp.draw.state, before.grooms[gp.index], mp,
                              cameraRaster(r, plan, gp, plan.camera(), res), &r.profiler);
      });
}

}  // namespace clhair
