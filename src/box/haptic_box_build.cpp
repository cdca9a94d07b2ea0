// Making a haptic box (haptic_box.h): the constructors over raw, mapped and compressed
// tables, compressed(), attach_surface() and the geometry checks every constructor runs. The
// query is haptic_box.cpp's.
#include "box/haptic_box.h"
#include "errors.h"
#include <string>

namespace hb {

HapticBox::HapticBox(const Obb& obb, const BoxParams& params, std::vector<Sample> table)
    : obb_(obb), params_(params) {
  if (params_.m < 2 || params_.n < 2)
    throw InvalidInput("HapticBox: m and n must be >= 2 (m=" + std::to_string(params_.m) +
                       ", n=" + std::to_string(params_.n) + ")");
  if (table.size() != params_.sample_count())
    throw InvalidInput("HapticBox: table has " + std::to_string(table.size()) +
                       " samples, expected " + std::to_string(params_.sample_count()));
  auto owned = std::make_shared<const std::vector<Sample>>(std::move(table));
  table_ = owned->data();
  owner_ = std::move(owned);
  samples_ = SampleTable(table_, params_);
  stats_.raw_bytes = stats_.bytes = raw_table_bytes();
  check_geometry();
  layout_ = BoxLayout(obb_, params_);
}

HapticBox::HapticBox(const Obb& obb, const BoxParams& params, const Sample* table,
                     std::shared_ptr<const void> owner)
    : obb_(obb), params_(params), table_(table), owner_(std::move(owner)) {
  if (params_.m < 2 || params_.n < 2) throw InvalidInput("HapticBox: m and n must be >= 2");
  if (!table_) throw InvalidInput("HapticBox: null table");
  samples_ = SampleTable(table_, params_);
  stats_.raw_bytes = stats_.bytes = raw_table_bytes();
  check_geometry();
  layout_ = BoxLayout(obb_, params_);
}

HapticBox::HapticBox(const Obb& obb, const BoxParams& params, CompressedTable table)
    : obb_(obb), params_(params), stats_(table.stats) {
  if (params_.m < 2 || params_.n < 2) throw InvalidInput("HapticBox: m and n must be >= 2");
  auto owned = std::make_shared<const std::vector<std::uint8_t>>(std::move(table.payload));
  samples_ = SampleTable(table.codec, owned->data(), owned->size(), params_);
  owner_ = std::move(owned);
  check_geometry();
  layout_ = BoxLayout(obb_, params_);
}

HapticBox::HapticBox(const Obb& obb, const BoxParams& params, CodecId codec, const std::uint8_t* payload,
                     std::size_t bytes, std::shared_ptr<const void> owner, const CodecStats& stats)
    : obb_(obb), params_(params), stats_(stats), owner_(std::move(owner)) {
  if (params_.m < 2 || params_.n < 2) throw InvalidInput("HapticBox: m and n must be >= 2");
  samples_ = SampleTable(codec, payload, bytes, params_);
  stats_.bytes = bytes;
  stats_.raw_bytes = raw_table_bytes();
  check_geometry();
  layout_ = BoxLayout(obb_, params_);
}

HapticBox::HapticBox(const Obb& obb, const BoxParams& params) : obb_(obb), params_(params) {
  if (params_.m < 2 || params_.n < 2) throw InvalidInput("HapticBox: m and n must be >= 2");
  check_geometry();
  layout_ = BoxLayout(obb_, params_);
}

HapticBox HapticBox::compressed(const CodecOptions& options) const {
  if (!has_table())
    throw InvalidInput("HapticBox: a frame has no table to compress (its scene is answered by exact Embree)");
  if (!table_) throw InvalidInput("HapticBox: the table is already compressed");
  HapticBox box(obb_, params_, compress_table(table_, params_, obb_.diagonal(), options));
  if (surface_) box.attach_surface(triangle_ids_, params_.sample_count(), ids_owner_, surface_, false);
  return box;
}

void HapticBox::attach_surface(const TriangleIds& triangle_ids, std::size_t count,
                               std::shared_ptr<const void> ids_owner, std::shared_ptr<const SurfaceTriangles> surface,
                               bool validate) {
  if (!triangle_ids.data || !surface) throw InvalidInput("HapticBox: refinement needs triangle ids and a surface");
  if (!has_table()) throw InvalidInput("HapticBox: a frame (no table) cannot refine");
  if (triangle_ids.width != 2 && triangle_ids.width != 4)
    throw InvalidInput("HapticBox: triangle ids of " + std::to_string(triangle_ids.width) + " bytes (2 or 4)");
  if (count != params_.sample_count())
    throw InvalidInput("HapticBox: " + std::to_string(count) + " triangle ids, expected " +
                       std::to_string(params_.sample_count()));
  if (validate)
    for (std::size_t k = 0; k < count; ++k)
      if (triangle_ids.at(k) != kNoTriangle && triangle_ids.at(k) >= surface->size())
        throw InvalidInput("HapticBox: sample " + std::to_string(k) + " names triangle " +
                           std::to_string(triangle_ids.at(k)) + ", the surface has " + std::to_string(surface->size()));
  triangle_ids_ = triangle_ids;
  ids_owner_ = std::move(ids_owner);
  surface_ = std::move(surface);
  // A refined hit farther than this from the blended one is a different surface than the one
  // the samples blend (a candidate behind the first one): two position cells.
  refine_tolerance_ = 2.f * 2.f * obb_.half.maxCoeff() / float(params_.m - 1);
}

void HapticBox::check_geometry() const {
  if (const std::string why = obb_problem(obb_); !why.empty()) throw InvalidInput("HapticBox: the box's " + why);
  if (params_.m > 4096 || params_.n > 4096)
    throw InvalidInput("HapticBox: m and n must be <= 4096 (m=" + std::to_string(params_.m) +
                       ", n=" + std::to_string(params_.n) + ")");
}

} // namespace hb
