// 1. Segments: an (N, 6) float32 C-contiguous array is the core's hb::Segment array as it is
//    (six floats each, sx sy sz ex ey ez): its buffer is passed to query_many, never copied.
//    Other float arrays are converted once; anything else is a ValueError saying which.
// 2. The values are checked with the GIL released (finite, within kMaxSegmentCoordinate, as
//    the command line's --segments CSV), then answered in chunks of kChunk into a reused
//    buffer and scattered into the output arrays (allocated before, with the GIL).
#include "arrays.h"
#include "evaluation/segments_csv.h"
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace hb::python {

static_assert(sizeof(Segment) == 6 * sizeof(float), "hb::Segment must be six packed floats to read numpy in place");

namespace {

constexpr std::size_t kChunk = 16384;

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// The first bad value (row, column) or count when all are good.
std::size_t first_bad_value(const float* v, std::size_t values) noexcept {
  for (std::size_t i = 0; i < values; ++i)
    if (!(std::fabs(v[i]) <= kMaxSegmentCoordinate)) return i;  // NaN fails the comparison too
  return values;
}

} // namespace

FloatRows float_rows(py::handle obj, const char* name, std::initializer_list<std::size_t> widths, const char* columns) {
  std::string shapes;
  for (std::size_t w : widths) shapes += (shapes.empty() ? "" : " or ") + std::string("(N, ") + std::to_string(w) + ")";
  if (!py::isinstance<py::array>(obj))
    throw py::value_error(std::string(name) + ": expected a numpy array of shape " + shapes + " (" + columns + "), got " +
                          std::string(py::str(py::type::handle_of(obj).attr("__name__"))));
  py::array a = py::reinterpret_borrow<py::array>(obj);
  bool width_ok = false;
  for (std::size_t w : widths) width_ok = width_ok || (a.ndim() == 2 && std::size_t(a.shape(1)) == w);
  if (!width_ok)
    throw py::value_error(std::string(name) + ": expected shape " + shapes + " (" + columns + " per row), got shape " +
                          shape_text(a));
  if (a.dtype().kind() != 'f')
    throw py::value_error(std::string(name) + ": expected a float array (float32 is read in place, float64 converted), got dtype " +
                          std::string(py::str(a.dtype())));
  FloatRows out;
  const bool in_place = a.dtype().is(py::dtype::of<float>()) && (a.flags() & py::array::c_style);
  out.keep = in_place ? a : py::array(py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a));
  if (!out.keep) throw py::value_error(std::string(name) + ": cannot be converted to float32");
  out.count = std::size_t(a.shape(0));
  out.width = std::size_t(a.shape(1));
  out.values = static_cast<const float*>(out.keep.data());
  std::size_t bad = 0;
  {
    py::gil_scoped_release release;
    bad = first_bad_value(out.values, out.count * out.width);
  }
  if (bad < out.count * out.width) {
    const float v = out.values[bad];
    const std::string what = std::isnan(v) ? "NaN" : std::isinf(v) ? "infinite" : "beyond 4e15 (the largest coordinate a probe may have)";
    throw py::value_error(std::string(name) + "[" + std::to_string(bad / out.width) + ", " + std::to_string(bad % out.width) +
                          "] is " + what + ": every value must be a finite number within 4e15 model units");
  }
  return out;
}

SegmentArray segment_array(py::handle obj, const char* name) {
  FloatRows rows = float_rows(obj, name, {6}, "sx, sy, sz, ex, ey, ez");
  SegmentArray out;
  out.keep = rows.keep;
  out.count = rows.count;
  out.segments = reinterpret_cast<const Segment*>(rows.values);
  return out;
}

ContactArrays::ContactArrays(std::size_t n)
    : contact(py::ssize_t(n)), depth(py::ssize_t(n)), point({py::ssize_t(n), py::ssize_t(3)}),
      normal({py::ssize_t(n), py::ssize_t(3)}), force({py::ssize_t(n), py::ssize_t(3)}),
      c_(contact.mutable_data()), d_(depth.mutable_data()), p_(point.mutable_data()), n_(normal.mutable_data()),
      f_(force.mutable_data()) {}

