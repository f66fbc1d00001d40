// test_link.cpp — hair linking and the alpha fix (Huang et al. 2025; kernels/link.cl,
// host/stages/link_stage.h) on synthetic G-buffers; the rendered
// frames' strand identities and linking are in test_link_frames.cpp.
//
// Synthetic G-buffers drive the link kernels directly, the curve layers filled as the curve
// pass would fill them (one pixel per column on the strand's line): a dashed diagonal strand
// comes out linked along its line only, with alpha = M / (M + N) from its own counts and
// its radiance conserved to 1 %; two crossing strands are each linked along their own line
// with their own identity; nothing is filled past a strand's end or over a filled pixel, nor
// past a nearer strand's pixel, while a walk passes its own drawn pixels and farther strands'
// ones (which count into its N); a hash table too small for the strands turns the rest
// away, counts them and leaves them at alpha 1. The anisotropic filter's tests are in
// test_link_filter.cpp, the helpers in link_synthetic.h. Tiny sizes: each test takes about
// a second or two.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <vector>

#include "link_synthetic.h"

namespace clhair {
namespace {

TEST(Link, DashedDiagonalStrandIsLinkedAlongItsLineWithAlphaMOverMPlusN) {
  Synthetic s;
  const int first = 3, last = 30;
  auto dash = [&](int i) { return (i - first) % 5 < 2 || i == last; };
  diagonal(s, 5, first, last, 1.3f, dash);
  int M = 0;
  for (int i = first; i <= last; ++i) M += dash(i);
  const int N = (last - first + 1) - M;
  const LinkResult r = runLink(s, linkOnly(), [](clh_u32) { return kRed; });
  const float alpha = float(M) / float(M + N);
  double sumBefore = 0.0, sumAfter = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::size_t p = std::size_t(y) * W + x;
      const bool onLine = x == y && x >= first && x <= last;
      SCOPED_TRACE(testing::Message() << "pixel " << x << "," << y);
      if (onLine) {
        ASSERT_NE(r.gbuf[p], kEmpty) << "a gap of the strand stayed empty";
        const clh_u64 id = r.gbuf[CLH_LAYER_ID * kPlane + p];
        EXPECT_EQ(clh_id_strand(id), 5u);
        EXPECT_EQ(clh_id_linked(id), dash(x) ? 0u : 1u);
        EXPECT_NEAR(r.out[p].s[3], alpha, 1e-6f);
        sumBefore += dash(x) ? kRed.s[0] : 0.0f;
      } else {
        EXPECT_EQ(r.gbuf[p], kEmpty) << "filled off the strand's line";
        EXPECT_EQ(r.out[p].s[3], 0.0f);
      }
      sumAfter += r.out[p].s[0];
    }
  EXPECT_EQ(r.counters.filled, std::uint32_t(N));
  EXPECT_EQ(r.counters.strands, 1u);
  EXPECT_EQ(r.counters.turnedAway, 0u);
  EXPECT_NEAR(sumAfter, sumBefore, 0.01 * sumBefore) << "radiance not conserved";
}

TEST(Link, WithoutLinkingTheGapsStayEmptyAndAlphaStaysOne) {
  // the same strand with linking and the alpha fix switched off: what the test above
  // asserts is the feature's doing
  Synthetic s;
  auto dash = [](int i) { return (i - 3) % 5 < 2; };
  diagonal(s, 5, 3, 30, 1.3f, dash);
  FilterParams f = linkOnly();
  f.link = false;
  f.alphaFix = false;
  const LinkResult r = runLink(s, f, [](clh_u32) { return kRed; });
  for (int i = 3; i <= 30; ++i) {
    const std::size_t p = std::size_t(i) * W + i;
    EXPECT_EQ(r.gbuf[p] != kEmpty, dash(i)) << i;
    EXPECT_EQ(r.out[p].s[3], dash(i) ? 1.0f : 0.0f) << i;
  }
  EXPECT_EQ(r.counters.filled, 0u);
}

// Strand 1 down-right along x = y, strand 2 up-right along x + y = 33, nearer; they cross
// between (16, 17) and (17, 16).
Synthetic crossing() {
  Synthetic s;
  for (int i = 4; i <= 29; ++i) {
    const float u = float(i - 4) / 25.0f;
    s.line(i, i, 1, u, 1.6f, 1.0f, 1.0f);
    if (i % 4 == 0 || i == 29) s.drawn(i, i, 1, u, 1.6f, 1.0f, 1.0f, kRed);
    s.line(i, 33 - i, 2, u, 1.2f, 1.0f, -1.0f);
    if (i % 4 == 2 || i == 29) s.drawn(i, 33 - i, 2, u, 1.2f, 1.0f, -1.0f, kBlue);
  }
  return s;
}

TEST(Link, CrossingStrandsAreEachLinkedAlongTheirOwnLine) {
  const Synthetic s = crossing();
  const LinkResult r = runLink(s, linkOnly(), [](clh_u32 k) { return k == 1 ? kRed : kBlue; });
  int linked1 = 0, linked2 = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const std::size_t p = std::size_t(y) * W + x;
      if (r.gbuf[p] == kEmpty) continue;
      const clh_u64 id = r.gbuf[CLH_LAYER_ID * kPlane + p];
      const clh_u32 k = clh_id_strand(id);
      SCOPED_TRACE(testing::Message() << "pixel " << x << "," << y << " strand " << k);
      if (k == 1) {
        EXPECT_EQ(x, y);
        linked1 += clh_id_linked(id);
      } else {
        EXPECT_EQ(k, 2u);
        EXPECT_EQ(x + y, 33);
        linked2 += clh_id_linked(id);
      }
    }
  // every gap of both lines is filled by its own strand
  for (int i = 4; i <= 29; ++i) {
    EXPECT_NE(r.gbuf[std::size_t(i) * W + i], kEmpty) << "strand 1 at " << i;
    EXPECT_NE(r.gbuf[std::size_t(33 - i) * W + i], kEmpty) << "strand 2 at " << i;
  }
  EXPECT_GT(linked1, 15);
  EXPECT_GT(linked2, 15);
  EXPECT_EQ(r.counters.strands, 2u);
}

