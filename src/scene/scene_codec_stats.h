#pragma once
// A scene's table codec figures, one definition for every front end (`bake --json`,
// `info --json`, reports): the boxes' CodecStats combined.
#include "scene/box_scene.h"
#include <algorithm>
#include <string>

namespace hb {

/// The codec figures of a whole scene.
struct SceneCodecStats {
  std::string codec = "none";       ///< the boxes' codec, or "mixed".
  std::uint64_t raw_bytes = 0;      ///< tables uncompressed (8 bytes a sample).
  std::uint64_t table_bytes = 0;    ///< tables as stored.
  double max_error_bound = 0.0;     ///< largest bound honoured by a box (relative to its diagonal).
  /// Means over the boxes weighted by their sample counts (a box of twice the samples counts
  /// twice): |t1 - t0| / box diagonal over hit samples, and the decoded normals' angle error.
  double t_error_mean = 0.0, normal_error_mean_deg = 0.0;
  double t_error_max = 0.0, normal_error_max_deg = 0.0;  ///< largest over the boxes.
  double compression_ratio() const { return table_bytes ? double(raw_bytes) / double(table_bytes) : 0.0; }
};

/// Combines the CodecStats of `scene`'s boxes (see SceneCodecStats).
inline SceneCodecStats scene_codec_stats(const BoxScene& scene) {
  SceneCodecStats s;
  double samples = 0.0;
  for (std::size_t b = 0; b < scene.parts().boxes.size(); ++b) {
    const HapticBox& box = scene.parts().boxes[b];
    const CodecStats& cs = box.codec_stats();
    const std::string name = codec_name(box.codec());
    s.codec = b == 0 || s.codec == name ? name : "mixed";
    s.raw_bytes += box.raw_table_bytes();
    s.table_bytes += box.table_bytes();
    const double w = double(box.params().sample_count());
    samples += w;
    s.t_error_mean += double(cs.t_error_mean) * w;
    s.normal_error_mean_deg += double(cs.normal_error_mean_deg) * w;
    s.t_error_max = std::max<double>(s.t_error_max, cs.t_error_max);
    s.normal_error_max_deg = std::max<double>(s.normal_error_max_deg, cs.normal_error_max_deg);
    s.max_error_bound = std::max<double>(s.max_error_bound, cs.max_error_bound);
  }
  if (samples > 0.0) {
    s.t_error_mean /= samples;
    s.normal_error_mean_deg /= samples;
  }
  return s;
}

} // namespace hb