void ContactArrays::put(const Contact* answers, std::size_t first, std::size_t count) {
  bool* c = c_ + first;
  float *d = d_ + first, *p = p_ + 3 * first, *n = n_ + 3 * first, *f = f_ + 3 * first;
  for (std::size_t i = 0; i < count; ++i) {
    const Contact& a = answers[i];
    c[i] = a.contact;
    d[i] = a.depth;
    std::memcpy(p + 3 * i, a.point.data(), 3 * sizeof(float));
    std::memcpy(n + 3 * i, a.normal.data(), 3 * sizeof(float));
    std::memcpy(f + 3 * i, a.force.data(), 3 * sizeof(float));
  }
}

py::dict ContactArrays::dict() const {
  py::dict d;
  d["contact"] = contact;
  d["depth"] = depth;
  d["point"] = point;
  d["normal"] = normal;
  d["force"] = force;
  return d;
}

py::dict answer_segments(const ContactQuery& query, py::handle segments, const ForceLaw& law) {
  const SegmentArray in = segment_array(segments, "segments");
  ContactArrays out(in.count);
  {
    py::gil_scoped_release release;
    std::vector<Contact> buffer(std::min(in.count, kChunk));
    for (std::size_t first = 0; first < in.count; first += kChunk) {
      const std::size_t count = std::min(kChunk, in.count - first);
      query.query_many(in.segments + first, count, law, buffer.data());
      out.put(buffer.data(), first, count);
    }
  }
  return out.dict();
}

std::pair<double, std::uintptr_t> time_query_many(const ContactQuery& query, py::handle segments, const ForceLaw& law) {
  const SegmentArray in = segment_array(segments, "segments");
  py::gil_scoped_release release;
  std::vector<Contact> buffer(std::min(in.count, kChunk));
  const auto start = std::chrono::steady_clock::now();
  for (std::size_t first = 0; first < in.count; first += kChunk)
    query.query_many(in.segments + first, std::min(kChunk, in.count - first), law, buffer.data());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {seconds, reinterpret_cast<std::uintptr_t>(in.segments)};
}

std::vector<Contact> contacts_from_dict(py::handle answers, const char* name) {
  if (!py::isinstance<py::dict>(answers))
    throw py::value_error(std::string(name) + ": expected a dict of answer arrays (contact, depth, point, normal, force) as query() returns");
  const py::dict d = py::reinterpret_borrow<py::dict>(answers);
  const auto column = [&](const char* key, int width) {
    if (!d.contains(key)) throw py::value_error(std::string(name) + ": no '" + key + "' array (give query()'s dict)");
    py::array a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(d[key]);
    if (!a) throw py::value_error(std::string(name) + "['" + key + "']: not a numeric array");
    const bool ok = width == 1 ? a.ndim() == 1 : a.ndim() == 2 && a.shape(1) == width;
    if (!ok)
      throw py::value_error(std::string(name) + "['" + key + "']: expected shape " + (width == 1 ? "(N,)" : "(N, 3)") +
                            ", got " + shape_text(a));
    return py::array_t<float>(a);
  };
  const py::array_t<float> c = column("contact", 1), dep = column("depth", 1), p = column("point", 3),
                           n = column("normal", 3), f = column("force", 3);
  const std::size_t count = std::size_t(c.shape(0));
  for (const py::array_t<float>* a : {&dep, &p, &n, &f})
    if (std::size_t(a->shape(0)) != count)
      throw py::value_error(std::string(name) + ": its arrays differ in length (contact has " + std::to_string(count) +
                            " rows, another " + std::to_string(a->shape(0)) + ")");
  std::vector<Contact> out(count);
  const float *cc = c.data(), *dd = dep.data(), *pp = p.data(), *nn = n.data(), *ff = f.data();
  for (std::size_t i = 0; i < count; ++i) {
    out[i].contact = cc[i] != 0.f;
    out[i].depth = dd[i];
    out[i].point = Vec3(pp[3 * i], pp[3 * i + 1], pp[3 * i + 2]);
    out[i].normal = Vec3(nn[3 * i], nn[3 * i + 1], nn[3 * i + 2]);
    out[i].force = Vec3(ff[3 * i], ff[3 * i + 1], ff[3 * i + 2]);
    if (!std::isfinite(out[i].force.squaredNorm()))
      throw py::value_error(std::string(name) + "['force'][" + std::to_string(i) + "] is not finite");
  }
  return out;
}

} // namespace hb::python
