// ply_values.cpp — see ply_values.h.
#include "io/ply_values.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "clhair/error.h"

namespace clhair::ply {

int typeBytes(Type t) {
  switch (t) {
    case Type::I8:
    case Type::U8:
      return 1;
    case Type::I16:
    case Type::U16:
      return 2;
    case Type::I32:
    case Type::U32:
    case Type::F32:
      return 4;
    case Type::F64:
      return 8;
  }
  return 4;
}

bool parseType(const std::string& s, Type& t) {
  static const struct {
    const char* name;
    Type type;
  } names[] = {
      {"char", Type::I8},   {"int8", Type::I8},     {"uchar", Type::U8},   {"uint8", Type::U8},
      {"short", Type::I16}, {"int16", Type::I16},   {"ushort", Type::U16}, {"uint16", Type::U16},
      {"int", Type::I32},   {"int32", Type::I32},   {"uint", Type::U32},   {"uint32", Type::U32},
      {"float", Type::F32}, {"float32", Type::F32}, {"double", Type::F64}, {"float64", Type::F64}};
  for (const auto& n : names)
    if (s == n.name) {
      t = n.type;
      return true;
    }
  return false;
}

std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
  return out;
}

double Values::next(Type t, const std::string& elem, std::uint64_t i, const std::string& prop) {
  elem_ = &elem;
  index_ = i;
  prop_ = &prop;
  if (fmt_ == Format::Ascii) return token();
  const int n = typeBytes(t);
  unsigned char b[8];
  for (int k = 0; k < n; ++k) b[fmt_ == Format::Little ? k : n - 1 - k] = byte();
  std::uint64_t u = 0;
  for (int k = n - 1; k >= 0; --k) u = u << 8 | b[k];
  switch (t) {
    case Type::I8:
      return static_cast<double>(static_cast<std::int8_t>(u));
    case Type::U8:
    case Type::U16:
    case Type::U32:
      return static_cast<double>(u);
    case Type::I16:
      return static_cast<double>(static_cast<std::int16_t>(u));
    case Type::I32:
      return static_cast<double>(static_cast<std::int32_t>(static_cast<std::uint32_t>(u)));
    case Type::F32: {
      const auto bits = static_cast<std::uint32_t>(u);
      float v;
      std::memcpy(&v, &bits, 4);
      return v;
    }
    case Type::F64: {
      double v;
      std::memcpy(&v, &u, 8);
      return v;
    }
  }
  return 0.0;
}

unsigned char Values::byte() {
  if (at_ == buf_.size()) {
    const std::uint64_t left = f_.size() - f_.offset();
    if (left == 0)
      throw Error(path_ + ": truncated: the file ends while reading " + what() +
                  " (is it complete?)");
    buf_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(left, 1 << 20)));
    f_.read(buf_.data(), buf_.size(), what());
    at_ = 0;
  }
  ++consumed_;
  return buf_[at_++];
}

double Values::token() {
  std::string& t = token_;
  t.clear();
  while (more()) {
    const unsigned char c = byte();
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
      if (!t.empty()) break;
      continue;
    }
    if (t.size() > 64) throw Error(path_ + ": " + what() + ": a value longer than 64 characters");
    t.push_back(static_cast<char>(c));
  }
  if (t.empty())
    throw Error(path_ + ": truncated: the file ends while reading " + what() +
                " (is it complete?)");
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size())
    throw Error(path_ + ": " + what() + ": \"" + t + "\" is not a number");
  return v;
}

}  // namespace clhair::ply
