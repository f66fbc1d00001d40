// environment.cpp — validating an environment map and building its prefiltered levels and
// SH coefficients with kernels/env.cl (see environment.h).
#include "lighting/environment.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "cl/cl_error.h"
#include "stages/env_stage.h"

namespace clhair {

static_assert(sizeof(gpu::ClhEnvLevel) == 16, "ClhEnvLevel layout (kernels/env.cl env_layout)");
static_assert(sizeof(gpu::ClhEnvSkyGpu) == 96, "ClhEnvSkyGpu layout (kernels/env.cl env_layout)");

namespace {

// ENV_WG of env.cl: one work-group size for every kernel (PoCL compiles once per size).
constexpr std::size_t kWg = 64;
constexpr double kPi = 3.14159265358979323846;

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

bool finite3(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool nonNegative3(const glm::vec3& v) { return v.x >= 0.0f && v.y >= 0.0f && v.z >= 0.0f; }

int floorPow2(int v) {
  int p = 1;
  while (p * 2 <= v) p *= 2;
  return p;
}

// Device buffers start zeroed by a host write: no kernel here reads what it has not
// written, but Oclgrind 21.10's --uninitialized check loses track of kernel-written data
// in buffers that start uninitialised (and a partial host write marks the rest of a buffer
// uninitialised), so full host writes keep the Oclgrind runs clean. Load time only.
template <typename T>
cl::Buffer allocate(Device::Impl& dev, const std::string& what, std::size_t count,
                    const void* init = nullptr) {
  std::size_t bytes = std::max<std::size_t>(count, 1) * sizeof(T);
  if (bytes > dev.info.maxAlloc)
    throw Error(what + " needs " + std::to_string(bytes >> 20) + " MiB in one buffer but " +
                dev.info.name + " allows at most " + std::to_string(dev.info.maxAlloc >> 20) +
                " MiB (use a smaller map)");
  std::vector<unsigned char> zeros(init ? 0 : bytes, 0);
  return clCall("allocating " + what, [&] {
    return cl::Buffer(dev.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, bytes,
                      const_cast<void*>(init ? init : zeros.data()));
  });
}

// GGX samples for a level of GGX alpha `alpha`: all of `maxSamples` for wide lobes, a
// quarter below 0.25, a sixteenth below 0.1 (at least 16). Filtered importance sampling
// matches each sample's source level to its solid angle, so fewer samples mean a blurrier
// rather than a noisier result, and narrow lobes (the large levels, where samples cost
// most) blur least. The wide lobes get many samples because they sit on small levels
// (cheap) and because there the pattern of a fixed sample set around a small bright source
// would otherwise show.
int samplesFor(int maxSamples, float alpha) {
  int n = alpha >= 0.25f ? maxSamples : alpha >= 0.1f ? maxSamples / 4 : maxSamples / 16;
  return std::max(n, 16);
}

gpu::ClhEnvSkyGpu packSky(const SkyParams& s) {
  gpu::ClhEnvSkyGpu g{};
  double e = s.sunElevationDeg * kPi / 180.0, a = s.sunAzimuthDeg * kPi / 180.0;
  double r = 0.5 * s.sunAngularDiameterDeg * kPi / 180.0;
  g.sun_dir[0] = static_cast<float>(std::cos(e) * std::sin(a));
  g.sun_dir[1] = static_cast<float>(std::sin(e));
  g.sun_dir[2] = static_cast<float>(-std::cos(e) * std::cos(a));
  g.sun_dir[3] = static_cast<float>(std::cos(r));
  // A uniform disc of radius r and radiance L gives E = L pi sin^2 r on a surface facing it.
  double radiance = s.sunIrradiance / (kPi * std::sin(r) * std::sin(r));
  for (int c = 0; c < 3; ++c) {
    g.sun_radiance[c] = static_cast<float>(radiance * s.sunColor[c]);
    g.zenith[c] = s.zenith[c];
    g.horizon[c] = s.horizon[c];
    g.ground[c] = s.ground[c];
  }
  g.shape[0] = s.gradientExponent;
  g.shape[1] = s.groundBlend;
  return g;
}

}  // namespace

std::string Environment::kernelDefines(const Options& options) {
  return "-DENV_WG=" + std::to_string(kWg) + " -DENV_SAMPLES=" + std::to_string(options.samples);
}

void Environment::validate(const Options& o, const std::string& what) {
  auto fail = [&](const std::string& msg) { throw Error(what + ": " + msg); };
  if (!std::isfinite(o.intensity) || o.intensity < 0.0f)
    fail("intensity " + fmt(o.intensity) + " must be a finite number >= 0");
  if (!std::isfinite(o.rotateYDegrees) || std::fabs(o.rotateYDegrees) > 1e6f)
    fail("rotate_y " + fmt(o.rotateYDegrees) + " must be a finite angle in degrees");
  if (o.levels < 1 || o.levels > CLH_ENV_MAX_LEVELS)
    fail("prefilter levels " + std::to_string(o.levels) + " must be in [1, " +
         std::to_string(CLH_ENV_MAX_LEVELS) + "]");
  if (!(o.minRoughness > 0.0f) || !(o.maxRoughness <= 1.0f) ||
      !(o.minRoughness <= o.maxRoughness) || (o.levels > 1 && !(o.minRoughness < o.maxRoughness)))
    fail("roughness range [" + fmt(o.minRoughness) + ", " + fmt(o.maxRoughness) +
         "] must satisfy 0 < min < max <= 1 (min = max only with one level)");
  if (o.baseWidth < kMinSourceWidth || o.baseWidth > kMaxSourceWidth)
    fail("base width " + std::to_string(o.baseWidth) + " must be in [" +
         std::to_string(kMinSourceWidth) + ", " + std::to_string(kMaxSourceWidth) + "]");
  if (o.minWidth < kMinSourceWidth || o.minWidth > o.baseWidth || o.minWidth % 2 != 0)
    fail("minimum width " + std::to_string(o.minWidth) + " must be even and in [" +
         std::to_string(kMinSourceWidth) + ", base width " + std::to_string(o.baseWidth) + "]");
  if (o.samples < 16 || o.samples > 1024)
    fail("samples " + std::to_string(o.samples) + " must be in [16, 1024]");
}

void Environment::validate(const SkyParams& s, const std::string& what) {
  auto fail = [&](const std::string& msg) { throw Error(what + ": sky " + msg); };
  if (!std::isfinite(s.sunElevationDeg) || std::fabs(s.sunElevationDeg) > 90.0f)
    fail("sun_elevation " + fmt(s.sunElevationDeg) + " must be in [-90, 90] degrees");
  if (!std::isfinite(s.sunAzimuthDeg) || std::fabs(s.sunAzimuthDeg) > 1e6f)
    fail("sun_azimuth " + fmt(s.sunAzimuthDeg) + " must be a finite angle in degrees");
  if (!(s.sunAngularDiameterDeg > 0.0f) || !(s.sunAngularDiameterDeg <= 45.0f))
    fail("sun_angular_diameter " + fmt(s.sunAngularDiameterDeg) + " must be in (0, 45] degrees");
  if (!std::isfinite(s.sunIrradiance) || s.sunIrradiance < 0.0f || s.sunIrradiance > 1e6f)
    fail("sun_irradiance " + fmt(s.sunIrradiance) + " must be in [0, 1e6]");
  const std::pair<const char*, const glm::vec3*> colours[] = {{"sun_color", &s.sunColor},
                                                              {"zenith", &s.zenith},
                                                              {"horizon", &s.horizon},
                                                              {"ground", &s.ground}};
  for (const auto& [name, c] : colours)
    if (!finite3(*c) || !nonNegative3(*c) || c->x > 1e6f || c->y > 1e6f || c->z > 1e6f)
      fail(std::string(name) + " must be three finite numbers in [0, 1e6]");
  if (!(s.gradientExponent > 0.0f) || !(s.gradientExponent <= 100.0f))
    fail("gradient_exponent " + fmt(s.gradientExponent) + " must be in (0, 100]");
  if (!(s.groundBlend > 0.0f) || !(s.groundBlend <= 1.0f))
    fail("ground_blend " + fmt(s.groundBlend) + " must be in (0, 1]");
  if (s.width < 16 || s.width > 4096 || s.width % 2 != 0)
    fail("resolution " + std::to_string(s.width) + " must be an even width in [16, 4096]");
}

Environment Environment::fromFile(Device::Impl& dev, const std::string& path,
                                  const Options& options, Profiler* profiler) {
  validate(options, path);
  Image image = readImage(path);
  return fromImage(dev, image, options, path, profiler);
}

Environment Environment::fromImage(Device::Impl& dev, const Image& image, const Options& options,
                                   const std::string& what, Profiler* profiler) {
  validate(options, what);
  const int w = image.width, h = image.height;
  const std::string size = std::to_string(w) + "x" + std::to_string(h);
  if (w <= 0 || h <= 0) throw Error(what + ": environment map is empty (" + size + ")");
  if (w > kMaxSourceWidth || h > kMaxSourceWidth / 2)
    throw Error(what + ": environment map is " + size + ", larger than the supported " +
                std::to_string(kMaxSourceWidth) + "x" + std::to_string(kMaxSourceWidth / 2) +
                " (downscale it; prefiltered levels use at most " +
                std::to_string(options.baseWidth) + " texels per row anyway)");
  if (w != 2 * h)
    throw Error(what + ": environment map is " + size +
                ", an equirectangular (lat-long) map needs width = 2 x height, e.g. 1024x512");
  if (w < kMinSourceWidth)
    throw Error(what + ": environment map is " + size + ", need at least " +
                std::to_string(kMinSourceWidth) + "x" + std::to_string(kMinSourceWidth / 2));
  const std::size_t texels = static_cast<std::size_t>(w) * h;
  if (image.rgba.size() != texels * 4)
    throw Error(what + ": environment image holds " + std::to_string(image.rgba.size()) +
                " floats, expected " + std::to_string(texels * 4) + " for " + size + " RGBA");
  std::vector<float> rgba(texels * 4);
  for (std::size_t p = 0; p < texels; ++p) {
    for (int c = 0; c < 3; ++c) {
      float v = image.rgba[p * 4 + c];
      if (!std::isfinite(v) || std::fabs(v) * options.intensity > kMaxRadiance) {
        const char* channel[] = {"red", "green", "blue"};
        throw Error(what + ": texel (" + std::to_string(p % w) + ", " + std::to_string(p / w) +
                    ") has " + channel[c] + " = " + fmt(v) +
                    (std::isfinite(v) ? ", above the supported radiance " + fmt(kMaxRadiance)
                                      : ", environment maps must be finite"));
      }
      rgba[p * 4 + c] = std::max(v, 0.0f);  // negative radiance (EXR ringing) is dropped
    }
    rgba[p * 4 + 3] = 1.0f;
  }
  return build(dev, &rgba, nullptr, w, options, what, profiler);
}

Environment Environment::fromSky(Device::Impl& dev, const SkyParams& sky, const Options& options,
                                 Profiler* profiler) {
  validate(options, "environment");
  validate(sky, "environment");
  return build(dev, nullptr, &sky, sky.width, options, "environment sky", profiler);
}

Environment Environment::build(Device::Impl& dev, const std::vector<float>* rgba,
                               const SkyParams* sky, int width, const Options& o,
                               const std::string& what, Profiler* profiler) {
  // OpenCL failures anywhere below (kernel arguments included) become one clhair::Error.
  try {
    return buildOnDevice(dev, rgba, sky, width, o, what, profiler);
  } catch (...) {
    rethrowAsClhairError(what + ": building environment lighting");
  }
}

Environment Environment::buildOnDevice(Device::Impl& dev, const std::vector<float>* rgba,
                                       const SkyParams* sky, int width, const Options& o,
                                       const std::string& what, Profiler* profiler) {
  auto t0 = std::chrono::steady_clock::now();
  Environment env;
  env.sourceWidth_ = width;
  env.sourceHeight_ = width / 2;

  // Source pyramid: level 0 is the map, each next level has half the rows (width = 2 rows),
  // down to 4 rows.
  std::vector<gpu::ClhEnvLevel> pyr;
  std::size_t pyrTexels = 0;
  for (std::uint32_t h = static_cast<std::uint32_t>(width / 2);
       pyr.size() < CLH_ENV_MAX_LEVELS && (pyr.empty() || h >= 4); h /= 2) {
    gpu::ClhEnvLevel lv{static_cast<gpu::clh_u32>(pyrTexels), 2 * h, h, 0.0f};
    pyr.push_back(lv);
    pyrTexels += static_cast<std::size_t>(lv.width) * lv.height;
  }

  // Prefiltered levels: power-of-two widths halving from baseWidth to minWidth, GGX alpha
  // geometric from minRoughness to maxRoughness.
  const int w0 = floorPow2(std::min(o.baseWidth, width));
  const int wMin = std::min(o.minWidth, w0);
  for (int i = 0; i < o.levels; ++i) {
    int w = std::max(w0 >> i, wMin);
    float t = o.levels > 1 ? static_cast<float>(i) / static_cast<float>(o.levels - 1) : 0.0f;
    float alpha = i == o.levels - 1 && o.levels > 1
                      ? o.maxRoughness
                      : o.minRoughness * std::pow(o.maxRoughness / o.minRoughness, t);
    gpu::ClhEnvLevel lv{static_cast<gpu::clh_u32>(env.texelCount_), static_cast<gpu::clh_u32>(w),
                        static_cast<gpu::clh_u32>(w / 2), alpha};
    env.levelTable_.push_back(lv);
    env.texelCount_ += static_cast<std::size_t>(lv.width) * lv.height;
  }

  EnvStage stage(dev, kernelDefines(o), kWg);
  const double rot = static_cast<double>(o.rotateYDegrees) * kPi / 180.0;
  EnvStage::Turn turn;
  turn.cos = static_cast<float>(std::cos(rot));
  turn.sin = static_cast<float>(std::sin(rot));
  turn.intensity = o.intensity;

  // ---- the source map: uploaded, or generated by env_sky ----
  // Coarser pyramid levels start as zeros until env_downsample fills them (see allocate()).
  std::vector<float> full;
  if (rgba) {
    full.assign(pyrTexels * 4, 0.0f);
    std::copy(rgba->begin(), rgba->end(), full.begin());
  }
  cl::Buffer pyramid =
      allocate<cl_float4>(dev, what + ": source pyramid", pyrTexels, rgba ? full.data() : nullptr);
  cl::Buffer pyrLevels =
      allocate<gpu::ClhEnvLevel>(dev, what + ": pyramid table", pyr.size(), pyr.data());
  EnvStage::Pyramid source;
  source.texels = &pyramid;
  source.count = static_cast<std::uint32_t>(pyrTexels);
  source.levels = &pyr;
  source.table = &pyrLevels;
  if (!rgba) {
    const gpu::ClhEnvSkyGpu params = packSky(*sky);
    cl::Buffer skyBuf = allocate<gpu::ClhEnvSkyGpu>(dev, "sky parameters", 1, &params);
    stage.sky(skyBuf, source, profiler);
  }
  stage.downsample(source, profiler);

  // ---- prefiltered levels ----
  env.texels_ = allocate<cl_float4>(dev, what + ": prefiltered levels", env.texelCount_);
  env.levels_ = allocate<gpu::ClhEnvLevel>(dev, what + ": level table", env.levelTable_.size(),
                                           env.levelTable_.data());
  for (const gpu::ClhEnvLevel& lv : env.levelTable_)
    stage.prefilter(source, lv, static_cast<std::uint32_t>(samplesFor(o.samples, lv.roughness)),
                    env.texels_, static_cast<std::uint32_t>(env.texelCount_), turn, profiler);

  // ---- SH: per-row partial sums, then a fixed-order sum per coefficient ----
  const std::size_t rowsFloats = static_cast<std::size_t>(pyr[0].height) * CLH_ENV_SH_FLOATS;
  cl::Buffer rows = allocate<float>(dev, what + ": SH row sums", rowsFloats);
  env.sh_ = allocate<float>(dev, what + ": SH coefficients", CLH_ENV_SH_FLOATS);
  stage.sh(source, rows, env.sh_, turn, profiler);
  clCall(what + ": reading SH coefficients", [&] {
    dev.queue.enqueueReadBuffer(env.sh_, CL_TRUE, 0, sizeof(float) * CLH_ENV_SH_FLOATS,
                                env.shCpu_.data());
    return dev.queue.finish();
  });
  for (float c : env.shCpu_)
    if (!std::isfinite(c))
      throw Error(what + ": SH projection produced a non-finite coefficient (radiance too large?)");

  env.loadMs_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return env;
}

glm::vec3 Environment::irradiance(const glm::vec3& n) const {
  float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  glm::vec3 d = len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
  glm::vec3 e;
  for (int c = 0; c < 3; ++c)
    e[c] = std::max(0.0f, gpu::clh_sh9_irradiance(shCpu_.data() + c, d.x, d.y, d.z));
  return e;
}

std::vector<float> Environment::downloadTexels(Device::Impl& dev) const {
  std::vector<float> out(texelCount_ * 4);
  if (out.empty()) return out;
  clCall("reading environment texels", [&] {
    dev.queue.enqueueReadBuffer(texels_, CL_TRUE, 0, out.size() * sizeof(float), out.data());
    return 0;
  });
  return out;
}

}  // namespace clhair
