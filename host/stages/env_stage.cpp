// env_stage.cpp — see env_stage.h.
#include "stages/env_stage.h"

namespace clhair {

EnvStage::EnvStage(Device::Impl& dev, const std::string& defines, std::size_t workGroup)
    : dev_(dev),
      wg_(workGroup),
      sky_(dev.kernel("env.cl", "env_sky", defines)),
      down_(dev.kernel("env.cl", "env_downsample", defines)),
      pre_(dev.kernel("env.cl", "env_prefilter", defines)),
      shRows_(dev.kernel("env.cl", "env_sh_rows", defines)),
      shReduce_(dev.kernel("env.cl", "env_sh_reduce", defines)) {}

void EnvStage::sky(const cl::Buffer& params, const Pyramid& p, Profiler* profiler) {
  const gpu::ClhEnvLevel& l0 = (*p.levels)[0];
  KernelArgs(sky_, "env_sky")
      .buffer("sky", params, sizeof(gpu::ClhEnvSkyGpu))
      .buffer("pyramid", *p.texels, bytes(p))
      .value("pyramid texels", static_cast<cl_uint>(p.count))
      .value("width", static_cast<cl_uint>(l0.width))
      .value("height", static_cast<cl_uint>(l0.height));
  dispatch(dev_, sky_, "env_sky", cl::NDRange(l0.width * l0.height), cl::NDRange(wg_), profiler);
}

void EnvStage::downsample(const Pyramid& p, Profiler* profiler) {
  const std::vector<gpu::ClhEnvLevel>& pyr = *p.levels;
  for (std::size_t l = 1; l < pyr.size(); ++l) {
    KernelArgs(down_, "env_pyramid")
        .buffer("pyramid", *p.texels, bytes(p))
        .value("pyramid texels", static_cast<cl_uint>(p.count))
        .value("source offset", pyr[l - 1].offset)
        .value("source width", pyr[l - 1].width)
        .value("source height", pyr[l - 1].height)
        .value("offset", pyr[l].offset)
        .value("width", pyr[l].width)
        .value("height", pyr[l].height);
    dispatch(dev_, down_, "env_pyramid", cl::NDRange(pyr[l].width * pyr[l].height),
             cl::NDRange(wg_), profiler);
  }
}

void EnvStage::prefilter(const Pyramid& p, const gpu::ClhEnvLevel& lv, std::uint32_t samples,
                         cl::Buffer& out, std::uint32_t outCount, const Turn& t,
                         Profiler* profiler) {
  KernelArgs(pre_, "env_prefilter")
      .buffer("pyramid", *p.texels, bytes(p))
      .value("pyramid texels", static_cast<cl_uint>(p.count))
      .buffer("pyramid levels", *p.table, p.levels->size() * sizeof(gpu::ClhEnvLevel))
      .value("pyramid level count", static_cast<cl_uint>(p.levels->size()))
      .buffer("prefiltered texels", out, std::uint64_t(outCount) * 4 * sizeof(float))
      .value("prefiltered texel count", static_cast<cl_uint>(outCount))
      .value("offset", lv.offset)
      .value("width", lv.width)
      .value("height", lv.height)
      .value("roughness", lv.roughness)
      .value("samples", static_cast<cl_uint>(samples))
      .value("rotation cos", t.cos)
      .value("rotation sin", t.sin)
      .value("intensity", t.intensity);
  dispatch(dev_, pre_, "env_prefilter", cl::NDRange(lv.width * lv.height), cl::NDRange(wg_),
           profiler);
}

void EnvStage::sh(const Pyramid& p, cl::Buffer& rows, cl::Buffer& sh, const Turn& t,
                  Profiler* profiler) {
  const gpu::ClhEnvLevel& l0 = (*p.levels)[0];
  const std::size_t rowsFloats = static_cast<std::size_t>(l0.height) * CLH_ENV_SH_FLOATS;
  KernelArgs(shRows_, "env_sh")
      .buffer("pyramid", *p.texels, bytes(p))
      .value("pyramid texels", static_cast<cl_uint>(p.count))
      .value("width", l0.width)
      .value("height", l0.height)
      .value("rotation cos", t.cos)
      .value("rotation sin", t.sin)
      .value("intensity", t.intensity)
      .buffer("row sums", rows, rowsFloats * sizeof(float))
      .value("row floats", static_cast<cl_uint>(rowsFloats));
  dispatch(dev_, shRows_, "env_sh", cl::NDRange(l0.height), cl::NDRange(wg_), profiler);
  KernelArgs(shReduce_, "env_sh")
      .buffer("row sums", rows, rowsFloats * sizeof(float))
      .value("rows", l0.height)
      .value("row floats", static_cast<cl_uint>(rowsFloats))
      .buffer("SH", sh, CLH_ENV_SH_FLOATS * sizeof(float));
  dispatch(dev_, shReduce_, "env_sh", cl::NDRange(CLH_ENV_SH_FLOATS), cl::NDRange(wg_), profiler);
}

}  // namespace clhair
