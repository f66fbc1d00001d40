// flip.cpp — LDR-FLIP (see flip.h), written from the paper's description.
//
// Two pipelines run on the reference and the test image and meet per pixel:
//   colour:  linear RGB -> YyCxCz -> contrast-sensitivity filters -> back to linear RGB,
//            clamped -> CIELAB -> Hunt adjustment -> HyAB distance -> power q_c ->
//            redistribution to [0, 1]                                   = deltaE_c
//   feature: luminance Y/Yn -> edge (1st derivative of Gaussian) and point (2nd derivative)
//            detectors -> larger difference of response magnitudes -> power q_f = deltaE_f
//   FLIP  =  deltaE_c ^ (1 - deltaE_f)
// All 2D filters of the paper are sums of separable ones, so each is applied as a row pass
// and a column pass; the results equal the paper's 2D kernels up to float rounding. Kernel
// weights are built in double (the tails underflow in float at small ppd) and normalised
// as the paper says: CSF kernels sum to one, feature kernels have positive weights summing
// to one and negative weights summing to minus one.
#include "metrics/flip.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <glm/glm.hpp>
#include <string>

#include "clhair/error.h"

namespace clhair {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Colour-pipeline constants (Andersson et al. 2020, colour pipeline).
constexpr float kQc = 0.7f;   // exponent applied to the HyAB distance
constexpr float kPc = 0.4f;   // fraction of the maximum error mapped to ...
constexpr float kPt = 0.95f;  // ... this fraction of the output range
// Feature-pipeline constants.
constexpr double kW = 0.082;  // peak-to-trough width of the edge detector, in degrees
constexpr float kQf = 0.5f;   // exponent applied to the feature difference

// Contrast sensitivity per opponent channel as a sum of two Gaussians in frequency,
// a1 exp(-b1 f^2) + a2 exp(-b2 f^2); in the spatial domain each term becomes
// a sqrt(pi / b) exp(-pi^2 x^2 / b) with x in degrees. Achromatic and red-green use one term.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfAchromatic{1.0, 0.0047, 0.0, 1e-5};
constexpr Csf kCsfRedGreen{1.0, 0.0053, 0.0, 1e-5};
constexpr Csf kCsfBlueYellow{34.1, 0.04, 13.5, 0.025};

// Linear sRGB (D65) -> CIE XYZ, the sRGB primaries' matrix (rows), and its exact inverse.
constexpr double kRgbToXyzRows[3][3] = {
    {0.4123907992659595, 0.3575843393838780, 0.1804807884018343},
    {0.2126390058715104, 0.7151686787677559, 0.0721923153607337},
    {0.0193308187155918, 0.1191947797946259, 0.9505321522496606}};

glm::mat3 rgbToXyzMatrix() {
  glm::dmat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m[c][r] = kRgbToXyzRows[r][c];  // glm is column-major
  return glm::mat3(m);
}

glm::mat3 xyzToRgbMatrix() {
  glm::dmat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m[c][r] = kRgbToXyzRows[r][c];
  return glm::mat3(glm::inverse(m));
}

const glm::mat3 kRgbToXyz = rgbToXyzMatrix();
const glm::mat3 kXyzToRgb = xyzToRgbMatrix();

glm::vec3 linearRgbToXyz(glm::vec3 c) { return kRgbToXyz * c; }
glm::vec3 xyzToLinearRgb(glm::vec3 c) { return kXyzToRgb * c; }

// The white all colour spaces below are relative to: display white, RGB (1, 1, 1).
const glm::vec3 kWhite = linearRgbToXyz(glm::vec3(1.0f));

// YyCxCz: an opponent space linear in XYZ (CIELAB without the cube root), so that the
// spatial filters act on quantities proportional to light.
glm::vec3 xyzToYcxcz(glm::vec3 xyz) {
  glm::vec3 n = xyz / kWhite;
  return {116.0f * n.y - 16.0f, 500.0f * (n.x - n.y), 200.0f * (n.y - n.z)};
}

glm::vec3 ycxczToXyz(glm::vec3 c) {
  float ny = (c.x + 16.0f) / 116.0f;
  return glm::vec3(ny + c.y / 500.0f, ny, ny - c.z / 200.0f) * kWhite;
}

float labF(float t) {
  constexpr float kDelta = 6.0f / 29.0f;
  return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3.0f * kDelta * kDelta) + 4.0f / 29.0f;
}

