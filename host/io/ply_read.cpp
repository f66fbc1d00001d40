// ply_read.cpp — reading strands from PLY files (layout in ply_strands.h).
//
// The PLY header is parsed completely first; every element's least size (binary: its bytes;
// ascii: one character and a separator per value) is checked against the bytes after the
// header, and the arrays kept against the caller's limit, before anything is allocated from
// a count. The data is read through a 1 MB buffer, values decoded byte by byte in the file's
// byte order, so the reader does not depend on the host's.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "clhair/error.h"
#include "io/binary_file.h"
#include "io/ply_layout.h"
#include "io/ply_strands.h"
#include "io/ply_values.h"

namespace clhair {

namespace {

using ply::Element;
using ply::Format;
using ply::parseType;
using ply::Prop;
using ply::Type;
using ply::typeBytes;
using ply::Values;
using ply::words;

float srgbToLinear(double c8) {
  const double c = c8 / 255.0;
  return static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

}  // namespace

PlyStrands readPlyStrands(const std::string& path, std::uint64_t maxBytes) {
  InputFile f(path, "PLY");
  // the header: lines up to "end_header", at most 64 KiB
  std::string header;
  {
    const std::uint64_t most = std::min<std::uint64_t>(f.size(), 65536);
    std::vector<unsigned char> head(static_cast<std::size_t>(most));
    if (most > 0) f.read(head.data(), head.size(), "the header");
    header.assign(head.begin(), head.end());
  }
  if (header == "ply" || header == "ply\r")
    throw Error(path + ": ends after its PLY signature \"ply\": no header follows (truncated, " +
                "is it complete?)");
  if (header.compare(0, 3, "ply") != 0 || header.size() < 4 ||
      (header[3] != '\n' && header[3] != '\r'))
    throw Error(path + ": starts with \"" +
                showBytes(reinterpret_cast<const unsigned char*>(header.data()),
                          std::min<std::size_t>(header.size(), 8)) +
                "\", not the PLY signature \"ply\" (is it a PLY file?)");
  std::size_t end = std::string::npos;
  for (std::size_t at = 0; at < header.size();) {
    std::size_t nl = header.find('\n', at);
    if (nl == std::string::npos) break;
    std::string line = header.substr(at, nl - at);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line == "end_header") {
      end = nl + 1;
      break;
    }
    at = nl + 1;
  }
  if (end == std::string::npos)
    throw Error(path + ": the PLY header has no \"end_header\" line in its first " +
                std::to_string(header.size()) + " bytes (truncated or not a PLY file)");

  Format fmt = Format::Ascii;
  bool haveFormat = false;
  std::vector<Element> elements;
  std::size_t lineNo = 0;
  for (std::size_t at = 0; at < end;) {
    const std::size_t nl = header.find('\n', at);
    std::string line = header.substr(at, nl - at);
    at = nl + 1;
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string> w = words(line);
    auto bad = [&](const std::string& why) {
      throw Error(path + ": header line " + std::to_string(lineNo) + " \"" + line + "\": " + why);
    };
    if (w.empty() || w[0] == "ply" || w[0] == "comment" || w[0] == "obj_info" ||
        w[0] == "end_header")
      continue;
    if (w[0] == "format") {
      if (w.size() != 3 || w[2] != "1.0") bad("expected \"format <kind> 1.0\"");
      if (w[1] == "ascii")
        fmt = Format::Ascii;
      else if (w[1] == "binary_little_endian")
        fmt = Format::Little;
      else if (w[1] == "binary_big_endian")
        fmt = Format::Big;
      else
        bad("unknown format (ascii, binary_little_endian or binary_big_endian)");
      haveFormat = true;
    } else if (w[0] == "element") {
      if (w.size() != 3) bad("expected \"element <name> <count>\"");
      char* e = nullptr;
      const unsigned long long n = std::strtoull(w[2].c_str(), &e, 10);
      if (*e != '\0' || w[2][0] == '-' || n > (1ull << 40)) bad("the count is not a whole number");
      elements.push_back({w[1], n, {}});
    } else if (w[0] == "property") {
      if (elements.empty()) bad("a property before any element");
      Prop p;
      if (w.size() == 5 && w[1] == "list") {
        if (!parseType(w[2], p.countType) || !parseType(w[3], p.type)) bad("unknown type");
        if (p.countType == Type::F32 || p.countType == Type::F64)
          bad("a list count must be an integer type");
        p.list = true;
        p.name = w[4];
      } else if (w.size() == 3) {
        if (!parseType(w[1], p.type)) bad("unknown type \"" + w[1] + "\"");
        p.name = w[2];
      } else {
        bad("expected \"property <type> <name>\" or \"property list <type> <type> <name>\"");
      }
      elements.back().props.push_back(p);
    } else {
      bad("unknown header keyword \"" + w[0] + "\"");
    }
  }
  if (!haveFormat) throw Error(path + ": the PLY header has no \"format\" line");

