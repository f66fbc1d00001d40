// arrays.h — NumPy arrays in and out of the binding: vectors handed to NumPy without a copy
// (the array owns the vector), and inputs checked for dtype, shape and finiteness with one
// clhair::Error line naming the argument, what was expected and what came.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

namespace clhair::py {

namespace nb = nanobind;

// A NumPy array that takes ownership of `values` (no copy) with the given shape.
template <class T>
nb::object toNumpy(std::vector<T>&& values, std::initializer_list<std::size_t> shape) {
  auto* heap = new std::vector<T>(std::move(values));
  nb::capsule owner(heap, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
  std::vector<std::size_t> dims(shape);
  return nb::cast(nb::ndarray<nb::numpy, T>(heap->data(), dims.size(), dims.data(), owner));
}

// "float32", "int64", ... of an array's dtype.
std::string dtypeName(const nb::ndarray<>& a);
// "(3, 4)" of an array's shape.
std::string shapeText(const nb::ndarray<>& a);

// The values of a float32 array of `ndim` dimensions whose last dimension is `inner` (0: any),
// row-major, strides honoured. Refuses another dtype or shape, an empty array when
// `allowEmpty` is false, and NaN or infinite values, naming `what`.
std::vector<float> floatValues(const nb::ndarray<>& a, const std::string& what, std::size_t ndim,
                               std::size_t inner, bool allowEmpty = false);
// The values of a one-dimensional array of any integer dtype, each in [lo, hi].
std::vector<std::int64_t> integerValues(const nb::ndarray<>& a, const std::string& what,
                                        std::int64_t lo, std::int64_t hi);

}  // namespace clhair::py
