// lod_passes.cpp — each drawn groom's LOD pre-pass from the camera, then the segment budget
// over all of them on the device, shared out by the options' rule (passes.h, frame_lod.h).
// The pre-pass also writes the groom's record for the camera (GroomGpu::prepare): the shadow
// pass before it wrote the light's.
#include "passes/passes.h"

namespace clhair {

void addLodPasses(FrameGraph& g, Renderer::Impl& r, FramePlan& plan) {
  for (GroomPlan& gp : plan.grooms) {
    if (!gp.active) continue;
    struct Data {
      FrameGraph::Handle view;
    };
    g.addPass<Data>(
        "lod " + std::to_string(gp.index),
        [&](FrameGraph::Setup& s, Data& d) {
          d.view = s.read(plan.camera().record);
          s.reads({gp.tables}).writes({gp.params, gp.lod});
          s.kernel(gp.draw.groom->kernels().lod).kernel("scan_bundles");
        },
        [&](const Data& data, const FrameGraph::Resources& res) {
          const GroomDraw& d = gp.draw;
          d.groom->useAo(plan.options.ambientOcclusion);
          // a faint strand file is widened where its hair is filtered (io/faint_groom.h)
          ViewDraw pass = plan.camera().draw;
          pass.widenFaint = gp.filtered;
          if (!d.groom->prepare(*d.state, d.instance->transform, pass))
            throw Error("groom \"" + d.instance->name +
                        "\": in front of the camera when the frame was planned, behind it now");
          d.groom->lod(*d.state, res[data.view], &r.profiler);
        });
  }
  g.addPass(
      "segment budget",
      [&](FrameGraph::Setup& s) {
        for (GroomPlan& gp : plan.grooms)
          if (gp.active) s.readsWrites({gp.lod});
        s.readsWrites({plan.lodArena});
        s.kernel("budget_measure").kernel("budget_plan").kernel("budget_apply");
      },
      [&](const FrameGraph::Resources&) {
        std::vector<GroomDraw> draws;
        std::vector<char> active, far;
        for (const GroomPlan& gp : plan.grooms) {
          draws.push_back(gp.draw);
          active.push_back(gp.active);
          far.push_back(gp.far);
        }
        r.frameLod.enqueue(draws, active, far, plan.budget, &r.profiler,
                           budgetRuleParams(plan.options, plan.camera().view));
      });
}

}  // namespace clhair