// The pixels holding a word in any layer: what a groom's screen box must hold, tight.
PixelRect tightBox(const Synthetic& s) {
  PixelRect b{W, H, 0, 0};
  for (std::size_t l = 0; l <= CLH_LAYER_LINKED; ++l)
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        if (s.gbuf[l * kPlane + std::size_t(y) * W + x] != kEmpty)
          b = b.united({x, y, x + 1, y + 1});
  return b;
}

// Strand 3 drawn at its root, its line running on behind a nearer pixel of strand 4;
// strand 6 drawn at its tip (NothingIsFilledPastTheStrandsEndOrOverAFilledPixel).
Synthetic endsAndFilled() {
  Synthetic s;
  // strand 3: drawn at its first two pixels, its line runs on to (24, 24), where it ends; a
  // pixel of strand 4, nearer (z 1.4 against 1.5), sits on the line at (12, 12): strand 3
  // goes behind it there
  for (int i = 2; i <= 24; ++i) {
    const float u = float(i - 2) / 22.0f;
    s.line(i, i, 3, u, 1.5f, 1.0f, 1.0f);
    if (i <= 3) s.drawn(i, i, 3, u, 1.5f, 1.0f, 1.0f, kRed);
  }
  s.drawn(12, 12, 4, 0.5f, 1.4f, 0.0f, 1.0f, kBlue);
  // strand 6: drawn at its last pixel (its tip), nothing beyond it on its line
  for (int i = 4; i <= 8; ++i) s.line(i + 20, 30 - i, 6, float(i - 4) / 4.0f, 1.5f, 1.0f, -1.0f);
  s.drawn(28, 22, 6, 1.0f, 1.5f, 1.0f, -1.0f, kRed);
  s.drawn(27, 23, 6, 0.75f, 1.5f, 1.0f, -1.0f, kRed);
  return s;
}

TEST(Link, NothingIsFilledPastTheStrandsEndOrOverAFilledPixel) {
  const Synthetic s = endsAndFilled();
  const LinkResult r = runLink(s, linkOnly(), [](clh_u32 k) { return k == 4 ? kBlue : kRed; });
  for (int i = 4; i <= 11; ++i)
    EXPECT_EQ(clh_id_strand(r.gbuf[CLH_LAYER_ID * kPlane + std::size_t(i) * W + i]), 3u) << i;
  EXPECT_EQ(clh_id_strand(r.gbuf[CLH_LAYER_ID * kPlane + 12 * W + 12]), 4u) << "overwritten";
  EXPECT_EQ(clh_id_linked(r.gbuf[CLH_LAYER_ID * kPlane + 12 * W + 12]), 0u);
  for (int i = 13; i <= 24; ++i)
    EXPECT_EQ(r.gbuf[std::size_t(i) * W + i], kEmpty) << "filled past a filled pixel at " << i;
  // past the tip of strand 6 (up-right of (28, 22)) nothing
  for (int i = 1; i <= 5; ++i)
    EXPECT_EQ(r.gbuf[std::size_t(22 - i) * W + 28 + i], kEmpty) << "filled past the tip";
  // strand 6's root side is filled down to its first line pixel (24, 26), no further
  EXPECT_NE(r.gbuf[26 * W + 24], kEmpty);
  EXPECT_EQ(r.gbuf[27 * W + 23], kEmpty);
}