  // what the strands need
  const Element* vertex = nullptr;
  const Element* strand = nullptr;
  const Element* edge = nullptr;
  for (const Element& e : elements) {
    if (e.name == "vertex") vertex = &e;
    if (e.name == "strand" || e.name == "curve") strand = &e;
    if (e.name == "edge") edge = &e;
  }
  auto findProp = [](const Element* e, const char* name) -> int {
    for (std::size_t i = 0; i < e->props.size(); ++i)
      if (e->props[i].name == name) return static_cast<int>(i);
    return -1;
  };
  if (!vertex) throw Error(path + ": has no \"element vertex\": no strand points to read");
  const int px = findProp(vertex, "x"), py = findProp(vertex, "y"), pz = findProp(vertex, "z");
  if (px < 0 || py < 0 || pz < 0)
    throw Error(path + ": the vertex element has no x, y and z properties");
  const int pr = findProp(vertex, "red"), pg = findProp(vertex, "green"),
            pb = findProp(vertex, "blue");
  const bool colours = pr >= 0 && pg >= 0 && pb >= 0;
  for (const Prop& p : vertex->props)
    if (p.list) throw Error(path + ": the vertex element has a list property \"" + p.name + "\"");
  if (!strand && !edge)
    throw Error(path + ": has neither an \"element strand\" (a segment or vertex count per " +
                "strand) nor an \"element edge\" (vertex1, vertex2): is it a mesh or a point " +
                "cloud rather than strands?");
  // the count: a scalar integer property named as ply_layout.h lists (others are skipped)
  int countProp = -1;
  bool countsSegments = false;
  if (strand) {
    for (std::size_t k = 0; k < strand->props.size() && countProp < 0; ++k)
      if (plyCountKind(strand->props[k].name) != PlyCountKind::Unknown)
        countProp = static_cast<int>(k);
    if (countProp < 0) {
      std::string names;
      for (const Prop& p : strand->props) names += (names.empty() ? "" : ", ") + p.name;
      throw Error(path + ": the " + strand->name + " element's properties (" +
                  (names.empty() ? "none" : names) + ") hold no count; expected one named for " +
                  plyCountNames());
    }
    const Prop& c = strand->props[static_cast<std::size_t>(countProp)];
    if (c.list || c.type == Type::F32 || c.type == Type::F64)
      throw Error(path + ": the " + strand->name + " element's " + c.name +
                  " must be a scalar integer (uchar to uint32), not a list or a float");
    countsSegments = plyCountKind(c.name) == PlyCountKind::Segments;
  }
  // the edge's two vertices: vertex1 and vertex2, else its only two properties
  int pv1 = edge ? findProp(edge, "vertex1") : -1, pv2 = edge ? findProp(edge, "vertex2") : -1;
  if (edge && (pv1 < 0 || pv2 < 0) && edge->props.size() == 2) {
    pv1 = 0;
    pv2 = 1;
  }
  if (edge && (pv1 < 0 || pv2 < 0 || edge->props[pv1].list || edge->props[pv2].list ||
               edge->props[pv1].type == Type::F32 || edge->props[pv1].type == Type::F64 ||
               edge->props[pv2].type == Type::F32 || edge->props[pv2].type == Type::F64))
    throw Error(path + ": the edge element needs two scalar integer vertex properties " +
                "(vertex1 and vertex2)");

  // sizes before allocating: every element's least size against the bytes left
  const std::uint64_t left = f.size() - end;
  std::uint64_t least = 0;
  for (const Element& e : elements) {
    std::uint64_t per = 0;
    for (const Prop& p : e.props)
      per += fmt == Format::Ascii
                 ? 2
                 : static_cast<std::uint64_t>(typeBytes(p.list ? p.countType : p.type));
    if (per > 0 && e.count > (left - std::min(left, least)) / per + (fmt == Format::Ascii ? 1 : 0))
      throw Error(path + ": truncated, the file is cut short: the header says " +
                  std::to_string(e.count) + " " + e.name + " elements, which need at least " +
                  std::to_string(e.count * per) + " bytes, but " + std::to_string(left) +
                  " bytes follow the header");
    least += per * e.count;
  }
  const std::uint64_t V = vertex->count;
  const std::uint64_t memory =
      V * (colours ? 24 : 12) + 4 * (strand ? strand->count : V) + (edge ? V : 0);
  const std::uint64_t limit =
      std::min<std::uint64_t>(maxBytes, std::numeric_limits<std::size_t>::max());
  if (memory > limit)
    throw Error(path + ": " + std::to_string(V) + " vertices need " + std::to_string(memory) +
                " bytes of arrays, more than the " + std::to_string(limit) +
                "-byte limit (the device's largest allocation)");
  if (V > 0xFFFFFFF0ull)
    throw Error(path + ": " + std::to_string(V) + " vertices, more than the strand tables address");

