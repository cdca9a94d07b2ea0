#pragma once
#include "haptic_box/haptic_box.h"
#include <string>
#include <vector>

namespace hb {

/// Facts about the mesh a scene was baked from, stored in box files.
struct SourceInfo {
  std::string mesh_path;          ///< as given to the bake.
  std::uint64_t mesh_hash = 0;    ///< xxHash64 of the mesh file's bytes.
  std::uint64_t triangles = 0;
  float diagonal = 0.f;           ///< bounding-box diagonal of the whole mesh, model units.
};

/// A scene of haptic boxes, one per piece. A query culls by PBB and the valid contact
/// nearest the handle wins, so its cost grows with the boxes the segment meets.
class BoxScene final : public ContactQuery {
public:
  BoxScene() = default;
  explicit BoxScene(std::vector<HapticBox> boxes, SourceInfo source = {});

  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override;

  const std::vector<HapticBox>& boxes() const { return boxes_; }
  const SourceInfo& source() const { return source_; }
  std::size_t table_bytes() const;

private:
  std::vector<HapticBox> boxes_;
  SourceInfo source_;
};

} // namespace hb
