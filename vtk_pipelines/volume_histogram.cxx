// volume_histogram: calibrated values (slope * stored + intercept) counted in equal bins.
#include "volume_histogram.h"
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <algorithm>
#include <cmath>

namespace hb::vtk {

VolumeHistogram volume_histogram(const Volume& volume, int bins) {
  VolumeHistogram h;
  vtkDataArray* scalars = volume.image ? volume.image->GetPointData()->GetScalars() : nullptr;
  if (!scalars || bins < 1) return h;
  double range[2];
  scalars->GetRange(range, 0);
  const double a = range[0] * volume.slope + volume.intercept, b = range[1] * volume.slope + volume.intercept;
  h.lo = std::min(a, b);
  h.hi = std::max(a, b);
  if (!(h.hi > h.lo)) h.hi = h.lo + 1.0;
  h.counts.assign(std::size_t(bins), 0.0);
  const vtkIdType n = scalars->GetNumberOfTuples();
  const vtkIdType stride = std::max<vtkIdType>(1, n / 4000000);
  for (vtkIdType i = 0; i < n; i += stride) {
    const double x = scalars->GetComponent(i, 0) * volume.slope + volume.intercept;
    const int bin = std::clamp(int((x - h.lo) / (h.hi - h.lo) * bins), 0, bins - 1);
    h.counts[std::size_t(bin)] += 1.0;
  }
  return h;
}

double otsu_threshold(const VolumeHistogram& h) {
  const int bins = int(h.counts.size());
  if (bins < 2) return h.lo;
  double total = 0, sum = 0;
  for (int b = 0; b < bins; ++b) {
    total += h.counts[std::size_t(b)];
    sum += b * h.counts[std::size_t(b)];
  }
  double w0 = 0, sum0 = 0, best = -1;
  int best_bin = bins / 2;
  for (int b = 0; b < bins - 1; ++b) {
    w0 += h.counts[std::size_t(b)];
    sum0 += b * h.counts[std::size_t(b)];
    const double w1 = total - w0;
    if (w0 == 0 || w1 == 0) continue;
    const double m0 = sum0 / w0, m1 = (sum - sum0) / w1;
    const double between = w0 * w1 * (m0 - m1) * (m0 - m1);
    if (between > best) {
      best = between;
      best_bin = b;
    }
  }
  return h.lo + (h.hi - h.lo) * (best_bin + 1) / bins;
}

} // namespace hb::vtk
