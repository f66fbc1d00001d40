// fit_mesh.cpp — fitHairMesh (clhair/fit.h): the fitting pipeline from resampled strands
// to a validated hair mesh and its report. Each phase lives in its own file:
//   fit_strands    validation and resampling at equal arc length
//   scalp_chart    the scalp's flat map (head_surface with --head)
//   bundle_clusters  k-means over roots and shapes -> bundles
//   cage_topology  one quad per bundle on the chart, corners welded where roots touch
//   cage_layers    strands placed in their quads; every layer by principal axes, then
//                  least squares (cage_solve)
//   style_fit      the styling parameters from the residual against the base curves
//   fit_error      the mesh's strands generated and measured against the input
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include <glm/geometric.hpp>

#include "clhair/error.h"
#include "clhair/fit.h"
#include "fit/base_curve.h"
#include "fit/bundle_clusters.h"
#include "fit/cage_layers.h"
#include "fit/cage_topology.h"
#include "fit/curl_detect.h"
#include "fit/fit_error.h"
#include "fit/fit_strands.h"
#include "fit/head_surface.h"
#include "fit/parallel.h"
#include "fit/scalp_chart.h"
#include "fit/style_fit.h"
#include "groom/hair_bsdf_cpu.h"

namespace clhair {

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kStrandsPerBundle = 64;
constexpr int kDefaultLayers = 16;
constexpr float kLayersPerTurn = 6.0f;  // layer intervals a curl turn needs to be followed
constexpr int kRefinements = 2;         // rounds of layers then styling after the first

int controlPointsFor(const StrandGroom& g, int layers) {
  std::vector<std::uint32_t> c = g.pointCounts;
  std::nth_element(c.begin(), c.begin() + c.size() / 2, c.end());
  const int want = std::max(static_cast<int>(c[c.size() / 2]), layers);
  int cp = 3;
  while (cp < want && cp < CLH_MAX_CONTROL_POINTS) cp = 2 * (cp - 1) + 1;
  return std::min(cp, CLH_MAX_CONTROL_POINTS);
}

// The groom's per-point colours, averaged near the roots and near the tips.
bool fileColours(const StrandGroom& g, glm::vec3& root, glm::vec3& tip) {
  if (g.colors.empty()) return false;
  glm::dvec3 r(0.0), t(0.0);
  std::size_t at = 0;
  for (std::uint32_t n : g.pointCounts) {
    r += glm::dvec3(g.colors[at]);
    t += glm::dvec3(g.colors[at + n - 1]);
    at += n;
  }
  const double k = static_cast<double>(g.pointCounts.size());
  root = glm::clamp(glm::vec3(r / k), glm::vec3(0.0f), glm::vec3(1.0f));
  tip = glm::clamp(glm::vec3(t / k), glm::vec3(0.0f), glm::vec3(1.0f));
  return true;
}

// A file's colour is its fibres' albedo (shade.cl: clh_hair_sigma_a_from_albedo), a hair
// mesh's root and tip colours go through Chiang et al.'s mapping (clh_hair_sigma_a_from_color,
// sigma_a = (ln c / d(beta_n))^2): the mesh colour with the same absorption is
// c = exp(-sqrt(sigma_a) d(beta_n)).
glm::vec3 meshColourOfAlbedo(glm::vec3 albedo, float betaN, float ior) {
  namespace hb = cpu_bsdf;
  const hb::clh_v3 s =
      hb::clh_hair_sigma_a_from_albedo(hb::clh_v3_make(albedo.x, albedo.y, albedo.z), ior);
  const float b = betaN, b2 = b * b, b3 = b2 * b, b4 = b2 * b2, b5 = b4 * b;
  const float d = 5.969f - 0.215f * b + 2.532f * b2 - 10.73f * b3 + 5.574f * b4 + 0.245f * b5;
  return glm::vec3(std::exp(-std::sqrt(std::max(s.x, 0.0f)) * d),
                   std::exp(-std::sqrt(std::max(s.y, 0.0f)) * d),
                   std::exp(-std::sqrt(std::max(s.z, 0.0f)) * d));
}

void checkOptions(const FitOptions& o) {
  if (o.bundles < 0 || o.bundles > kFitMaxBundles)
    throw Error("bundles is " + std::to_string(o.bundles) + ", expected 1.." +
                std::to_string(kFitMaxBundles) + " (0: automatic)");
  if (o.layers != 0 && (o.layers < 2 || o.layers > CLH_MAX_LAYERS))
    throw Error("layers is " + std::to_string(o.layers) + ", expected 2.." +
                std::to_string(CLH_MAX_LAYERS) + " (0: automatic)");
  if (!(o.fibreWidth >= 0.0f) || !std::isfinite(o.fibreWidth))
    throw Error("fibre width must be a finite number >= 0 (0: from the strands)");
  if (!(o.shapeWeight >= 0.0f) || !std::isfinite(o.shapeWeight) || !(o.shapeScale >= 0.0f) ||
      !std::isfinite(o.shapeScale))
    throw Error("shape weight and shape scale must be finite numbers >= 0");
}

// No generated strand is longer than kLengthCap times the longest input strand. The layers
// never reach past the longest strand (cage_layers.cpp); what the styling adds to a full-
// length strand (frizz, flyaways, curl on base curves that may hold some of it already,
// clumping that pulls tips across the cage) is scaled down in steps until the longest
// generated strand fits, and a report note says so.
constexpr float kLengthCap = 1.1f;

float longestOf(const fit::GeneratedStrands& g) {
  const std::vector<float> l = fit::generatedLengths(g);
  return l.empty() ? 0.0f : *std::max_element(l.begin(), l.end());
}

void capLengths(HairMesh& m, float longest, int threads, fit::GeneratedStrands& gen,
                FitReport& rep) {
  float out = longestOf(gen);
  if (!(out > kLengthCap * longest)) return;
  const float before = out;
  const StyleParams fitted = m.style;
  float k = 1.0f;
  for (int step = 0; step < 8 && out > kLengthCap * longest; ++step) {
    k *= 0.7f;
    m.style.frizzAmplitude = fitted.frizzAmplitude * k;
    m.style.flyawayAmplitude = fitted.flyawayAmplitude * k;
    m.style.curlAmplitude = fitted.curlAmplitude * k;
    m.style.clumpStrength = fitted.clumpStrength * k;
    gen = fit::generateStrandsCpu(m, threads);
    out = longestOf(gen);
  }
  char buf[300];
  std::snprintf(buf, sizeof(buf),
                "the styling's frizz, flyaway and curl amplitudes and its clumping are scaled by "
                "%.3g: with the "
                "fitted ones the longest generated strand was %.4g m, %.2fx the longest input "
                "strand (%.4g m); now %.4g m (%.2fx)",
                static_cast<double>(k), static_cast<double>(before),
                static_cast<double>(before / longest), static_cast<double>(longest),
                static_cast<double>(out), static_cast<double>(out / longest));
  rep.notes.push_back(buf);
}

}  // namespace