TEST(LinkScreenBox, PassesOverTheHairsTightBoxEqualThePassesOverTheWholeImage) {
  // The kernels over the tightest box a groom could have (every pixel holding a word in any
  // layer), each grown by its own margin (link.cl, "Screen boxes"): the G-buffer, the
  // counts and the result inside the box are those of the whole-image passes, which leave
  // 0 outside it. A margin too small fails here: the empty pixels beside a strand's first
  // and last pixels select it (select, propagate: box + 1) and lie on its tangent line,
  // where the filter reads them (the alpha fix: box + 3).
  auto colour = [](clh_u32 k) { return k == 2 || k == 4 ? kBlue : kRed; };
  Synthetic dashed;
  diagonal(dashed, 5, 3, 30, 1.3f, [](int i) { return (i - 3) % 5 < 2 || i == 30; });
  const std::pair<const char*, Synthetic> cases[] = {
      {"dashed diagonal", dashed}, {"crossing strands", crossing()}, {"ends", endsAndFilled()}};
  for (const auto& [name, s] : cases) {
    for (const bool aniso : {true, false}) {
      SCOPED_TRACE(testing::Message() << name << (aniso ? ", filtered" : ", alpha fix"));
      FilterParams f = linkOnly();
      f.aniso = aniso;
      const PixelRect box = tightBox(s);
      ASSERT_TRUE(box.x0 > 0 && box.y0 > 0 && box.x1 < W && box.y1 < H);
      const LinkResult whole = runLink(s, f, colour);
      const LinkResult bounded = runLink(s, f, colour, box);
      EXPECT_GT(whole.counters.filled, 0u);
      EXPECT_EQ(bounded.counters.selecting, whole.counters.selecting);
      EXPECT_EQ(bounded.counters.filled, whole.counters.filled);
      EXPECT_EQ(bounded.counters.strands, whole.counters.strands);
      EXPECT_EQ(bounded.counters.bounds, whole.counters.bounds);
      EXPECT_TRUE(bounded.gbuf == whole.gbuf) << "the G-buffers differ";
      std::size_t differ = 0, outside = 0;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          const std::size_t p = std::size_t(y) * W + x;
          if (x >= box.x0 && x < box.x1 && y >= box.y0 && y < box.y1) {
            differ += std::memcmp(&bounded.out[p], &whole.out[p], sizeof(cl_float4)) != 0;
          } else {
            outside += whole.out[p].s[3] != 0.0f || whole.out[p].s[0] != 0.0f;
          }
        }
      EXPECT_EQ(differ, 0u) << "results inside the box differ";
      EXPECT_EQ(outside, 0u) << "the whole-image result is not 0 outside the box";
    }
  }
}

TEST(Link, WalkPassesItsOwnPixelsAndFartherStrandsAndCountsThemForAlpha) {
  Synthetic s;
  // strand 3 along x = y from (2, 2) to (20, 20), z 1.5, drawn at 2, 3 and 14; strand 4, a
  // vertical one behind it (z 1.8), won the centre sample at (8, 8)
  const int first = 2, last = 20;
  auto own = [](int i) { return i == 2 || i == 3 || i == 14; };
  for (int i = first; i <= last; ++i) {
    const float u = float(i - first) / float(last - first);
    s.line(i, i, 3, u, 1.5f, 1.0f, 1.0f);
    if (own(i)) s.drawn(i, i, 3, u, 1.5f, 1.0f, 1.0f, kRed);
  }
  s.drawn(8, 8, 4, 0.5f, 1.8f, 0.0f, 1.0f, kBlue);
  const LinkResult r = runLink(s, linkOnly(), [](clh_u32 k) { return k == 4 ? kBlue : kRed; });
  // past the farther strand's pixel and past its own drawn pixel the walk goes on
  for (int i = first; i <= last; ++i) {
    const std::size_t p = std::size_t(i) * W + i;
    SCOPED_TRACE(testing::Message() << "pixel " << i);
    const clh_u64 id = r.gbuf[CLH_LAYER_ID * kPlane + p];
    if (i == 8) {  // never overwritten: one word a pixel, the sample's strand keeps it
      EXPECT_EQ(clh_id_strand(id), 4u);
      EXPECT_EQ(clh_id_linked(id), 0u);
      continue;
    }
    ASSERT_NE(r.gbuf[p], kEmpty) << "a gap of strand 3 stayed empty";
    EXPECT_EQ(clh_id_strand(id), 3u);
    EXPECT_EQ(clh_id_linked(id), own(i) ? 0u : 1u);
  }
  // M = 3 drawn; N = the 15 filled pixels and (8, 8), where strand 3 passes in front
  const int M = 3, filled = (last - first + 1) - M - 1;
  EXPECT_EQ(r.counters.filled, std::uint32_t(filled));
  const float alpha = float(M) / float(M + filled + 1);
  for (int i = first; i <= last; ++i) {
    if (i != 8) {
      EXPECT_NEAR(r.out[std::size_t(i) * W + i].s[3], alpha, 1e-6f) << i;
    }
  }
}

