// arrays.cpp — checked conversion of NumPy inputs (arrays.h).
#include "arrays.h"

#include <cmath>
#include <cstring>

#include "clhair/error.h"

namespace clhair::py {

std::string dtypeName(const nb::ndarray<>& a) {
  const nb::dlpack::dtype t = a.dtype();
  const char* kind = "?";
  switch (static_cast<nb::dlpack::dtype_code>(t.code)) {
    case nb::dlpack::dtype_code::Int:
      kind = "int";
      break;
    case nb::dlpack::dtype_code::UInt:
      kind = "uint";
      break;
    case nb::dlpack::dtype_code::Float:
      kind = "float";
      break;
    case nb::dlpack::dtype_code::Bool:
      return "bool";
    case nb::dlpack::dtype_code::Complex:
      kind = "complex";
      break;
    default:
      kind = "other";
      break;
  }
  return std::string(kind) + std::to_string(t.bits);
}

std::string shapeText(const nb::ndarray<>& a) {
  std::string s = "(";
  for (std::size_t i = 0; i < a.ndim(); ++i) {
    if (i) s += ", ";
    s += std::to_string(a.shape(i));
  }
  if (a.ndim() == 1) s += ",";
  return s + ")";
}

namespace {

void checkHost(const nb::ndarray<>& a, const std::string& what) {
  if (a.device_type() != nb::device::cpu::value)
    throw Error(what + ": the array lives on another device; pass a NumPy array in host memory");
}

}  // namespace

std::vector<float> floatValues(const nb::ndarray<>& a, const std::string& what, std::size_t ndim,
                               std::size_t inner, bool allowEmpty) {
  checkHost(a, what);
  std::string want = ndim == 1 ? "(N,)" : "(N, " + std::to_string(inner) + ")";
  if (a.dtype() != nb::dtype<float>())
    throw Error(what + ": dtype " + dtypeName(a) + ", expected float32 of shape " + want +
                " (convert with .astype(numpy.float32))");
  if (a.ndim() != ndim || (ndim == 2 && inner && a.shape(1) != inner))
    throw Error(what + ": shape " + shapeText(a) + ", expected " + want);
  const std::size_t rows = a.ndim() ? a.shape(0) : 0;
  const std::size_t cols = ndim == 2 ? a.shape(1) : 1;
  if (rows == 0 && !allowEmpty) throw Error(what + ": is empty, expected at least one row");
  std::vector<float> out(rows * cols);
  const auto* base = static_cast<const float*>(a.data());
  const std::int64_t s0 = a.stride(0), s1 = ndim == 2 ? a.stride(1) : 0;
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t j = 0; j < cols; ++j) {
      const float v = base[static_cast<std::int64_t>(i) * s0 + static_cast<std::int64_t>(j) * s1];
      if (!std::isfinite(v))
        throw Error(what + ": value " + std::to_string(v) + " at " +
                    (ndim == 2 ? "[" + std::to_string(i) + ", " + std::to_string(j) + "]"
                               : "[" + std::to_string(i) + "]") +
                    " is not finite");
      out[i * cols + j] = v;
    }
  return out;
}

std::vector<std::int64_t> integerValues(const nb::ndarray<>& a, const std::string& what,
                                        std::int64_t lo, std::int64_t hi) {
  checkHost(a, what);
  const nb::dlpack::dtype t = a.dtype();
  const auto code = static_cast<nb::dlpack::dtype_code>(t.code);
  if ((code != nb::dlpack::dtype_code::Int && code != nb::dlpack::dtype_code::UInt) ||
      (t.bits != 8 && t.bits != 16 && t.bits != 32 && t.bits != 64))
    throw Error(what + ": dtype " + dtypeName(a) + ", expected an integer array of shape (S,)");
  if (a.ndim() != 1) throw Error(what + ": shape " + shapeText(a) + ", expected (S,)");
  if (a.shape(0) == 0) throw Error(what + ": is empty, expected at least one strand");
  std::vector<std::int64_t> out(a.shape(0));
  const auto* bytes = static_cast<const std::uint8_t*>(a.data());
  const std::size_t size = t.bits / 8;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::uint8_t* p =
        bytes + static_cast<std::int64_t>(i) * a.stride(0) * static_cast<std::int64_t>(size);
    std::int64_t v = 0;
    const bool isSigned = code == nb::dlpack::dtype_code::Int;
    if (size == 1) v = isSigned ? std::int64_t(*reinterpret_cast<const std::int8_t*>(p)) : *p;
    if (size == 2) {
      std::uint16_t u;
      std::memcpy(&u, p, 2);
      v = isSigned ? std::int64_t(static_cast<std::int16_t>(u)) : u;
    }
    if (size == 4) {
      std::uint32_t u;
      std::memcpy(&u, p, 4);
      v = isSigned ? std::int64_t(static_cast<std::int32_t>(u)) : u;
    }
    if (size == 8) {
      std::uint64_t u;
      std::memcpy(&u, p, 8);
      if (!isSigned && u > static_cast<std::uint64_t>(hi))
        throw Error(what + "[" + std::to_string(i) + "] = " + std::to_string(u) + " is outside " +
                    std::to_string(lo) + ".." + std::to_string(hi));
      v = static_cast<std::int64_t>(u);
    }
    if (v < lo || v > hi)
      throw Error(what + "[" + std::to_string(i) + "] = " + std::to_string(v) + " is outside " +
                  std::to_string(lo) + ".." + std::to_string(hi));
    out[i] = v;
  }
  return out;
}

}  // namespace clhair::py