FitResult fitHairMesh(const StrandGroom& groom, const FitOptions& opt) {
  checkOptions(opt);
  const auto start = Clock::now();
  auto lap = start;
  FitResult result;
  FitReport& rep = result.report;
  auto phase = [&](const char* name) {
    const auto now = Clock::now();
    rep.timings.push_back({name, std::chrono::duration<double>(now - lap).count()});
    lap = now;
  };
  const int threads = fit::resolveThreads(opt.threads);
  rep.input = groom.name;

  // 1. input
  fit::FitStrands s = fit::prepareFitStrands(groom, kFitSamples, opt.fibreWidth, threads);
  const std::size_t n = s.count();
  // a fibre wider than a tenth of a typical strand is no hair (and sizes the cage's quads
  // and the error's search beyond the groom: fit-mesh --fibre-width 1e30)
  if (!(s.fibreWidth <= 0.1 * s.medianLength) && s.medianLength > 0.0)
    throw Error("fibre width " + std::to_string(s.fibreWidth) +
                " is more than a tenth of the "
                "median strand length " +
                std::to_string(s.medianLength) +
                (opt.fibreWidth > 0.0f ? " (--fibre-width)" : " (the strand file's thickness)"));
  rep.fibreWidth = s.fibreWidth;
  rep.strandsIn = n;
  rep.lengthIn = fit::lengthStats(s.length);
  rep.strandBytes = static_cast<std::uint64_t>(groom.points.size()) * 12u;
  phase("resample");

  // 2. scalp chart
  std::unique_ptr<fit::HeadSurface> head;
  if (opt.head) {
    validateTriangleMesh(*opt.head, "head mesh");
    head = std::make_unique<fit::HeadSurface>(*opt.head);
  }
  std::vector<glm::vec3> roots(n), growth(n);
  for (std::size_t i = 0; i < n; ++i) {
    roots[i] = s.root(i);
    growth[i] = s.atFraction(i, 0.1f) - s.root(i);
  }
  const fit::ScalpChart chart = fit::fitScalpChart(roots, growth, head.get());
  std::vector<glm::vec2> chartRoots(n);
  for (std::size_t i = 0; i < n; ++i) chartRoots[i] = chart.toChart(roots[i]);
  phase("chart");

  // 3. bundles
  const int target = opt.bundles > 0
                         ? opt.bundles
                         : std::clamp(static_cast<int>(n / kStrandsPerBundle), 1, kFitMaxBundles);
  const float shapeScale =
      opt.shapeScale > 0.0f ? opt.shapeScale : 0.1f * static_cast<float>(s.medianLength);
  const std::vector<float> shape = fit::shapeFeatures(s, threads);
  fit::Clusters clusters =
      fit::clusterStrands(chartRoots, shape, target, opt.shapeWeight, shapeScale, threads);
  bool coincide = true;
  for (const glm::vec2& c : chartRoots)
    coincide = coincide && glm::length(c - chartRoots[0]) < 1e-9f;
  if (n == 1)
    rep.notes.push_back("one strand: the mesh is a single bundle around it");
  else if (coincide)
    rep.notes.push_back("all roots coincide: the mesh is a single bundle");
  else if (clusters.count == 1)
    rep.notes.push_back(opt.bundles == 1 ? "one bundle was asked for"
                                         : "too few strands for more than one bundle: the mesh "
                                           "is a single bundle");
  if (clusters.count == 1) {  // a single-bundle fit needs the cluster's own statistics
    clusters.centre = {glm::vec2(0.0f)};
    for (const glm::vec2& c : chartRoots) clusters.centre[0] += c / static_cast<float>(n);
    clusters.shape.assign(fit::kShapeDims, 0.0f);
    clusters.members = {static_cast<int>(n)};
  }
  phase("cluster");

  // 4. cage
  // a quad at least a tenth of a lattice cell across; a single bundle of coinciding roots
  // one fibre width across (its strands start within a fibre of the input's root)
  const float minExtent = clusters.spacing > 0.0f
                              ? std::max(0.1f * clusters.spacing, 2.0f * s.fibreWidth)
                              : 0.5f * s.fibreWidth;
  const fit::CageTopology topo =
      fit::buildCageTopology(clusters, chartRoots, minExtent, opt.shapeWeight, shapeScale, 2.0f);
  fit::StrandPlacement place = fit::placeStrands(s, clusters, topo, chartRoots, threads);
  const int L = opt.layers > 0 ? opt.layers : kDefaultLayers;
  HairMesh& m = result.mesh;
  m.name = groom.name.empty() ? "fitted" : groom.name + "_fitted";
  m.layerCount = L;
  m.vertexCount = static_cast<int>(topo.vertexChart.size());
  // a curl the layers are too sparse to follow is smoothed away for the first cage
  const float turns = fit::detectCurlTurns(s, threads);
  const bool followCurl = static_cast<float>(L - 1) >= kLayersPerTurn * turns;
  {
    const fit::FitStrands first = followCurl ? s : fit::smoothOverTurn(s, turns, threads);
    fit::StrandPlacement firstPlace = place;
    fit::fullLengths(first, topo, firstPlace);
    m.positions = fit::fitCageLayers(first, clusters, topo, chart, firstPlace,
                                     fit::linearLayerArcs(first, firstPlace, L, false), L, nullptr,
                                     head.get(), threads);
  }
  for (const auto& f : topo.faces) m.faces.push_back({f[0], f[1], f[2], f[3]});
  glm::vec2 lo(1e30f), hi(-1e30f);
  for (const glm::vec2& c : topo.vertexChart) {
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
  }
  const float span = std::max(std::max(hi.x - lo.x, hi.y - lo.y), 1e-12f);
  for (const glm::vec2& c : topo.vertexChart) m.uv.push_back(0.05f + 0.9f * (c - lo) / span);
  m.strandCount = static_cast<std::int64_t>(n);
  m.controlPoints = controlPointsFor(groom, L);
  m.seed = opt.seed;
  m.appearance = groom.appearance;
  m.appearance.useFileColor = false;
  m.appearance.strandWidth = s.fibreWidth;
  // the file's transparency: strand files draw a fibre (1 - t) times as wide (its share of
  // a pixel's coverage), hair meshes have no transparency, so the width carries it
  if (!groom.transparency.empty()) {
    double t = 0.0;
    for (float v : groom.transparency) t += static_cast<double>(v);
    t /= static_cast<double>(groom.transparency.size());
    m.appearance.strandWidth *= static_cast<float>(1.0 - std::min(std::max(t, 0.0), 0.99));
  }
  glm::vec3 rootColour, tipColour;
  if (fileColours(groom, rootColour, tipColour)) {
    m.appearance.rootColor = meshColourOfAlbedo(rootColour, m.appearance.betaN, m.appearance.ior);
    m.appearance.tipColor = meshColourOfAlbedo(tipColour, m.appearance.betaN, m.appearance.ior);
    m.appearance.useMelanin = false;
  }
  m.lod = groom.lod;
  rep.bundles = static_cast<int>(m.faces.size());
  rep.layers = L;
  rep.vertices = m.vertexCount;
  phase("cage");

  // 5. styling
  validateHairMesh(m, "fitted mesh");
  // a first styling fit, then the layers again where that curl and the first base curves
  // say each layer lies along the strands, and the styling again on the new base curves
  // The layers and the styling are fitted in turn. A first styling fit against layers
  // placed at equal arc length along the strands; then, kRefinements times, the layers
  // again (the last base curves carrying short strands on to the upper layers) and the
  // styling again on the new base curves. When the layers are too sparse to follow the
  // curl found (fewer than kLayersPerTurn per turn), the layers are fitted to the strands
  // with their fitted curl taken out, so that they hold the base curves alone and the
  // styling all of the curl; otherwise the layers follow the curls (with their phases where
  // the input has them) and the styling keeps the rest.
  auto base = std::make_unique<fit::BaseCurves>(m);
  fit::StyleFitResult style = fit::fitStyle(s, place, m, *base, nullptr, threads);
  const bool sparse =
      !followCurl || (style.global.curlAmplitude > 0.0f &&
                      static_cast<float>(L - 1) < kLayersPerTurn * style.global.curlFrequency);
  for (int it = 0; it < kRefinements; ++it) {
    const FittedStyle before = style.global;
    const fit::FitStrands cageInput =
        sparse ? fit::removeCurl(s, place, *base, before, it > 0 ? &before : nullptr, threads) : s;
    fit::StrandPlacement cagePlace = place;
    fit::fullLengths(cageInput, topo, cagePlace);
    m.positions = fit::fitCageLayers(cageInput, clusters, topo, chart, cagePlace,
                                     fit::linearLayerArcs(cageInput, cagePlace, L, true), L,
                                     base.get(), head.get(), threads);
    base = std::make_unique<fit::BaseCurves>(m);
    style = fit::fitStyle(s, place, m, *base, &before, threads);
  }
  if (sparse)
    rep.notes.push_back("the curl (" + std::to_string(style.global.curlFrequency) +
                        " turns) is too fine for " + std::to_string(L) +
                        " layers: the layers follow the base curves and the styling holds the "
                        "curl, with phases of its own");
  fit::applyStyle(style.global, m.style);
  rep.fitted = style.global;
  rep.notes.insert(rep.notes.end(), style.notes.begin(), style.notes.end());
  validateHairMesh(m, "fitted mesh");
  phase("style");

  // 6. report: per-bundle counts and densities, then (optionally) distances
  const GroomData& data = base->data();
  rep.perBundle.resize(m.faces.size());
  for (std::size_t i = 0; i < n; ++i) ++rep.perBundle[place.face[i]].strandsIn;
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    FitBundleReport& b = rep.perBundle[f];
    b.strandsOut = data.bundles[f].strand_count;
    b.style = style.perBundle[f];
    const auto& q = m.faces[f];
    const glm::vec3 &p0 = m.position(0, q[0]), &p1 = m.position(0, q[1]), &p2 = m.position(0, q[2]),
                    &p3 = m.position(0, q[3]);
    const double area = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0)) +
                        0.5 * glm::length(glm::cross(p2 - p0, p3 - p0));
    b.width = 0.25 * (glm::length(p1 - p0) + glm::length(p2 - p1) + glm::length(p3 - p2) +
                      glm::length(p0 - p3));
    b.rootDensityIn = area > 0.0 ? b.strandsIn / area : 0.0;
    b.rootDensityOut = area > 0.0 ? b.strandsOut / area : 0.0;
  }
  fit::GeneratedStrands gen = fit::generateStrandsCpu(m, threads);
  if (!s.length.empty())
    capLengths(m, *std::max_element(s.length.begin(), s.length.end()), threads, gen, rep);
  rep.strandsOut = gen.count();
  rep.lengthOut = fit::lengthStats(fit::generatedLengths(gen));
  phase("generate");
  if (opt.evaluate) {
    std::vector<std::size_t> measured;
    const std::size_t every = opt.errorSample > 0 && opt.errorSample < n ? n / opt.errorSample : 1;
    for (std::size_t i = 0; i < n; i += every)
      if (s.length[i] > 0.0f) measured.push_back(i);
    const std::vector<float> d = fit::strandDistances(s, measured, gen, threads);
    rep.error = fit::summarize(d, s.fibreWidth);
    std::vector<std::vector<float>> per(m.faces.size());
    for (std::size_t k = 0; k < measured.size(); ++k) per[place.face[measured[k]]].push_back(d[k]);
    for (std::size_t f = 0; f < per.size(); ++f)
      rep.perBundle[f].error = fit::summarize(per[f], s.fibreWidth);
    phase("error");
  }
  rep.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return result;
}

}  // namespace clhair