glm::vec3 xyzToLab(glm::vec3 xyz) {
  glm::vec3 n = xyz / kWhite;
  float fx = labF(n.x), fy = labF(n.y), fz = labF(n.z);
  return {116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz)};
}

// Hunt effect: chroma is perceived weaker at low lightness, so scale a and b by L / 100.
glm::vec3 hunt(glm::vec3 lab) { return {lab.x, 0.01f * lab.x * lab.y, 0.01f * lab.x * lab.z}; }

// HyAB: city-block distance in lightness plus Euclidean distance in the chroma plane, which
// matches large colour differences better than Euclidean CIELAB distance.
float hyab(glm::vec3 a, glm::vec3 b) {
  glm::vec3 d = a - b;
  return std::abs(d.x) + std::sqrt(d.y * d.y + d.z * d.z);
}

// A single-channel float image.
struct Plane {
  int width = 0, height = 0;
  std::vector<float> v;
  Plane(int w, int h) : width(w), height(h), v(static_cast<std::size_t>(w) * h, 0.0f) {}
  float& at(int x, int y) { return v[static_cast<std::size_t>(y) * width + x]; }
  float at(int x, int y) const { return v[static_cast<std::size_t>(y) * width + x]; }
};

// An odd-length 1D kernel; tap i weighs the sample at offset i - radius.
using Kernel = std::vector<float>;

// Correlation along rows (filterRows) or columns (filterColumns); samples outside the image
// repeat the nearest edge pixel. Both keep the innermost loop running along a row, with no
// bounds logic in it, so it vectorises and reads memory in order.
Plane filterRows(const Plane& in, const Kernel& k) {
  const int w = in.width, r = static_cast<int>(k.size() / 2);
  Plane out(w, in.height);
  std::vector<float> padded(static_cast<std::size_t>(w) + 2 * r);
  for (int y = 0; y < in.height; ++y) {
    const float* row = &in.v[static_cast<std::size_t>(y) * w];
    for (int x = -r; x < w + r; ++x) padded[x + r] = row[std::clamp(x, 0, w - 1)];
    float* dst = &out.v[static_cast<std::size_t>(y) * w];
    for (int i = 0; i <= 2 * r; ++i) {
      const float ki = k[i];
      const float* src = &padded[i];
      for (int x = 0; x < w; ++x) dst[x] += ki * src[x];
    }
  }
  return out;
}

Plane filterColumns(const Plane& in, const Kernel& k) {
  const int w = in.width, h = in.height, r = static_cast<int>(k.size() / 2);
  Plane out(w, h);
  for (int y = 0; y < h; ++y) {
    float* dst = &out.v[static_cast<std::size_t>(y) * w];
    for (int i = -r; i <= r; ++i) {
      const float ki = k[i + r];
      const float* src = &in.v[static_cast<std::size_t>(std::clamp(y + i, 0, h - 1)) * w];
      for (int x = 0; x < w; ++x) dst[x] += ki * src[x];
    }
  }
  return out;
}

Plane filterSeparable(const Plane& in, const Kernel& kx, const Kernel& ky) {
  return filterColumns(filterRows(in, kx), ky);
}

Kernel toFloat(const std::vector<double>& k) { return Kernel(k.begin(), k.end()); }

