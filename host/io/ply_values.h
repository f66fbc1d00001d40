// ply_values.h — the PLY header's types and the values after it (ply_read.cpp): property
// types and their sizes, elements, the three formats, and Values, which decodes the data
// value by value through a 1 MB buffer in the file's byte order (binary) or as text
// (ascii), naming the element, index and property in every error.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "io/binary_file.h"

namespace clhair::ply {

enum class Type { I8, U8, I16, U16, I32, U32, F32, F64 };

struct Prop {
  std::string name;
  Type type = Type::F32;
  bool list = false;
  Type countType = Type::U8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Prop> props;
};

enum class Format { Ascii, Little, Big };

// Bytes of one value of type t in a binary file.
int typeBytes(Type t);
// The type a header names ("uchar", "float32", ...); false for an unknown name.
bool parseType(const std::string& s, Type& t);
// The words of a header line (spaces and tabs between them).
std::vector<std::string> words(const std::string& line);

// The data after the header, value by value.
class Values {
 public:
  Values(InputFile& f, Format fmt, const std::string& path) : f_(f), fmt_(fmt), path_(path) {}

  // The next value as a double (integers exactly up to 2^53): property `prop` of element
  // `elem` number i (named only in errors).
  double next(Type t, const std::string& elem, std::uint64_t i, const std::string& prop);
  std::uint64_t consumed() const { return consumed_; }

 private:
  std::string what() const { return *elem_ + " " + std::to_string(index_) + " " + *prop_; }
  unsigned char byte();
  bool more() const { return at_ < buf_.size() || f_.offset() < f_.size(); }
  double token();

  InputFile& f_;
  Format fmt_;
  std::string path_;
  std::vector<unsigned char> buf_;
  std::size_t at_ = 0;
  std::uint64_t consumed_ = 0;
  std::string token_;
  const std::string* elem_ = nullptr;
  const std::string* prop_ = nullptr;
  std::uint64_t index_ = 0;
};

}  // namespace clhair::ply
