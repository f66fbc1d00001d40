// fit.h — a hair mesh fitted to explicit strands (`clhair fit-mesh`, docs/fitting.md).
//
// fitHairMesh turns a StrandGroom (a cyHair, USC-HairSalon or TressFX file, or strands built
// in memory) into a HairMesh whose generated strands follow the input: the strands are
// clustered by root position on the scalp and by shape, each cluster becomes a bundle whose
// quads come from its cross-sections at equal arc length (centre and principal axes, then a
// least-squares refinement in which neighbouring bundles share corners), and the styling
// parameters of the generator (curl, clumping, frizz, length variation, root density) are
// fitted by least squares to what the bundles' Hermite base curves leave unexplained.
// The report measures the result against the input: distances from every input strand to
// the nearest generated strand, strand counts and lengths in and out, sizes and times.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "clhair/hair_mesh.h"
#include "clhair/strand_groom.h"
#include "clhair/triangle_mesh.h"

namespace clhair {

struct FitOptions {
  // Bundles (scalp faces) to aim for; 0: chosen from the strand count and the size budget
  // (about one bundle per 64 strands, at most kFitMaxBundles).
  int bundles = 0;
  // Layers per bundle, 2..64; 0: 16. A curl finer than the layers can follow (fewer than six
  // layer intervals a turn) is left to the styling (docs/fitting.md).
  int layers = 0;
  // Optional scalp surface (same units and axes as the strands): the root layer is placed
  // on it and the scalp chart follows it. Null: the scalp comes from the roots alone.
  const TriangleMesh* head = nullptr;
  // Fibre width for the mesh's appearance and the error in fibre widths; 0: the groom's
  // per-point thickness (median) when it has one, else appearance.strandWidth.
  float fibreWidth = 0.0f;
  // Weight of strand shape against root position when clustering: 1 puts a difference of
  // `shapeScale` metres between two strands' resampled shapes level with one bundle width
  // between their roots. 0: roots only.
  float shapeWeight = 1.0f;
  float shapeScale = 0.0f;  // metres; 0: a tenth of the median strand length
  // Measure the fit error (generates every strand of the mesh on the CPU). Off: the report
  // has counts, lengths and times but no distances.
  bool evaluate = true;
  // Strands whose distance is measured (an even sample); 0: all of them.
  std::size_t errorSample = 0;
  std::uint32_t seed = 1;  // the mesh's seed (styling randomness, LOD offsets)
  int threads = 0;         // worker threads; 0: the hardware's
};

// Limits of the fitter: bundles it makes at most, points it resamples every strand to.
constexpr int kFitMaxBundles = 16384;
constexpr int kFitSamples = 48;

// Distances from input strands to the nearest generated strand: the distance of strand I to
// strand G is the mean over I's resampled points of the distance to G's polyline, and each
// I takes the G that makes it smallest (docs/fitting.md, "Fit error").
struct FitDistance {
  std::size_t strands = 0;  // input strands measured
  double meanM = 0.0, p95M = 0.0;
  double meanWidths = 0.0, p95Widths = 0.0;  // the same in fibre widths
};

// Strand lengths (arc length along the polyline), metres.
struct LengthStats {
  std::size_t strands = 0;
  double mean = 0.0, min = 0.0, p05 = 0.0, median = 0.0, p95 = 0.0, max = 0.0;
};

// The styling the fit estimates for one bundle (or, for FitReport::fitted, the whole groom),
// before it is aggregated into the mesh's single StyleParams.
struct FittedStyle {
  float curlAmplitude = 0.0f, curlFrequency = 0.0f, curlHelix = 0.0f, curlPhaseJitter = 0.0f;
  float clumpStrength = 0.0f, clumpFrequency = 0.0f, clumpShape = 0.0f;
  float frizzAmplitude = 0.0f, frizzFrequency = 0.0f;
  float flyawayFraction = 0.0f, flyawayAmplitude = 0.0f;
  float lengthVariation = 0.0f;
};

struct FitBundleReport {
  std::uint32_t strandsIn = 0;   // input strands assigned to the bundle
  std::uint32_t strandsOut = 0;  // strands the mesh generates in it
  double width = 0.0;            // root quad's mean side, metres
  double rootDensityIn = 0.0;    // input roots per square metre of the root quad
  double rootDensityOut = 0.0;   // generated roots per square metre
  FitDistance error;
  FittedStyle style;  // this bundle's own estimate
};

struct FitReport {
  std::string input;  // name of the strand groom
  float fibreWidth = 0.0f;
  int bundles = 0, layers = 0, vertices = 0;
  std::size_t strandsIn = 0, strandsOut = 0;
  LengthStats lengthIn, lengthOut;
  FitDistance error;   // every measured input strand
  FittedStyle fitted;  // the groom-wide estimate written into the mesh's style
  std::vector<FitBundleReport> perBundle;
  // Sizes: the strand data as stored in memory (12 bytes per point) and, when the caller
  // knows them, the files (0: unknown).
  std::uint64_t strandBytes = 0, strandFileBytes = 0, meshFileBytes = 0;
  // Wall time of each phase, seconds, in order, and their total.
  std::vector<std::pair<std::string, double>> timings;
  double seconds = 0.0;
  // Things the mesh cannot represent or that were adjusted, one line each.
  std::vector<std::string> notes;
};

struct FitResult {
  HairMesh mesh;  // passes validateHairMesh
  FitReport report;
};

// Fits a hair mesh to `strands`. Throws clhair::Error (one line) for input that cannot be
// fitted: no strands, non-finite points, every strand of zero length, options out of range.
// One strand, or strands whose roots all coincide, give a single-bundle mesh (a note says so).
FitResult fitHairMesh(const StrandGroom& strands, const FitOptions& options = {});

// The report as JSON (docs/fitting.md, "The report"); written atomically.
std::string fitReportJson(const FitReport& report);
void writeFitReport(const FitReport& report, const std::string& path);

}  // namespace clhair