TEST(Link, AlphaFixBlendsLinkedPixelsOverTheBackgroundAndDrawnOnesOverTheirNeighbours) {
  Synthetic s;
  // the dashed diagonal strand 5, and beside it (one pixel to the right) a fully drawn blue
  // strand 9: a linked pixel of strand 5 saw the background, so behind its alpha there is
  // nothing (the scene, at compositing); a drawn pixel saw only strand 5, so behind it lies
  // the mean of its other neighbours, blue strand 9 among them
  const int first = 3, last = 30;
  auto dash = [&](int i) { return (i - first) % 5 < 2 || i == last; };
  diagonal(s, 5, first, last, 1.3f, dash);
  for (int i = first; i <= last; ++i)
    s.drawn(i + 1, i, 9, float(i - first) / float(last - first), 1.3f, 1.0f, 1.0f, kBlue);
  const LinkResult r = runLink(s, linkOnly(), [](clh_u32 k) { return k == 9 ? kBlue : kRed; });
  int M = 0;
  for (int i = first; i <= last; ++i) M += dash(i);
  const float alpha = float(M) / float(last - first + 1);
  int linked = 0;
  for (int i = first + 1; i < last; ++i) {
    const std::size_t p = std::size_t(i) * W + i;
    SCOPED_TRACE(testing::Message() << "pixel " << i);
    ASSERT_EQ(clh_id_strand(r.gbuf[CLH_LAYER_ID * kPlane + p]), 5u);
    if (!dash(i)) {  // exactly the strand's share, nothing of strand 9
      ++linked;
      EXPECT_NEAR(r.out[p].s[3], alpha, 1e-6f);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.out[p].s[c], alpha * kRed.s[c], 1e-6f) << c;
    } else {  // strand 9 shows behind it: more blue and more cover than the share alone
      EXPECT_GT(r.out[p].s[2], alpha * kRed.s[2] + 0.05f);
      EXPECT_GT(r.out[p].s[3], alpha + 0.05f);
    }
  }
  EXPECT_GT(linked, 10);
}

TEST(Link, AFullHashTableTurnsStrandsAwayCountedAndLeavesThemAtAlphaOne) {
  Synthetic s;
  // two dashed horizontal strands, rows 10 and 20
  for (int x = 2; x <= 33; ++x) {
    const float u = float(x - 2) / 31.0f;
    for (clh_u32 k : {7u, 8u}) {
      const int y = k == 7u ? 10 : 20;
      s.line(x, y, k, u, 1.5f, 1.0f, 0.0f);
      if (x % 3 == 0) s.drawn(x, y, k, u, 1.5f, 1.0f, 0.0f, kRed);
    }
  }
  FilterParams f = linkOnly();
  f.linkTable = 1;  // room for one strand
  const LinkResult r = runLink(s, f, [](clh_u32) { return kRed; });
  EXPECT_EQ(r.counters.strands, 1u);
  EXPECT_GT(r.counters.turnedAway, 0u) << "an overflow went uncounted";
  // one strand has its alpha fix, the other keeps alpha 1 on every pixel (linked ones too)
  int fixed = 0, kept = 0;
  for (int y : {10, 20}) {
    float a = r.out[std::size_t(y) * W + 9].s[3];
    for (int x = 3; x <= 32; ++x) EXPECT_EQ(r.out[std::size_t(y) * W + x].s[3], a) << x << "," << y;
    fixed += a < 0.5f;
    kept += a == 1.0f;
  }
  EXPECT_EQ(fixed, 1);
  EXPECT_EQ(kept, 1);
}

}  // namespace
}  // namespace clhair