// The CSF filter of one channel. Its 2D kernel G1 + G2 (normalised to sum one) is applied
// as two separable Gaussians, each scaled by its share of the 2D sum.
Plane filterCsf(const Plane& in, const Csf& csf, double ppd) {
  // One radius for all channels, from the widest Gaussian: 3 standard deviations.
  const double widest = std::max({kCsfAchromatic.b1, kCsfAchromatic.b2, kCsfRedGreen.b1,
                                  kCsfRedGreen.b2, kCsfBlueYellow.b1, kCsfBlueYellow.b2});
  const int r = static_cast<int>(std::ceil(3.0 * std::sqrt(widest / (2.0 * kPi * kPi)) * ppd));
  auto gaussian = [&](double b, double& sum) {
    std::vector<double> k(2 * r + 1);
    sum = 0.0;
    for (int i = -r; i <= r; ++i) {
      double x = i / ppd;  // degrees
      k[i + r] = std::exp(-kPi * kPi * x * x / b);
      sum += k[i + r];
    }
    return k;
  };
  double s1 = 0.0, s2 = 0.0;
  std::vector<double> g1 = gaussian(csf.b1, s1), g2 = gaussian(csf.b2, s2);
  // 2D sums of the two terms: amplitude times the square of the 1D sum.
  const double amp1 = csf.a1 * std::sqrt(kPi / csf.b1), amp2 = csf.a2 * std::sqrt(kPi / csf.b2);
  const double total = amp1 * s1 * s1 + amp2 * s2 * s2;
  auto scaled = [](std::vector<double> k, double f) {
    for (double& v : k) v *= f;
    return toFloat(k);
  };
  // Split the scale between the row and column pass so both stay near unit size.
  const double f1 = std::sqrt(amp1 / total);
  Plane out = filterSeparable(in, scaled(g1, f1), scaled(g1, f1));
  if (csf.a2 != 0.0) {
    const double f2 = std::sqrt(amp2 / total);
    Plane second = filterSeparable(in, scaled(g2, f2), scaled(g2, f2));
    for (std::size_t i = 0; i < out.v.size(); ++i) out.v[i] += second.v[i];
  }
  return out;
}

// Feature detectors on a Gaussian of standard deviation w/2 (w = kW degrees): the edge
// detector is its first derivative across x, the point detector its second derivative.
// Both are separable into (derivative kernel along x) x (Gaussian along y), and because
// the sign of a weight depends on x alone, normalising positive weights to +1 and negative
// ones to -1 in 2D is the same as doing so for the x kernel with a unit-sum y Gaussian.
struct FeatureKernels {
  Kernel gauss, edge, point;
};

FeatureKernels makeFeatureKernels(double ppd) {
  const double sd = 0.5 * kW * ppd;  // pixels
  const int r = static_cast<int>(std::ceil(3.0 * sd));
  std::vector<double> g(2 * r + 1), e(2 * r + 1), p(2 * r + 1);
  for (int i = -r; i <= r; ++i) {
    double x = i;
    g[i + r] = std::exp(-x * x / (2.0 * sd * sd));
    e[i + r] = -x * g[i + r];
    p[i + r] = (x * x / (sd * sd) - 1.0) * g[i + r];
  }
  auto unitSum = [](std::vector<double>& k) {
    double s = 0.0;
    for (double v : k) s += v;
    for (double& v : k) v /= s;
  };
  auto balance = [](std::vector<double>& k) {
    double pos = 0.0, neg = 0.0;
    for (double v : k) (v > 0.0 ? pos : neg) += v;
    if (!(pos > 0.0) || !(neg < 0.0))
      throw Error("FLIP: feature kernel degenerate (pixels per degree too small)");
    for (double& v : k) v /= v > 0.0 ? pos : -neg;
  };
  unitSum(g);
  balance(e);
  balance(p);
  return {toFloat(g), toFloat(e), toFloat(p)};
}

// Per pixel: magnitudes of the (x, y) edge and point responses of a luminance plane.
struct Features {
  Plane edge, point;
};

Features detectFeatures(const Plane& lum, const FeatureKernels& k) {
  const Plane smoothRows = filterRows(lum, k.gauss);  // shared by both y derivatives
  const Plane ex = filterColumns(filterRows(lum, k.edge), k.gauss),
              ey = filterColumns(smoothRows, k.edge);
  const Plane px = filterColumns(filterRows(lum, k.point), k.gauss),
              py = filterColumns(smoothRows, k.point);
  Features f{Plane(lum.width, lum.height), Plane(lum.width, lum.height)};
  for (std::size_t i = 0; i < lum.v.size(); ++i) {
    f.edge.v[i] = std::hypot(ex.v[i], ey.v[i]);
    f.point.v[i] = std::hypot(px.v[i], py.v[i]);
  }
  return f;
}

// The per-image half of both pipelines: Hunt-adjusted CIELAB of the CSF-filtered image, and
// feature magnitudes of the unfiltered luminance.
struct Prepared {
  std::vector<glm::vec3> huntLab;
  Features features;
};

