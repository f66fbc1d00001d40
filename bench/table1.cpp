// table1.cpp — the benchmark's table1 section (clhair_bench --only table1):
// Lipp et al. Table 1 for this device: {MSAA 1, 2, 4, 8} x {LOD off, on} x {close, mid, far} x
// {groom 1, groom 2}; per-stage medians after warm-up, strands and segments drawn, G-buffer writes,
// atomics issued and skipped.
#include "harness.h"

#include <cstdio>
#include <string>
#include <vector>

namespace clhair::bench {

void runTable1(Run& r) {
  // rows: software MSAA 1 (filter off), SWR1+F (the default filter: Huang's), MSAA 2, 4, 8
  struct Row {
    int msaa;
    bool filter;
    const char* label;
  };
  std::vector<Row> rows = r.opt.quick
                              ? std::vector<Row>{{1, false, "1"}, {1, true, "1+F"}, {4, false, "4"}}
                              : std::vector<Row>{{1, false, "1"},
                                                 {1, true, "1+F"},
                                                 {2, false, "2"},
                                                 {4, false, "4"},
                                                 {8, false, "8"}};
  r.md << "## Table 1: frame time in ms, total (strand pass), " << r.opt.width << "x"
       << r.opt.height << "\n\n";
  r.md << "| LOD | MSAA | " << r.groomNames[0] << " close | mid | far | " << r.groomNames[1]
       << " close | mid | far |\n";
  r.md << "|---|---|---|---|---|---|---|---|\n";
  json t1 = json::array();
  std::ostringstream counts;
  counts << "\n### Work per frame (LOD off / on, MSAA 1, no filter)\n\n| groom | distance | "
            "LOD | strands | segments | "
            "G-buffer writes | atomics issued | skipped by the load "
            "|\n|---|---|---|---|---|---|---|---|\n";
  for (int lod = 0; lod < 2; ++lod) {
    for (const Row& rowSpec : rows) {
      const int msaa = rowSpec.msaa;
      r.md << "| " << (lod ? "on" : "off") << " | " << rowSpec.label << " |";
      for (int g = 0; g < 2; ++g) {
        for (int d = 0; d < 3; ++d) {
          if (r.opt.only == "atomics" && (msaa != 1 || rowSpec.filter)) continue;
          Scene s = framed(r.scenes[g], r.dists[d], r.opt.width, r.opt.height);
          RenderOptions o;
          o.lod = lod ? Toggle::On : Toggle::Off;
          o.msaa = msaa;
          o.filter = rowSpec.filter ? Toggle::On : Toggle::Off;
          Measured m = r.b.measure(s, o);
          r.md << " " << fmt(m.wall.median) << " (" << fmt(m.total.median) << "; "
               << fmt(stageMedian(m, "strands")) << ") |";
          json row = measuredJson(m);
          row["groom"] = r.groomNames[g];
          row["lod"] = lod == 1;
          row["msaa"] = msaa;
          row["filter"] = rowSpec.filter;
          row["distance"] = r.distNames[d];
          t1.push_back(row);
          r.csvRow(rowSpec.filter ? "table1+F" : "table1", r.groomNames[g], lod, msaa,
                   r.distNames[d], r.scenes[g].grooms[0].mesh->strandCount, r.opt.width,
                   r.opt.height, "auto", m);
          if (msaa == 1 && !rowSpec.filter) {
            r.msaa1Rows.push_back(
                {std::string(r.groomNames[g]) + " " + r.distNames[d] + (lod ? " LOD" : ""), m});
            counts << "| " << r.groomNames[g] << " | " << r.distNames[d] << " | "
                   << (lod ? "on" : "off") << " | " << m.counts.strandsDrawn << " | "
                   << m.counts.segmentsDrawn << " | " << m.counts.pixelWrites << " | "
                   << m.counts.atomicsIssued << " | " << m.counts.atomicsSkipped << " |\n";
          }
          std::fprintf(stderr, "table1 %s LOD %d MSAA %s %s: %.1f ms\n", r.groomNames[g], lod,
                       rowSpec.label, r.distNames[d], m.total.median);
        }
      }
      r.md << "\n";
    }
  }
  r.md << counts.str();
  // LOD speed-up at far, per groom (MSAA 1)
  for (bool filtered : {false, true}) {
    r.md << "\nLOD speed-up at far (" << (filtered ? "SWR1+F" : "SWR1") << ", total frame): ";
    for (int g = 0; g < 2; ++g) {
      double off = 0, on = 0;
      for (const auto& row : t1)
        if (row["groom"] == r.groomNames[g] && row["distance"] == "far" && row["msaa"] == 1 &&
            row["filter"].get<bool>() == filtered)
          (row["lod"].get<bool>() ? on : off) = row["total_ms"]["median"].get<double>();
      if (on > 0) r.md << r.groomNames[g] << " " << fmt(off / on) << "x" << (g == 0 ? ", " : "\n");
      r.report["lod_far_speedup"][filtered ? "SWR1+F" : "SWR1"][r.groomNames[g]] =
          on > 0 ? off / on : 0.0;
    }
  }
  r.report["table1"] = t1;
}

}  // namespace clhair::bench
