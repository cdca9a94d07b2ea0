#pragma once
// The histogram of a volume's calibrated values (Hounsfield units for CT), for choosing an
// iso-value by eye: the window draws it under the iso-value with the Otsu threshold marked.
#include "volume_reader.h"
#include <vector>

namespace hb::vtk {

struct VolumeHistogram {
  double lo = 0.0, hi = 0.0;   ///< calibrated value range (lo: left edge of bin 0, hi: right edge of the last).
  std::vector<double> counts;  ///< voxels per bin (every voxel, or an even sample of at most 4 M).
  double bin_width() const { return counts.empty() ? 0.0 : (hi - lo) / double(counts.size()); }
};

/// The histogram of `volume` in `bins` bins over its calibrated value range (256 bins: the
/// binning volume_surface's automatic iso-value uses).
VolumeHistogram volume_histogram(const Volume& volume, int bins = 256);

/// Otsu's threshold of the histogram (the value between the two classes that maximises their
/// between-class variance): the iso-value volume_surface takes when none is given.
double otsu_threshold(const VolumeHistogram& histogram);

} // namespace hb::vtk
