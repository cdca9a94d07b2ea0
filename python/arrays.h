#pragma once
// numpy arrays in and out of the core: probe segments read in place from an (N, 6) float32
// array (no copy), answers written into new arrays, and the one checker whose ValueErrors say
// which element is bad and why.
#include "contact/contact.h"
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <utility>
#include <vector>

namespace hb::python {

namespace py = pybind11;

/// Segments checked for the core: `segments` points at `count` hb::Segment (sx, sy, sz, ex, ey,
/// ez in model units), which `keep` holds alive (the caller's array itself for a C-contiguous
/// float32 array, else a float32 copy of it).
struct SegmentArray {
  py::array keep;
  const Segment* segments = nullptr;
  std::size_t count = 0;
};

/// Rows of floats read from numpy: `values` points at count x width floats, held by `keep`.
struct FloatRows {
  py::array keep;
  const float* values = nullptr;
  std::size_t count = 0, width = 0;
};

/// Reads `obj` as an (N, W) array of finite floats within hb::kMaxSegmentCoordinate, W one of
/// `widths` (`columns` names them in messages, e.g. "sx, sy, sz, ex, ey, ez"). A C-contiguous
/// float32 array is read in place; another float array is converted once. Throws
/// py::value_error as segment_array does.
FloatRows float_rows(py::handle obj, const char* name, std::initializer_list<std::size_t> widths, const char* columns);

/// Reads `obj` as an (N, 6) array of finite floats within hb::kMaxSegmentCoordinate. A
/// C-contiguous float32 array is read in place; another float array (float64, strided) is
/// converted once. Throws py::value_error naming the argument and what is wrong: not an
/// array, its shape, a dtype that is not a float, or the first NaN, infinite or too large
/// value with its row and column. `name` names the argument in messages ("segments").
SegmentArray segment_array(py::handle obj, const char* name);

/// The answers as numpy arrays: "contact" (N,) bool, "depth" (N,) float32 model units,
/// "point" and "normal" (N, 3) float32, "force" (N, 3) float32 newtons.
struct ContactArrays {
  py::array_t<bool> contact;
  py::array_t<float> depth, point, normal, force;
  /// Allocates the arrays (with the GIL).
  explicit ContactArrays(std::size_t n);
  /// Copies answers [first, first + count) in (no Python object touched: the GIL may be off).
  void put(const Contact* answers, std::size_t first, std::size_t count);
  py::dict dict() const;

private:
  bool* c_ = nullptr;
  float *d_ = nullptr, *p_ = nullptr, *n_ = nullptr, *f_ = nullptr;
};

/// `query`'s answers to the segments (ContactQuery::query_many, in chunks, the GIL released
/// from the check of the values to the last answer) under `law`.
py::dict answer_segments(const ContactQuery& query, py::handle segments, const ForceLaw& law);

/// For the batch's measurement (bench/python_query.py): the seconds `query.query_many` takes
/// over the segments in C++ alone (the same chunks, no numpy output), and the address it read
/// them from (the array's own buffer when it is read in place).
std::pair<double, std::uintptr_t> time_query_many(const ContactQuery& query, py::handle segments, const ForceLaw& law);

/// The contacts of a dict of answer arrays as answer_segments returns it (contact, depth,
/// point, normal, force; N the same in all). `name` names the argument in messages.
std::vector<Contact> contacts_from_dict(py::handle answers, const char* name);

} // namespace hb::python