Prepared prepare(const Image& img, double ppd, const FeatureKernels& fk) {
  const int w = img.width, h = img.height;
  Plane cy(w, h), cx(w, h), cz(w, h), lum(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* p = img.pixel(x, y);
      glm::vec3 rgb = glm::clamp(glm::vec3(p[0], p[1], p[2]), 0.0f, 1.0f);
      glm::vec3 xyz = linearRgbToXyz(rgb);
      glm::vec3 o = xyzToYcxcz(xyz);
      cy.at(x, y) = o.x;
      cx.at(x, y) = o.y;
      cz.at(x, y) = o.z;
      lum.at(x, y) = xyz.y / kWhite.y;  // = (Yy + 16) / 116
    }
  Plane fy = filterCsf(cy, kCsfAchromatic, ppd);
  Plane fx = filterCsf(cx, kCsfRedGreen, ppd);
  Plane fz = filterCsf(cz, kCsfBlueYellow, ppd);
  Prepared out{std::vector<glm::vec3>(static_cast<std::size_t>(w) * h), detectFeatures(lum, fk)};
  for (std::size_t i = 0; i < out.huntLab.size(); ++i) {
    // The filters can leave the RGB gamut; clamp it so the colour stays displayable.
    glm::vec3 rgb = glm::clamp(xyzToLinearRgb(ycxczToXyz({fy.v[i], fx.v[i], fz.v[i]})), 0.0f, 1.0f);
    out.huntLab[i] = hunt(xyzToLab(linearRgbToXyz(rgb)));
  }
  return out;
}

}  // namespace

double flipPixelsPerDegree(double distanceMeters, double monitorWidthMeters,
                           int monitorWidthPixels) {
  return distanceMeters * (monitorWidthPixels / monitorWidthMeters) * (kPi / 180.0);
}

FlipResult computeFlip(const Image& reference, const Image& test, double ppd) {
  if (reference.width != test.width || reference.height != test.height)
    throw Error("FLIP: image sizes differ (" + std::to_string(reference.width) + "x" +
                std::to_string(reference.height) + " vs " + std::to_string(test.width) + "x" +
                std::to_string(test.height) + ")");
  if (reference.width <= 0 || reference.height <= 0) throw Error("FLIP: the images are empty");
  if (!(ppd >= kFlipMinPpd && ppd <= kFlipMaxPpd))
    throw Error("FLIP: pixels per degree " + std::to_string(ppd) + " is outside " +
                std::to_string(kFlipMinPpd) + ".." + std::to_string(kFlipMaxPpd));

  const FeatureKernels fk = makeFeatureKernels(ppd);
  // The two images are independent until the per-pixel comparison: prepare them in parallel.
  std::future<Prepared> refJob =
      std::async(std::launch::async, [&] { return prepare(reference, ppd, fk); });
  const Prepared tst = prepare(test, ppd, fk);
  const Prepared ref = refJob.get();

  // The largest colour distance in the gamut, between green and blue, scales deltaE_c.
  const float cmax = std::pow(hyab(hunt(xyzToLab(linearRgbToXyz({0.0f, 1.0f, 0.0f}))),
                                   hunt(xyzToLab(linearRgbToXyz({0.0f, 0.0f, 1.0f})))),
                              kQc);
  const float pcCmax = kPc * cmax;

  FlipResult r;
  r.width = reference.width;
  r.height = reference.height;
  r.error.resize(ref.huntLab.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < r.error.size(); ++i) {
    // Colour: compress the distance, then send [0, pc*cmax) to [0, pt) and the rest of
    // [pc*cmax, cmax] to [pt, 1], so small differences get most of the range.
    const float d = std::pow(hyab(ref.huntLab[i], tst.huntLab[i]), kQc);
    const float dc =
        d < pcCmax ? kPt / pcCmax * d : kPt + (d - pcCmax) / (cmax - pcCmax) * (1.0f - kPt);
    // Features: the larger of the edge and point differences, scaled to [0, 1] (each
    // magnitude is at most sqrt(2)), compressed by q_f.
    const float de = std::abs(ref.features.edge.v[i] - tst.features.edge.v[i]);
    const float dp = std::abs(ref.features.point.v[i] - tst.features.point.v[i]);
    const float df = std::pow(std::min(std::max(de, dp) / std::sqrt(2.0f), 1.0f), kQf);
    // Missing or new features make a colour difference count more (a smaller exponent).
    const float e = std::pow(dc, 1.0f - df);
    r.error[i] = e;
    sum += e;
  }
  r.mean = sum / static_cast<double>(r.error.size());
  return r;
}

}  // namespace clhair