  f.seek(end, "the data after the header");
  Values in(f, fmt, path);
  PlyStrands out;
  CyHair& h = out.hair;
  h.info = "PLY";
  std::vector<float> pts, cols;
  std::vector<std::uint32_t> counts;  // points per strand (element strand)
  std::vector<unsigned char> next;    // edge: vertex i joined to i + 1
  for (const Element& e : elements) {
    const bool isVertex = &e == vertex, isStrand = &e == strand, isEdge = &e == edge;
    if (isVertex) {
      pts.resize(static_cast<std::size_t>(3 * V));
      if (colours) cols.resize(static_cast<std::size_t>(3 * V));
    }
    if (isStrand) counts.reserve(static_cast<std::size_t>(e.count));
    if (isEdge) next.assign(static_cast<std::size_t>(V), 0);
    // an element without properties takes no bytes, however many it declares: skipped whole
    if (e.props.empty()) continue;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      auto what = [&] { return e.name + " " + std::to_string(i); };
      double edgeFirst = 0.0;  // the edge's first-listed vertex of vertex1, vertex2
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const Prop& p = e.props[k];
        if (p.list) {
          const double n = in.next(p.countType, e.name, i, p.name);
          if (!(n >= 0.0 && n <= 1e6))
            throw Error(path + ": " + what() + ": list " + p.name + " has " + std::to_string(n) +
                        " entries");
          for (int j = 0; j < static_cast<int>(n); ++j) in.next(p.type, e.name, i, p.name);
          continue;
        }
        const double v = in.next(p.type, e.name, i, p.name);
        const int ki = static_cast<int>(k);
        if (isVertex) {
          const int c = ki == px ? 0 : ki == py ? 1 : ki == pz ? 2 : -1;
          const int rgb = !colours ? -1 : ki == pr ? 0 : ki == pg ? 1 : ki == pb ? 2 : -1;
          if ((c >= 0 || rgb >= 0) && !std::isfinite(v))
            throw Error(path + ": vertex " + std::to_string(i) + " " + p.name + " is " +
                        showFloat(static_cast<float>(v)) + ", expected a finite number");
          if (c >= 0) {
            const auto fv = static_cast<float>(v);
            if (!std::isfinite(fv))
              throw Error(path + ": vertex " + std::to_string(i) + " " + p.name +
                          " is beyond the float range");
            pts[static_cast<std::size_t>(3 * i + c)] = fv;
          }
          if (rgb >= 0) {
            const bool eight = p.type != Type::F32 && p.type != Type::F64;
            cols[static_cast<std::size_t>(3 * i + rgb)] =
                eight ? srgbToLinear(std::min(std::max(v, 0.0), 255.0))
                      : static_cast<float>(std::min(std::max(v, 0.0), 1.0));
          }
        } else if (isStrand && ki == countProp) {
          const double points = countsSegments ? v + 1.0 : v;
          if (!(points >= 0.0 && points <= 65536.0 && points == std::floor(points)))
            throw Error(path + ": " + what() + " has " + (countsSegments ? "segment" : "vertex") +
                        " count " + std::to_string(v) +
                        ", expected a whole number up to 65535 segments");
          counts.push_back(static_cast<std::uint32_t>(points));
        } else if (isEdge && (ki == pv1 || ki == pv2)) {
          if (!(v >= 0.0 && v < static_cast<double>(V) && v == std::floor(v)))
            throw Error(path + ": " + what() + " names vertex " + std::to_string(v) +
                        ", but there are " + std::to_string(V) + " vertices");
          if (ki == std::min(pv1, pv2)) {
            edgeFirst = v;
          } else {
            const double a = std::min(edgeFirst, v), b = std::max(edgeFirst, v);
            if (b != a + 1.0)
              throw Error(path + ": " + what() + " joins vertices " +
                          std::to_string(static_cast<std::uint64_t>(edgeFirst)) + " and " +
                          std::to_string(static_cast<std::uint64_t>(v)) +
                          ": strands must be runs of consecutive vertices");
            next[static_cast<std::size_t>(a)] = 1;
          }
        }
      }
    }
  }

  // strands from the counts (checked against the edges when both are given) or the edges
  std::vector<std::uint32_t> pointsPer;
  if (strand) {
    std::uint64_t sum = 0;
    for (std::uint32_t c : counts) sum += c;
    if (sum != V)
      throw Error(path + ": the " + strand->name + " counts add up to " + std::to_string(sum) +
                  " vertices, but the file has " + std::to_string(V));
    if (edge && edge->count > 0) plyCheckEdgesAgree(counts, next, path, strand->name);
    pointsPer = std::move(counts);
  } else {
    pointsPer = plyStrandsFromEdges(next);
  }
  std::uint64_t at = 0;
  for (std::uint32_t n : pointsPer) {
    if (n >= 2) {
      h.segments.push_back(n - 1);
      h.points.insert(h.points.end(), pts.begin() + static_cast<std::ptrdiff_t>(3 * at),
                      pts.begin() + static_cast<std::ptrdiff_t>(3 * (at + n)));
      if (colours)
        h.colors.insert(h.colors.end(), cols.begin() + static_cast<std::ptrdiff_t>(3 * at),
                        cols.begin() + static_cast<std::ptrdiff_t>(3 * (at + n)));
    } else {
      ++out.skippedStrands;
    }
    at += n;
  }
  if (h.segments.empty()) throw Error(path + ": no strand has 2 or more points, nothing to draw");
  h.trailingBytes = fmt == Format::Ascii ? 0 : f.size() - end - in.consumed();
  return out;
}

}  // namespace clhair
