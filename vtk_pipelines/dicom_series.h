#pragma once
// A DICOM series read as one volume (read_volume's reader for a directory or a .dcm file).
#include "volume_reader.h"
#include <cstddef>
#include <string>

namespace hb::vtk {

/// Reads the series of `input`: a directory must hold one series (every file in it must read
/// as DICOM); a file reads the files of its directory with its SeriesInstanceUID. Every file is
/// checked (hb::check_dicom_header) before VTK's DICOM parser sees it. The slices, sorted along
/// their normal, must share size, pixel spacing, orientation, pixel type and rescale, and be
/// evenly spaced. Throws hb::IoError or hb::InvalidInput naming the file and the cause.
Volume read_dicom_series(const std::string& input, std::size_t max_voxels);

} // namespace hb::vtk
